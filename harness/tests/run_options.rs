//! `harness run --stop-time/--step-size` and `harness paper --set`: the options change what
//! is flown, and bad values are refused before anything runs, all at once, exit code 1.
use crate::common;

use common::harness;

#[test]
fn stop_time_and_step_size_override_the_scenario() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("short.csv");
    // A scenario without requirements: cut short, the paper's would be inconclusive.
    let output = harness(&[
        "run",
        "upright",
        "--stop-time",
        "5",
        "--step-size",
        "0.02",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let csv = std::fs::read_to_string(&out).unwrap();
    let times: Vec<&str> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').next().unwrap())
        .collect();
    // 5 s in steps of 0.02 s: 251 rows, from 0 to 5 s
    assert_eq!(times.len(), 251);
    assert_eq!((times[1], *times.last().unwrap()), ("0.02", "5.0"));
}

#[test]
fn bad_stop_time_and_step_size_are_refused_together_before_the_run() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("never.csv");
    let output = harness(&[
        "run",
        "paper",
        "--stop-time",
        "-5",
        "--step-size",
        "0",
        "-o",
        out.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("step_size must be a positive number, got 0"),
        "{stderr}"
    );
    assert!(
        stderr.contains("stop_time (-5) must be after start_time (0)"),
        "{stderr}"
    );
    assert!(!out.exists());
}

#[test]
fn paper_applies_set_to_every_law_and_refuses_the_law_it_varies() {
    // GIVEN the paper command with the start altitude changed, for 1 s
    let dir = tempfile::tempdir().unwrap();
    let scenario = dir.path().join("short.toml");
    let text =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/scenarios/paper.toml"))
            .unwrap()
            .replace("stop_time = 172.0", "stop_time = 1.0");
    // the paper scenario's requirements read up to 172 s; a 1 s flight only needs the runs
    let text = text.split("[[requirement]]").next().unwrap().to_owned();
    std::fs::write(&scenario, text).unwrap();
    let out_dir = dir.path().join("paper");
    let output = harness(&[
        "paper",
        scenario.to_str().unwrap(),
        "--set",
        "plant.r0_nue[2]=600",
        "--no-plots",
        "--out-dir",
        out_dir.to_str().unwrap(),
    ]);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    // THEN every law's flight starts at 600 m
    let mut flights = 0;
    for entry in std::fs::read_dir(&out_dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "csv") && path.to_string_lossy().contains("-") {
            let csv = std::fs::read_to_string(&path).unwrap();
            let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
            let column = header.iter().position(|h| *h == "plant.r_nue[2]");
            let Some(column) = column else { continue };
            let first: Vec<&str> = csv.lines().nth(1).unwrap().split(',').collect();
            assert_eq!(first[column], "600.0", "{}", path.display());
            flights += 1;
        }
    }
    let system = lander::scenarios::load("paper").unwrap();
    let laws = lander::laws::Laws::of_instance(&system, "gnc", &common::fmu_dir()).unwrap();
    assert_eq!(flights, laws.all().len(), "one trajectory per law");
    // AND setting the law it varies is refused, with the other problems, exit 1
    let output = harness(&[
        "paper",
        scenario.to_str().unwrap(),
        "--set",
        "gnc.control_law=1",
        "--set",
        "nosuch.x=1",
        "--no-plots",
        "--out-dir",
        out_dir.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("this command sets gnc.control_law itself"),
        "{stderr}"
    );
    assert!(
        stderr.contains("--set nosuch.x=1: no instance 'nosuch'"),
        "{stderr}"
    );
}

/// A results file that cannot take the rows (here the disk is full) stops the run at the
/// first row that failed, exit code 1, instead of flying on to the end and saying so then.
#[test]
fn a_write_error_stops_the_run_where_it_happened() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("full.csv");
    // The run writes OUT.partial until it ends: point that at a device whose every write
    // fails with ENOSPC.
    std::os::unix::fs::symlink("/dev/full", dir.path().join("full.csv.partial")).unwrap();
    let output = harness(&["run", "paper", "-o", out.to_str().unwrap()]);
    // The error verdict of a run that started is on stdout.
    let stderr = String::from_utf8_lossy(&output.stdout);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    let time: f64 = stderr
        .split("recording the row at t = ")
        .nth(1)
        .and_then(|rest| rest.split_whitespace().next())
        .and_then(|t| t.trim_end_matches(',').parse().ok())
        .unwrap_or_else(|| panic!("no failed row named in: {stderr}"));
    // The first 8 KiB buffer of rows (about 1,000 bytes per row) fails long before 172 s.
    assert!(time < 1.0, "stopped at {time} s: {stderr}");
    assert!(stderr.contains("No space left on device"), "{stderr}");
    assert!(
        !out.exists(),
        "a failed run must leave no file under its name"
    );
}

/// Every recorded column carries its FMU's unit: in the Arrow schema (field metadata
/// `unit`) and, for a CSV, in `NAME.units.csv` beside it.
#[test]
fn results_carry_the_units_the_fmus_declare() {
    let dir = tempfile::tempdir().unwrap();
    let expected = [
        ("time", "s"),
        ("plant.r_nue[2]", "m"),
        ("plant.omega_body[1]", "rad/s"),
        ("gnc.thrust_cmd", "N"),
    ];
    let csv = dir.path().join("short.csv");
    let arrow = dir.path().join("short.arrow");
    for out in [&csv, &arrow] {
        let output = harness(&[
            "run",
            "upright",
            "--stop-time",
            "0.1",
            "-o",
            out.to_str().unwrap(),
        ]);
        assert!(
            output.status.success(),
            "{}",
            String::from_utf8_lossy(&output.stderr)
        );
    }
    let units_csv = std::fs::read_to_string(dir.path().join("short.units.csv")).unwrap();
    assert!(
        units_csv.starts_with("column,unit\ntime,s\n"),
        "{units_csv}"
    );
    let header = std::fs::read_to_string(&csv).unwrap();
    let columns = header.lines().next().unwrap().split(',').count();
    assert_eq!(units_csv.lines().count(), columns + 1, "one row per column");
    let from_arrow = cosim::results::read_arrow_units(&arrow).unwrap();
    assert_eq!(from_arrow.len(), columns);
    for (name, unit) in expected {
        assert!(
            units_csv.contains(&format!("\n{name},{unit}\n")),
            "{name}: {units_csv}"
        );
        assert!(
            from_arrow.contains(&(name.to_owned(), unit.to_owned())),
            "{name}: {from_arrow:?}"
        );
    }
    assert!(!dir.path().join("short.arrow.units.csv").exists());
}

/// A reader that closes the pipe before the summary is printed (`harness run ... | head -0`)
/// ends the harness as it ends any command-line tool (SIGPIPE), with no panic on stderr.
#[test]
#[cfg(unix)]
fn a_closed_stdout_ends_the_run_quietly() {
    use std::os::unix::process::ExitStatusExt;
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("run.csv");
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_harness"))
        .arg("--fmu-dir")
        .arg(common::fmu_dir())
        .args(["run", "paper", "-o", out.to_str().unwrap()])
        .env("RUST_BACKTRACE", "1")
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let output = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert_eq!(output.status.signal(), Some(SIGPIPE), "{:?}", output.status);
    // The results were complete before the summary line failed.
    assert!(out.exists());
}

/// SIGPIPE on Linux and the BSDs.
const SIGPIPE: i32 = 13;

/// A `record` list that leaves out the touchdown columns still has its landing judged (they
/// are read once, at the end, and not written), and a pattern records a family of columns.
#[test]
fn a_record_list_leaves_the_landing_judged_and_patterns_select_columns() {
    let dir = tempfile::tempdir().unwrap();
    let header = |path: &std::path::Path| -> Vec<String> {
        let text = std::fs::read_to_string(path).unwrap();
        text.lines()
            .next()
            .unwrap()
            .split(',')
            .map(str::to_owned)
            .collect()
    };
    let few = dir.path().join("few.csv");
    let output = harness(&[
        "run",
        "landing",
        "--record",
        "plant.r_nue",
        "-o",
        few.to_str().unwrap(),
    ]);
    let text = String::from_utf8_lossy(&output.stdout);
    assert_eq!(
        output.status.code(),
        Some(lander::verdict::EXIT_OK),
        "{text}"
    );
    assert!(text.contains("landed inside the envelope"), "{text}");
    assert_eq!(
        header(&few),
        ["time", "plant.r_nue[1]", "plant.r_nue[2]", "plant.r_nue[3]"]
    );

    let family = dir.path().join("family.csv");
    let output = harness(&[
        "run",
        "landing",
        "--record",
        "plant.touchdown*,plant.r_nue[2],plant.touchdown",
        "-o",
        family.to_str().unwrap(),
    ]);
    let text = String::from_utf8_lossy(&output.stdout);
    assert_eq!(
        output.status.code(),
        Some(lander::verdict::EXIT_OK),
        "{text}"
    );
    let columns = header(&family);
    assert!(
        columns
            .iter()
            .skip(1)
            .all(|c| c.starts_with("plant.touchdown") || c == "plant.r_nue[2]"),
        "{columns:?}"
    );
    for wanted in [
        "plant.touchdown",
        "plant.touchdown_time",
        "plant.touchdown_v_nue[3]",
        "plant.touchdown_tilt",
    ] {
        assert_eq!(
            columns.iter().filter(|c| *c == wanted).count(),
            1,
            "{wanted} in {columns:?}"
        );
    }

    let output = harness(&[
        "run",
        "landing",
        "--record",
        "plant.nothing_like_this*",
        "-o",
        family.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_ne!(output.status.code(), Some(0));
    assert!(
        stderr.contains("'plant.nothing_like_this*' matches no variable"),
        "{stderr}"
    );
}

/// `--fmu-dir` given twice: a relative FMU path is looked up in each, in order, also by the
/// worker process that runs the FMUs; a file in none is named with every directory tried.
#[test]
fn repeated_fmu_dirs_are_searched_in_order() {
    let (scenarios, more) = (tempfile::tempdir().unwrap(), tempfile::tempdir().unwrap());
    let oscillator = crate::common::fmu_dir().join("Oscillator.fmu");
    std::fs::copy(&oscillator, more.path().join("Elsewhere.fmu")).unwrap();
    let scenario = scenarios.path().join("elsewhere.toml");
    std::fs::write(
        &scenario,
        "name = \"elsewhere\"\nstop_time = 1.0\n[[instance]]\nname = \"osc\"\nfmu = \"Elsewhere.fmu\"\n",
    )
    .unwrap();
    let out = scenarios.path().join("out.csv");
    let args = |extra: &[&str]| {
        let mut all = vec![
            "run",
            scenario.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ];
        all.extend_from_slice(extra);
        harness(&all)
    };
    // The helper's own --fmu-dir (target/fmu) comes first and has no Elsewhere.fmu.
    let output = args(&["--fmu-dir", more.path().to_str().unwrap()]);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    assert!(std::fs::read_to_string(&out)
        .unwrap()
        .starts_with("time,osc.x"));

    let output = args(&[]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("Elsewhere.fmu") && stderr.contains("--fmu-dir (repeatable)"),
        "{stderr}"
    );
}
