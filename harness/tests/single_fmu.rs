//! `harness run X.fmu`: one FMU flown alone over its DefaultExperiment, as fmpy's
//! `simulate_fmu` and fmusim run one; the interface chosen from what the FMU declares, or
//! named with `--interface`.
use crate::common;

use common::harness;
use std::path::{Path, PathBuf};

fn oscillator(version: &str) -> PathBuf {
    let dir = common::workspace_root().join("target/fmu");
    let path = match version {
        "2.0" => dir.join("Oscillator.fmu"),
        _ => dir.join("fmi3/Oscillator.fmu"),
    };
    assert!(
        path.is_file(),
        "{} is missing: run `cargo xtask fmus`",
        path.display()
    );
    path
}

fn run(args: &[&str]) -> (String, String) {
    let output = harness(args);
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    assert!(output.status.success(), "{args:?}: {stderr}");
    (String::from_utf8_lossy(&output.stdout).into_owned(), stderr)
}

fn joined<'a>(a: &[&'a str], b: &[&'a str]) -> Vec<&'a str> {
    [a, b].concat()
}

fn csv_rows(path: &Path) -> Vec<Vec<String>> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .map(|l| l.split(',').map(str::to_owned).collect())
        .collect()
}

#[test]
fn an_fmu_runs_alone_over_its_default_experiment_recording_every_output() {
    for version in ["2.0", "3.0"] {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("osc.csv");
        let fmu = oscillator(version);
        run(&["run", fmu.to_str().unwrap(), "-o", out.to_str().unwrap()]);
        let rows = csv_rows(&out);
        // Every output, the Integer step counter included, under the file's name.
        assert_eq!(
            rows[0],
            [
                "time",
                "Oscillator.x",
                "Oscillator.v",
                "Oscillator.step_count"
            ],
            "FMI {version}"
        );
        // DefaultExperiment: 0 to 10 s in steps of 0.01 s.
        assert_eq!(rows.len() - 1, 1001, "FMI {version}");
        assert_eq!(rows.last().unwrap()[0].parse::<f64>().unwrap(), 10.0);
        let steps: f64 = rows.last().unwrap()[3].parse().unwrap();
        assert_eq!(steps, 1000.0, "FMI {version}");
    }
}

#[test]
fn a_single_fmu_takes_bare_variable_names_in_set_and_record() {
    let dir = tempfile::tempdir().unwrap();
    let fmu = oscillator("3.0");
    let stiff = dir.path().join("stiff.csv");
    let soft = dir.path().join("soft.csv");
    for (k, out) in [("4", &stiff), ("1", &soft)] {
        run(&[
            "run",
            fmu.to_str().unwrap(),
            "--set",
            &format!("k={k}"),
            "--record",
            "x,Oscillator.v",
            "--stop-time",
            "1",
            "-o",
            out.to_str().unwrap(),
        ]);
    }
    let (stiff, soft) = (csv_rows(&stiff), csv_rows(&soft));
    assert_eq!(stiff[0], ["time", "Oscillator.x", "Oscillator.v"]);
    assert_eq!(stiff.len() - 1, 101);
    // A stiffer spring: x(t) = x0 cos(sqrt(k) t) leaves x0 sooner.
    let x_at_half = |rows: &[Vec<String>]| rows[51][1].parse::<f64>().unwrap();
    assert!(x_at_half(&stiff) < x_at_half(&soft), "{stiff:?}");
}

/// The FMI 3.0 Oscillator with its `<CoSimulation>` element removed: an FMU that declares
/// Model Exchange only.
fn model_exchange_only(dir: &Path) -> PathBuf {
    let unpacked = dir.join("unpacked");
    common::unzip_to(&oscillator("3.0"), &unpacked);
    let xml_path = unpacked.join("modelDescription.xml");
    let xml = std::fs::read_to_string(&xml_path).unwrap();
    let start = xml.find("<CoSimulation").unwrap();
    let end = start + xml[start..].find("/>").unwrap() + 2;
    std::fs::write(&xml_path, format!("{}{}", &xml[..start], &xml[end..])).unwrap();
    let path = dir.join("OscillatorME.fmu");
    common::zip_dir(&unpacked, &path);
    path
}

#[test]
fn a_model_exchange_only_fmu_runs_through_model_exchange_unasked() {
    let dir = tempfile::tempdir().unwrap();
    let only = model_exchange_only(dir.path());
    let auto = dir.path().join("auto.csv");
    let named = dir.path().join("named.csv");
    let both = dir.path().join("both.csv");
    let stop = ["--stop-time", "2"];
    run(&joined(
        &["run", only.to_str().unwrap(), "-o", auto.to_str().unwrap()],
        &stop,
    ));
    // The same FMU with both interfaces, Model Exchange asked for on the command line: the
    // same run to the bit.
    let fmu = oscillator("3.0");
    run(&joined(
        &[
            "run",
            fmu.to_str().unwrap(),
            "--interface",
            "model-exchange",
            "-o",
            named.to_str().unwrap(),
        ],
        &stop,
    ));
    let rename = |rows: Vec<Vec<String>>| -> Vec<Vec<String>> {
        rows.into_iter()
            .map(|r| {
                r.into_iter()
                    .map(|c| c.replace("OscillatorME.", "Oscillator."))
                    .collect()
            })
            .collect()
    };
    assert_eq!(rename(csv_rows(&auto)), csv_rows(&named));
    // Unasked, an FMU with both runs through Co-Simulation, which differs in the last bits.
    run(&joined(
        &["run", fmu.to_str().unwrap(), "-o", both.to_str().unwrap()],
        &stop,
    ));
    assert_ne!(csv_rows(&both), csv_rows(&named));
    // Co-Simulation named for the Model Exchange-only FMU is refused, saying why.
    let refused = harness(&[
        "run",
        only.to_str().unwrap(),
        "--interface",
        "co-simulation",
        "-o",
        dir.path().join("cs.csv").to_str().unwrap(),
    ]);
    assert_eq!(refused.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert!(stderr.contains("CoSimulation"), "{stderr}");
}

#[test]
fn bad_interfaces_are_refused_together_before_the_run() {
    let dir = tempfile::tempdir().unwrap();
    let output = harness(&[
        "run",
        "landing",
        "--interface",
        "plant=model_exchange",
        "--interface",
        "plnt=model-exchange",
        "-o",
        dir.path().join("x.csv").to_str().unwrap(),
    ]);
    assert_eq!(output.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("'model_exchange' is neither co-simulation nor model-exchange"),
        "{stderr}"
    );
    assert!(
        stderr.contains("no instance 'plnt' (did you mean 'plant'?)"),
        "{stderr}"
    );
    assert!(!dir.path().join("x.csv").exists());
}

#[test]
fn the_plant_of_a_scenario_runs_through_model_exchange_when_asked_on_the_command_line() {
    let dir = tempfile::tempdir().unwrap();
    let cli = dir.path().join("cli.csv");
    let scenario = dir.path().join("scenario.csv");
    let options = ["--stop-time", "3", "--record", "plant.r_nue,plant.v_nue"];
    // Cut short before the touchdown, the landing's verdict fails (exit 3) either way.
    let exits: Vec<Option<i32>> = [
        joined(
            &[
                "run",
                "landing",
                "--interface",
                "plant=model-exchange",
                "-o",
                cli.to_str().unwrap(),
            ],
            &options,
        ),
        joined(
            &[
                "run",
                "landing-model-exchange",
                "-o",
                scenario.to_str().unwrap(),
            ],
            &options,
        ),
    ]
    .iter()
    .map(|args| harness(args).status.code())
    .collect();
    assert_eq!(exits, [Some(3), Some(3)]);
    // The scenario names the default solver and tolerances: the same run to the bit.
    assert_eq!(csv_rows(&cli), csv_rows(&scenario));
    // Through Co-Simulation the plant integrates with its own fixed step: other bits.
    let cs = dir.path().join("cs.csv");
    harness(&joined(
        &["run", "landing", "-o", cs.to_str().unwrap()],
        &options,
    ));
    assert_ne!(csv_rows(&cs), csv_rows(&scenario));
}

/// fmpy's run of `fmu` with `table` as its inputs: (column names, rows).
fn fmpy_with_input(fmu: &Path, table: &Path, out: &Path) -> Vec<Vec<String>> {
    let python = common::workspace_root().join(".venv/bin/python");
    assert!(
        python.is_file(),
        "{} is missing: run `cargo xtask python-env` (or `cargo xtask test`, which does)",
        python.display()
    );
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/python/simulate_with_input.py");
    let output = std::process::Command::new(python)
        .arg(script)
        .arg(fmu)
        .arg(table)
        .arg(out)
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    csv_rows(out)
}

#[test]
fn an_input_table_drives_the_fmu_as_in_fmpy() {
    let dir = tempfile::tempdir().unwrap();
    let fmu = oscillator("2.0");
    // A force ramped up, held, then stepped back to zero at 6 s.
    let table = dir.path().join("in.csv");
    std::fs::write(&table, "time,u\n0,0\n2,3\n6,3\n6,0\n10,0\n").unwrap();
    let ours = dir.path().join("ours.csv");
    run(&[
        "run",
        fmu.to_str().unwrap(),
        "--input",
        table.to_str().unwrap(),
        "-o",
        ours.to_str().unwrap(),
    ]);
    let ours = csv_rows(&ours);
    let theirs = fmpy_with_input(&fmu, &table, &dir.path().join("fmpy.csv"));
    assert_eq!(ours.len(), theirs.len());
    // Same outputs at every point: fmpy sets the interpolated input at each communication
    // point as the harness does.
    let value = |cell: &str| cell.trim_matches('"').parse::<f64>().unwrap();
    let mut worst = 0.0_f64;
    for (a, b) in ours.iter().skip(1).zip(theirs.iter().skip(1)) {
        for k in 0..3 {
            worst = worst.max((value(&a[k]) - value(&b[k])).abs());
        }
    }
    assert!(worst < 1e-12, "largest difference from fmpy: {worst:e}");
    // And the input mattered: without it the oscillator does something else.
    let free = dir.path().join("free.csv");
    run(&["run", fmu.to_str().unwrap(), "-o", free.to_str().unwrap()]);
    assert_ne!(csv_rows(&free)[500], ours[500]);
}

#[test]
fn an_input_table_naming_no_input_is_refused_with_every_problem() {
    let dir = tempfile::tempdir().unwrap();
    let table = dir.path().join("in.csv");
    std::fs::write(&table, "time,u,x,uu\n0,0,0,0\n").unwrap();
    let fmu = oscillator("3.0");
    let output = harness(&[
        "run",
        fmu.to_str().unwrap(),
        "--input",
        table.to_str().unwrap(),
        "-o",
        dir.path().join("x.csv").to_str().unwrap(),
    ]);
    assert_eq!(output.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("'Oscillator.x' has causality Output"),
        "{stderr}"
    );
    assert!(stderr.contains("no variable 'uu'"), "{stderr}");
}
