//! `harness campaign`: the campaign a scenario's `[campaign]` table declares, over the
//! Oscillator test FMU (docs/examples/oscillator-campaign.toml): it runs and judges every run
//! by the requirements; shards merged equal the whole byte for byte; `--resume` runs only the
//! missing runs; `--replay` reproduces a run's row bit for bit; bad tables are refused with
//! every problem at once.
use crate::common;
use std::path::{Path, PathBuf};
use std::process::Output;

fn example() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/examples/oscillator-campaign.toml")
}

fn campaign(out_dir: &Path, extra: &[&str]) -> Output {
    let scenario = example();
    let mut args = vec![
        "campaign",
        scenario.to_str().unwrap(),
        "-n",
        "6",
        "--out-dir",
    ];
    args.push(out_dir.to_str().unwrap());
    args.extend(extra);
    common::harness(&args)
}

/// The run finished (0: every run passed; 3: some did not, which is a result too).
fn finished(output: &Output) -> String {
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    assert!(
        matches!(output.status.code(), Some(0 | 3)),
        "{:?}\n{stdout}\n{}",
        output.status,
        String::from_utf8_lossy(&output.stderr)
    );
    stdout
}

fn manifest(dir: &Path) -> String {
    std::fs::read_to_string(dir.join("manifest.csv")).unwrap()
}

#[test]
fn a_campaign_runs_every_point_and_judges_each_run_by_the_requirements() {
    let dir = tempfile::tempdir().unwrap();
    let stdout = finished(&campaign(dir.path(), &["--workers", "2"]));
    let text = manifest(dir.path());
    let mut lines = text.lines();
    assert_eq!(
        lines.next().unwrap(),
        "index,run,run_seed,point,osc.c,osc.k,osc.x0,end,verdict,robustness:settles,\
         robustness:bounded,error"
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 18, "3 sweep points x 6 runs");
    for (i, row) in rows.iter().enumerate() {
        assert_eq!(row[0], i.to_string());
        // Run j meets every point with the same draw; point p sets c to its value.
        let (run, point) = (i / 3, i % 3);
        assert_eq!(
            (row[1], row[3]),
            (run.to_string().as_str(), point.to_string().as_str())
        );
        assert_eq!(row[4], ["0.2", "0.4", "0.8"][point]);
        assert_eq!(row[5..7], rows[run * 3][5..7]);
        let k: f64 = row[5].parse().unwrap();
        let x0: f64 = row[6].parse().unwrap();
        assert!(
            (0.5..=1.5).contains(&k) && (0.5..=1.5).contains(&x0),
            "{row:?}"
        );
        // The verdict is the requirements' conjunction.
        let robustness: Vec<f64> = row[9..11].iter().map(|r| r.parse().unwrap()).collect();
        let pass = robustness.iter().all(|r| *r > 0.0);
        assert_eq!(row[8], if pass { "pass" } else { "fail" }, "{row:?}");
        // "bounded": |x| stays below 1.6 from a start at most 1.5: robustness 1.6 - x0.
        assert!((robustness[1] - (1.6 - x0)).abs() < 1e-12, "{row:?}");
    }
    // More damping settles more: the strongest damping passes every run, the weakest not.
    let passes = |p: usize| {
        rows.iter()
            .filter(|r| r[3] == p.to_string() && r[8] == "pass")
            .count()
    };
    assert_eq!(passes(2), 6);
    assert!(passes(0) < 6, "{stdout}");
    assert!(stdout.contains("95 % Clopper-Pearson"), "{stdout}");
    assert!(
        stdout.contains("point 2 (osc.c = 0.8): pass 6/6"),
        "{stdout}"
    );
    let summary = std::fs::read_to_string(dir.path().join("summary.csv")).unwrap();
    assert!(
        summary.starts_with("point,osc.c,requirement,runs,passed,pass_rate"),
        "{summary}"
    );
    assert!(dir.path().join("sensitivity.csv").is_file());
    let report = common::harness(&["report", dir.path().to_str().unwrap()]);
    assert!(report.status.success(), "{report:?}");
    let page = std::fs::read_to_string(dir.path().join("report.html")).unwrap();
    assert!(page.contains("Campaign summary") && page.contains("Clopper-Pearson"));
}

#[test]
fn shards_merged_equal_the_whole_campaign_byte_for_byte() {
    let dir = tempfile::tempdir().unwrap();
    let whole = dir.path().join("whole");
    finished(&campaign(&whole, &["--workers", "2", "--quiet"]));
    let shards: Vec<PathBuf> = (1..=2)
        .map(|k| dir.path().join(format!("shard{k}")))
        .collect();
    for (k, shard) in shards.iter().enumerate() {
        let spec = format!("{}/2", k + 1);
        finished(&campaign(
            shard,
            &["--shard", &spec, "--workers", "1", "--quiet", "--no-plots"],
        ));
        assert_eq!(manifest(shard).lines().count(), 1 + 9);
    }
    let merged = dir.path().join("merged");
    let output = common::harness(&[
        "merge-mc",
        shards[0].to_str().unwrap(),
        shards[1].to_str().unwrap(),
        "--out-dir",
        merged.to_str().unwrap(),
    ]);
    finished(&output);
    assert_eq!(manifest(&merged), manifest(&whole));
    // A shard merged twice is refused.
    let output = common::harness(&[
        "merge-mc",
        shards[0].to_str().unwrap(),
        shards[0].to_str().unwrap(),
        "--out-dir",
        dir.path().join("twice").to_str().unwrap(),
    ]);
    assert!(!output.status.success());
    assert!(String::from_utf8_lossy(&output.stderr).contains("appear in two shards"));
}

#[test]
fn resume_runs_only_the_missing_runs_to_the_same_manifest() {
    let dir = tempfile::tempdir().unwrap();
    finished(&campaign(dir.path(), &["--quiet"]));
    let full = manifest(dir.path());
    // Keep the header and the last 7 rows, then half a row as a kill mid-write leaves it:
    // the runs resumed come before the kept ones, so only a sorted rewrite gives the whole
    // campaign's file.
    let lines: Vec<&str> = full.lines().collect();
    let mut cut = [&lines[..1], &lines[12..]].concat().join("\n");
    cut.push('\n');
    cut.push_str(&lines[3][..lines[3].len() / 2]);
    std::fs::write(dir.path().join("manifest.csv"), cut).unwrap();
    let stdout = finished(&campaign(dir.path(), &["--resume", "--quiet"]));
    assert!(
        stdout.contains("ran 11 runs (7 kept from before)"),
        "{stdout}"
    );
    assert_eq!(manifest(dir.path()), full);
    // Another definition is not resumed.
    let output = campaign(dir.path(), &["--resume", "--seed", "8"]);
    assert!(!output.status.success());
    assert!(String::from_utf8_lossy(&output.stderr).contains("holds another campaign"));
}

#[test]
fn a_replayed_run_reproduces_its_manifest_row_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    finished(&campaign(dir.path(), &["--quiet", "--workers", "2"]));
    let out = dir.path().join("run13.csv");
    let output = campaign(
        dir.path(),
        &["--replay", "13", "--out", out.to_str().unwrap()],
    );
    let stdout = finished(&output);
    assert!(
        stdout.contains("identical to") && stdout.contains("row 13, bit for bit"),
        "{stdout}"
    );
    // The trajectory holds every output; its x starts at the run's dispersed x0.
    let row: Vec<String> = manifest(dir.path())
        .lines()
        .nth(14)
        .unwrap()
        .split(',')
        .map(String::from)
        .collect();
    let trajectory = std::fs::read_to_string(&out).unwrap();
    let mut lines = trajectory.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let x = header.iter().position(|h| *h == "osc.x").unwrap();
    let first: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(
        first[x].parse::<f64>().unwrap(),
        row[6].parse::<f64>().unwrap()
    );
    assert!(header.contains(&"osc.v"));
    // A manifest whose row differs is reported as not reproduced.
    let tampered = manifest(dir.path()).replacen(&row[9], "0.123", 1);
    std::fs::write(dir.path().join("manifest.csv"), tampered).unwrap();
    let output = campaign(
        dir.path(),
        &["--replay", "13", "--out", out.to_str().unwrap()],
    );
    assert!(!output.status.success());
    assert!(String::from_utf8_lossy(&output.stderr).contains("does not reproduce"));
}

#[test]
fn every_problem_of_a_campaign_table_is_named_at_once_without_a_backtrace() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(example()).unwrap();
    let bad = text
        .replace("parameter = \"osc.c\"", "parameter = \"spring.c\"")
        .replace("sd = 0.2", "sd = 0.0")
        .replace("min = 0.5\nmax = 1.5\n\n[[campaign.correlation]]", "min = 1.5\nmax = 0.5\n\n[[campaign.correlation]]")
        .replace("rho = 0.3", "rho = 1.0")
        + "\n[[campaign.dispersion]]\nparameter = \"osc.x\"\ndistribution = \"normal\"\nmean = 0.0\nsd = 1.0\n\
           \n[[campaign.dispersion]]\nparameter = \"osc.nope\"\ndistribution = \"normal\"\nmean = 0.0\nsd = 1.0\n";
    let path = dir.path().join("bad.toml");
    std::fs::write(&path, bad).unwrap();
    let output = common::harness(&[
        "campaign",
        path.to_str().unwrap(),
        "--out-dir",
        dir.path().to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    for expected in [
        "6 problems",
        "the scenario has no instance 'spring'",
        "osc.k: sd = 0 must be greater than 0",
        "osc.x0: min = 1.5 must be less than max = 0.5",
        "rho = 1 is not inside (-1, 1)",
        "'x' has causality Output",
        "declares no variable 'nope'",
    ] {
        assert!(
            stderr.contains(expected),
            "missing '{expected}' in:\n{stderr}"
        );
    }
    assert!(
        !stderr.contains("panicked") && !stderr.contains("backtrace"),
        "{stderr}"
    );
    assert!(!dir.path().join("manifest.csv").exists());
}

#[test]
fn a_campaign_without_requirements_is_refused_rather_than_passing_unjudged_runs() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(example()).unwrap();
    let unjudged = &text[..text.find("[[requirement]]").unwrap()];
    let path = dir.path().join("unjudged.toml");
    std::fs::write(&path, unjudged).unwrap();
    let output = common::harness(&[
        "campaign",
        path.to_str().unwrap(),
        "--out-dir",
        dir.path().to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("1 problem in its campaign")
            && stderr.contains("declares no [[requirement]]"),
        "{stderr}"
    );
    assert!(!dir.path().join("manifest.csv").exists());
}

#[test]
fn an_ssp_scenario_takes_its_campaign_from_a_sidecar_file() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(example()).unwrap();
    // The same system as an SSD (its step: 0.01 s) and as TOML with that step.
    let toml = dir.path().join("osc.toml");
    std::fs::write(&toml, text.replace("step_size = 0.05", "step_size = 0.01")).unwrap();
    let ssd = common::oscillator_campaign_ssd(dir.path());
    let run = |scenario: &Path, out: &str| {
        let out = dir.path().join(out);
        finished(&common::harness(&[
            "campaign",
            scenario.to_str().unwrap(),
            "-n",
            "4",
            "--quiet",
            "--out-dir",
            out.to_str().unwrap(),
        ]));
        manifest(&out)
    };
    let from_ssd = run(&ssd, "ssd");
    assert_eq!(from_ssd.lines().count(), 1 + 12);
    assert_eq!(from_ssd, run(&toml, "toml"));
    // Without its sidecar an SSD has no campaign.
    std::fs::remove_file(dir.path().join("osc.campaign.toml")).unwrap();
    let output = common::harness(&["campaign", ssd.to_str().unwrap()]);
    assert!(String::from_utf8_lossy(&output.stderr).contains("osc.campaign.toml: cannot read it"));
}

/// The Oscillator with a scenario event (`osc.k` stiffened at 5 s) whose time a campaign
/// draws, and an Integer parameter (`osc.substeps`) swept.
const EVENT_CAMPAIGN: &str = r#"name = "oscillator-event"
stop_time = 20.0
step_size = 0.05

[[instance]]
name = "osc"
fmu = "Oscillator.fmu"
[instance.parameters]
substeps = 1

[[event]]
name = "stiffen"
time = 5.0
set = "osc.k"
value = 4.0

[campaign]
runs = 3
seed = 5

[[campaign.sweep]]
parameter = "osc.substeps"
values = [1, 3]

[[campaign.dispersion]]
parameter = "event.stiffen.time"
distribution = "uniform"
min = 2.0
max = 15.0

[[requirement]]
name = "bounded"
formula = "always [0, 20] abs(osc.x) < 1.6"
"#;

/// The `osc.x` column of a trajectory CSV, as bits.
fn x_column(path: &Path) -> Vec<u64> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let x = header.iter().position(|h| *h == "osc.x").unwrap();
    lines
        .map(|l| {
            l.split(',')
                .nth(x)
                .unwrap()
                .parse::<f64>()
                .unwrap()
                .to_bits()
        })
        .collect()
}

#[test]
fn a_drawn_event_time_is_flown_as_a_harness_run_with_that_event_time() {
    let dir = tempfile::tempdir().unwrap();
    let scenario = dir.path().join("event.toml");
    std::fs::write(&scenario, EVENT_CAMPAIGN).unwrap();
    let out_dir = dir.path().join("campaign");
    let (scenario, out) = (scenario.to_str().unwrap(), out_dir.to_str().unwrap());
    finished(&common::harness(&[
        "campaign",
        scenario,
        "--out-dir",
        out,
        "--quiet",
    ]));
    let manifest = manifest(&out_dir);
    let mut lines = manifest.lines();
    assert!(lines
        .next()
        .unwrap()
        .starts_with("index,run,run_seed,point,osc.substeps,event.stiffen.time,"));
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    // The Integer sweep's values are written as integers, each on the same draws.
    let substeps: Vec<&str> = rows.iter().map(|r| r[4]).collect();
    assert_eq!(substeps, ["1", "3", "1", "3", "1", "3"]);
    let times: Vec<f64> = rows.iter().map(|r| r[5].parse().unwrap()).collect();
    assert!(times.iter().all(|t| (2.0..15.0).contains(t)), "{times:?}");
    assert_eq!(times[2], times[3]);
    assert_ne!(times[0], times[2]);
    // Run 2 (substeps 1) replayed equals `harness run` of the scenario with its drawn time.
    let replayed = dir.path().join("replay.csv");
    finished(&common::harness(&[
        "campaign",
        scenario,
        "--out-dir",
        out,
        "--replay",
        "2",
        "--out",
        replayed.to_str().unwrap(),
    ]));
    let run_with = |time: &str, name: &str| {
        let path = dir.path().join(format!("{name}.toml"));
        let text = EVENT_CAMPAIGN.replace("time = 5.0", &format!("time = {time}"));
        std::fs::write(&path, text).unwrap();
        let csv = dir.path().join(format!("{name}.csv"));
        let output = common::harness(&[
            "run",
            path.to_str().unwrap(),
            "--out",
            csv.to_str().unwrap(),
        ]);
        assert!(output.status.success(), "{output:?}");
        x_column(&csv)
    };
    let campaign_x = x_column(&replayed);
    assert!(
        campaign_x == run_with(rows[2][5], "drawn"),
        "run 2 is not `harness run` with event time {}",
        rows[2][5]
    );
    // Not the declared time's run: the drawn time is what moved the event.
    assert!(campaign_x != run_with("5.0", "declared"));
}

#[test]
fn every_bad_event_or_integer_target_is_named_at_once() {
    let dir = tempfile::tempdir().unwrap();
    let bad = EVENT_CAMPAIGN
        .replace("values = [1, 3]", "values = [1.5, 2000]")
        + "\n[[campaign.sweep]]\nparameter = \"event.stiffen.time\"\nvalues = [25.0]\n\
           \n[[campaign.dispersion]]\nparameter = \"event.nope.time\"\ndistribution = \"uniform\"\nmin = 1.0\nmax = 2.0\n\
           \n[[campaign.dispersion]]\nparameter = \"osc.crossing_direction\"\ndistribution = \"uniform\"\nmin = 1.0\nmax = 2.0\n";
    let bad = bad.replace(
        "[[campaign.dispersion]]\nparameter = \"event.stiffen.time\"",
        "[[campaign.dispersion]]\nparameter = \"event.stiffen.value\"",
    );
    let path = dir.path().join("bad.toml");
    std::fs::write(&path, bad).unwrap();
    let output = common::harness(&[
        "campaign",
        path.to_str().unwrap(),
        "--out-dir",
        dir.path().to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    for expected in [
        "5 problems",
        "osc.substeps: value 1.5 is not an integer",
        "osc.substeps: value 2000 is outside the declared range [1, 1000]",
        "event.stiffen.time: value 25: event 'stiffen'",
        "the scenario has no event 'nope' (it has stiffen)",
        "osc.crossing_direction: an integer is swept over its values, not drawn",
    ] {
        assert!(
            stderr.contains(expected),
            "missing '{expected}' in:\n{stderr}"
        );
    }
    assert!(!dir.path().join("manifest.csv").exists());
}

#[test]
fn a_drawn_event_time_the_event_rules_refuse_ends_that_run_in_error() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("late.toml");
    let text = EVENT_CAMPAIGN.replace("min = 2.0\nmax = 15.0", "min = 10.0\nmax = 30.0");
    std::fs::write(&path, text.replace("runs = 3", "runs = 8")).unwrap();
    let output = common::harness(&[
        "campaign",
        path.to_str().unwrap(),
        "--out-dir",
        dir.path().to_str().unwrap(),
        "--quiet",
    ]);
    assert_eq!(output.status.code(), Some(1), "{output:?}");
    let mut reader = csv::Reader::from_path(dir.path().join("manifest.csv")).unwrap();
    let mut errors = 0;
    for record in reader.records() {
        let row = record.unwrap();
        let time: f64 = row[5].parse().unwrap();
        // The last step starts at 19.95 s; a later time changes nothing and is refused.
        assert_eq!(time > 19.95, &row[7] == "error", "{row:?}");
        if time > 20.0 {
            assert!(
                row[9].contains("is outside [start_time, stop_time]"),
                "{row:?}"
            );
        }
        errors += usize::from(&row[7] == "error");
    }
    assert!(errors > 0 && errors < 16, "{errors} of 16 runs in error");
}
