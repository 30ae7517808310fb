//! The harness imports FMI 3.0 Co-Simulation FMUs (`cargo xtask fmus` writes them to
//! target/fmu/fmi3/): the paper scenario flown with the FMI 3.0 pair gives the FMI 2.0 pair's
//! verdict and trajectory, array elements answer to the FMI 2.0 scalar names, a model alone
//! runs, and FMI 3.0 input the harness cannot drive is refused before the run. The importer's
//! own FMI 3.0 behaviour (Step and Event Mode, every exchanged type) is tested in
//! fmi-import/tests/fmi3_import.rs.
use crate::common;
use fmi_import::{FmiVersion, Fmu};
use std::fs;
use std::path::{Path, PathBuf};

/// target/fmu (checked to hold the FMI 2.0 FMUs) with every FMI 3.0 FMU the crates'
/// metadata ships under fmi3/.
fn fmu_dir() -> PathBuf {
    let dir = common::fmu_dir();
    let fmus = fmu_metadata::fmus_around(env!("CARGO_MANIFEST_DIR")).unwrap();
    let shipped = fmus.iter().filter(|f| f.ships(fmu_metadata::Fmi::V3));
    for fmu in shipped.map(|f| &f.model_identifier) {
        let path = dir.join("fmi3").join(format!("{fmu}.fmu"));
        assert!(
            path.is_file(),
            "{} is missing: run `cargo xtask fmus` first",
            path.display()
        );
    }
    dir
}

fn scenario(name: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("scenarios/{name}.toml"));
    fs::read_to_string(path).unwrap()
}

/// The scenario text with every `fmu = "X.fmu"` pointed at `fmi3/X.fmu`, checked to change
/// `expected` lines and nothing else.
fn with_fmi3_paths(text: &str, expected: usize) -> String {
    let mut changed = 0;
    let out: Vec<String> = text
        .lines()
        .map(|line| match line.strip_prefix("fmu = \"") {
            Some(rest) => {
                changed += 1;
                format!("fmu = \"fmi3/{rest}")
            }
            None => line.to_owned(),
        })
        .collect();
    assert_eq!(changed, expected, "fmu lines in the scenario");
    out.join("\n") + "\n"
}

/// `harness run` of a scenario text; its stdout and the recorded CSV.
fn run(dir: &Path, label: &str, text: &str, extra: &[&str]) -> (String, String) {
    let toml = dir.join(format!("{label}.toml"));
    let csv = dir.join(format!("{label}.csv"));
    fs::write(&toml, text).unwrap();
    let mut args = vec!["run", toml.to_str().unwrap(), "-o", csv.to_str().unwrap()];
    args.extend_from_slice(extra);
    let output = harness_in(&fmu_dir(), &args);
    // Flown: exit 0, or 3 when a shortened run leaves the scenario's requirement windows
    // uncovered (inconclusive); the trajectories are what is compared.
    assert!(
        matches!(output.status.code(), Some(0 | 3)),
        "{label}: harness run failed: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    let stdout = String::from_utf8_lossy(&output.stdout).replace(csv.to_str().unwrap(), "OUT");
    (stdout, fs::read_to_string(csv).unwrap())
}

fn harness_in(fmu_dir: &Path, args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_harness"))
        .arg("--fmu-dir")
        .arg(fmu_dir)
        .args(args)
        .env("RUST_BACKTRACE", "0")
        .output()
        .unwrap()
}

fn rows(csv: &str) -> Vec<Vec<&str>> {
    csv.lines().map(|line| line.split(',').collect()).collect()
}

#[test]
fn the_paper_scenario_with_the_fmi3_pair_flies_the_fmi2_trajectory_bit_for_bit() {
    // GIVEN the shipped paper.toml and the same file with its two FMUs the FMI 3.0 twins
    let temp = tempfile::tempdir().unwrap();
    let fmi2 = scenario("paper");
    let fmi3 = with_fmi3_paths(&fmi2, 2);
    // WHEN both are flown by `harness run`
    let (verdict2, csv2) = run(temp.path(), "fmi2", &fmi2, &[]);
    let (verdict3, csv3) = run(temp.path(), "fmi3", &fmi3, &[]);
    // THEN the verdict is the same, and so is every recorded value: the CSV holds the shortest
    // round-trip text of each double, so equal text is equal bits. Gauss-Seidel puts LanderGnc
    // (every output depends on every input) in Event Mode, where a get after a set sees the
    // inputs just set, as in FMI 2.0: the same call order, no added delay.
    assert!(
        verdict2.contains("verdict: completed at t = 172.00 s"),
        "{verdict2}"
    );
    assert_eq!(verdict3, verdict2);
    assert_eq!(rows(&csv3).len(), 17_202, "header and 17,201 rows");
    assert!(csv3.starts_with("time,gnc.thrust_cmd,gnc.torque_cmd_body[1],"));
    assert!(
        csv3 == csv2,
        "the FMI 3.0 trajectory differs from FMI 2.0's"
    );
}

#[test]
fn a_touchdown_ends_the_fmi3_run_with_the_touchdown_row_as_the_last() {
    // GIVEN the landing scenario, which flies to touchdown, in both versions
    let temp = tempfile::tempdir().unwrap();
    let fmi2 = scenario("landing");
    let (verdict2, csv2) = run(temp.path(), "fmi2", &fmi2, &[]);
    let (verdict3, csv3) = run(temp.path(), "fmi3", &with_fmi3_paths(&fmi2, 2), &[]);
    // THEN FMI 3.0's early return with terminateSimulation ends the run as FMI 2.0's
    // fmi2Discard + fmi2Terminated does: the same verdict and the same rows, the last one at
    // the touchdown itself (lastSuccessfulTime of the early return, as
    // fmi2LastSuccessfulTime), every value bit for bit.
    assert!(verdict2.contains("touchdown at t = 323.61 s"), "{verdict2}");
    assert_eq!(verdict3, verdict2);
    let (rows2, rows3) = (rows(&csv2), rows(&csv3));
    let last = rows2.len() - 1;
    let previous: f64 = rows2[last - 1][0].parse().unwrap();
    let touchdown: f64 = rows3[last][0].parse().unwrap();
    assert!(
        previous < touchdown && touchdown < previous + 0.01,
        "the touchdown row is inside the last step: {touchdown}"
    );
    assert!(csv3 == csv2, "the FMI 3.0 landing differs from FMI 2.0's");
}

#[test]
fn jacobi_is_the_same_in_both_versions_the_last_row_included() {
    // GIVEN the paper scenario with Jacobi ordering, in both versions
    let temp = tempfile::tempdir().unwrap();
    let fmi2 = scenario("paper");
    let jacobi = ["--ordering", "jacobi"];
    let (verdict2, csv2) = run(temp.path(), "fmi2", &fmi2, &jacobi);
    let (verdict3, csv3) = run(temp.path(), "fmi3", &with_fmi3_paths(&fmi2, 2), &jacobi);
    assert_eq!(verdict3, verdict2);
    // THEN Jacobi never reads an output after setting an input at the same point, so FMI 3.0
    // stays in Step Mode, and neither version exchanges after the last step: every row is
    // the same, the last included (its command is the GNC's answer to the inputs of the
    // last step, in both).
    let (rows2, rows3) = (rows(&csv2), rows(&csv3));
    assert_eq!(rows2.len(), 17_202, "a header and 17,201 rows");
    assert_eq!(rows2, rows3);
}

#[test]
fn array_elements_answer_to_the_fmi2_scalar_names_in_set_connections_and_columns() {
    // GIVEN both plants loaded
    let dir = fmu_dir();
    let plant2 = Fmu::load(dir.join("LanderPlant.fmu")).unwrap();
    let plant3 = Fmu::load(dir.join("fmi3/LanderPlant.fmu")).unwrap();
    assert_eq!(plant2.fmi_version(), FmiVersion::Fmi2);
    assert_eq!(plant3.fmi_version(), FmiVersion::Fmi3);
    // THEN the FMI 3.0 array r0_nue of dimension 3 is seen as r0_nue[1..3], as FMI 2.0 names
    // its scalars, with the same types and causalities
    let names = |fmu: &Fmu| -> Vec<String> {
        fmu.model_description()
            .model_variables
            .variables
            .iter()
            .map(|v| v.name.clone())
            .filter(|n| n != "time")
            .collect()
    };
    let mut names2 = names(&plant2);
    let mut names3 = names(&plant3);
    names2.sort();
    names3.sort();
    assert_eq!(names3, names2);
    for name in ["r0_nue[2]", "r_nue[3]", "q_body_to_nue[4]", "thrust_cmd"] {
        let (a, b) = (
            plant2.variable(name).unwrap(),
            plant3.variable(name).unwrap(),
        );
        assert_eq!((a.kind, a.causality), (b.kind, b.causality), "{name}");
    }
    assert_eq!(
        plant3
            .fmi3_description()
            .unwrap()
            .variables
            .iter()
            .filter(|v| v.name == "r0_nue")
            .count(),
        1
    );
    // AND a scenario setting one element with --set flies the same in both versions
    let temp = tempfile::tempdir().unwrap();
    let fmi2 = scenario("paper").replace("stop_time = 172.0", "stop_time = 3.0");
    let set = ["--set", "plant.r0_nue[2]=600", "--record", "plant.r_nue"];
    let (_, csv2) = run(temp.path(), "fmi2", &fmi2, &set);
    let (_, csv3) = run(temp.path(), "fmi3", &with_fmi3_paths(&fmi2, 2), &set);
    // (the paper scenario's requirements record their signal too: the 15 deg start tilt)
    assert!(
        csv3.starts_with(
            "time,plant.r_nue[1],plant.r_nue[2],plant.r_nue[3],gnc.tilt_error\n\
             0.0,0.0,600.0,0.0,0.2617993877991494\n"
        ),
        "{}",
        &csv3[..120]
    );
    assert!(csv3 == csv2);
}

#[test]
fn the_oscillator_and_the_navigation_model_run_alone_in_fmi3() {
    let temp = tempfile::tempdir().unwrap();
    let oscillator = |fmu: &str| {
        format!(
            "name = \"oscillator\"\nstart_time = 0.0\nstop_time = 5.0\nstep_size = 0.01\n\n\
             [[instance]]\nname = \"osc\"\nfmu = \"{fmu}\"\n[instance.parameters]\n\
             k = 4.0\nstop_at_threshold = false\nlabel = \"alone\"\ncrossing_direction = 2\n"
        )
    };
    let (verdict2, csv2) = run(temp.path(), "osc2", &oscillator("Oscillator.fmu"), &[]);
    let (verdict3, csv3) = run(temp.path(), "osc3", &oscillator("fmi3/Oscillator.fmu"), &[]);
    assert!(verdict3.contains("completed at t = 5.00 s"), "{verdict3}");
    assert_eq!(verdict3, verdict2);
    // An Integer column is written as integers.
    assert!(csv3.starts_with("time,osc.x,osc.v,osc.step_count\n0.0,1.0,0.0,0\n"));
    // The state event inside the third step: FMI 2.0 has no early return and the FMU steps
    // on from the event within fmi2DoStep; FMI 3.0 returns early there and the importer
    // steps on with fmi3DoStep(t_event, t + h - t_event), whose end the FMU recomputes as
    // t_event + (t + h - t_event): the same time to within a rounding, and the rest of the
    // step integrated from the event as one span rather than as the FMU's own continuation.
    // Measured: 5.4e-11 relative over the 5 s (three crossings).
    let (rows2, rows3) = (rows(&csv2), rows(&csv3));
    assert_eq!(rows2.len(), rows3.len());
    let mut worst = 0.0f64;
    for (a, b) in rows2.iter().zip(&rows3).skip(1) {
        assert_eq!(a[0], b[0], "the grid");
        assert_eq!(a[3], b[3], "step_count");
        for j in 1..3 {
            let (x, y): (f64, f64) = (a[j].parse().unwrap(), b[j].parse().unwrap());
            worst = worst.max((x - y).abs() / x.abs().max(1e-3));
        }
    }
    assert!(
        worst < 1e-9,
        "FMI 3.0 vs FMI 2.0 oscillator: relative {worst:e}"
    );
    assert!(rows2[..4] == rows3[..4], "identical before the event");
    // The navigation error model between plant and GNC, all three in FMI 3.0.
    let nav = scenario("paper-nav").replace("stop_time = 172.0", "stop_time = 5.0");
    let (verdict2, csv2) = run(temp.path(), "nav2", &nav, &[]);
    let (verdict3, csv3) = run(temp.path(), "nav3", &with_fmi3_paths(&nav, 3), &[]);
    assert_eq!(verdict3, verdict2);
    assert!(csv3 == csv2);
}

/// An unpacked copy of the FMI 3.0 Oscillator with its model description edited.
fn edited_oscillator(dir: &Path, edit: impl Fn(&str) -> String) -> PathBuf {
    let unpacked = dir.join("Edited");
    common::unzip_to(&fmu_dir().join("fmi3/Oscillator.fmu"), &unpacked);
    let description = unpacked.join("modelDescription.xml");
    let text = fs::read_to_string(&description).unwrap();
    let edited = edit(&text);
    assert_ne!(edited, text, "the edit applies");
    fs::write(&description, edited).unwrap();
    unpacked
}

#[test]
fn fmi3_input_the_harness_cannot_drive_is_refused_before_the_run_naming_fmu_and_reason() {
    type Edit = fn(&str) -> String;
    let cases: [(&str, Edit, &str); 3] = [
        (
            "Scheduled Execution only",
            |xml| {
                let mut xml = xml.to_owned();
                let mut identifier = String::new();
                for element in ["  <CoSimulation ", "  <ModelExchange "] {
                    if let Some(start) = xml.find(element) {
                        let end = start + xml[start..].find("/>\n").unwrap() + 3;
                        let tag = &xml[start..end];
                        let id = tag.split("modelIdentifier=\"").nth(1).unwrap();
                        identifier = id[..id.find('"').unwrap()].to_owned();
                        xml.replace_range(start..end, "");
                    }
                }
                let at = xml
                    .find("  <ModelVariables>")
                    .unwrap_or(xml.find('\n').unwrap() + 1);
                xml.insert_str(
                    at,
                    &format!("  <ScheduledExecution modelIdentifier=\"{identifier}\"/>\n"),
                );
                xml
            },
            "it has neither <CoSimulation> nor <ModelExchange> (only <ScheduledExecution>)",
        ),
        (
            "a clock",
            |xml| {
                xml.replace(
                    "<ModelVariables>",
                    "<ModelVariables>\n    <Clock name=\"tick\" valueReference=\"77\" \
                     causality=\"input\" intervalVariability=\"triggered\"/>",
                )
            },
            "it declares the clock 'tick'; the harness does not drive clocks",
        ),
        (
            "an array sized by a variable that does not exist",
            |xml| {
                xml.replace(
                    "<ModelVariables>",
                    "<ModelVariables>\n    <Float64 name=\"z\" valueReference=\"78\" \
                     causality=\"local\"><Dimension valueReference=\"999\"/></Float64>",
                )
            },
            "array 'z' takes a dimension from value reference 999, which no variable has",
        ),
    ];
    for (label, edit, reason) in cases {
        let temp = tempfile::tempdir().unwrap();
        let fmu = edited_oscillator(temp.path(), edit);
        let toml = temp.path().join("alone.toml");
        fs::write(
            &toml,
            format!(
                "name = \"alone\"\nstart_time = 0.0\nstop_time = 1.0\nstep_size = 0.01\n\n\
                 [[instance]]\nname = \"osc\"\nfmu = \"{}\"\n",
                fmu.display()
            ),
        )
        .unwrap();
        let out = temp.path().join("never.csv");
        let output = harness_in(
            &fmu_dir(),
            &["run", toml.to_str().unwrap(), "-o", out.to_str().unwrap()],
        );
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(!output.status.success(), "{label}: accepted");
        assert!(!out.exists(), "{label}: a run started");
        assert!(
            stderr.contains("instance 'osc'") && stderr.contains(&fmu.display().to_string()),
            "{label}: the FMU is named: {stderr}"
        );
        assert!(
            stderr.contains("model 'Oscillator' (FMI 3.0) cannot be run")
                && stderr.contains(reason),
            "{label}: the reason is given: {stderr}"
        );
    }
}

#[test]
fn a_monte_carlo_campaign_over_the_fmi3_pair_gives_the_fmi2_manifest() {
    // GIVEN a small dispersed campaign of the paper scenario (dispersions set through array
    // element names, instances reset between flights) in both versions
    let temp = tempfile::tempdir().unwrap();
    let fmi2 = scenario("paper");
    let scenarios = [("fmi2", fmi2.clone()), ("fmi3", with_fmi3_paths(&fmi2, 2))];
    let mut manifests = Vec::new();
    for (label, text) in scenarios {
        let toml = temp.path().join(format!("{label}.toml"));
        fs::write(&toml, text).unwrap();
        let out = temp.path().join(label);
        let output = harness_in(
            &fmu_dir(),
            &[
                "monte-carlo",
                "--scenario",
                toml.to_str().unwrap(),
                "-n",
                "3",
                "--workers",
                "1",
                "--seed",
                "7",
                "--out-dir",
                out.to_str().unwrap(),
                "--no-plots",
                "-q",
            ],
        );
        // 3: flown, some flights outside the paper scenario's limits.
        assert!(
            matches!(output.status.code(), Some(0 | 3)),
            "{label}: {}",
            String::from_utf8_lossy(&output.stderr)
        );
        manifests.push(fs::read_to_string(out.join("manifest.csv")).unwrap());
    }
    // THEN every flight's metrics and verdict are the same, to the last digit
    assert!(manifests[0].lines().count() > 3, "a header and the flights");
    assert!(manifests[1] == manifests[0], "the FMI 3.0 campaign differs");
}
