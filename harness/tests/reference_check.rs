//! `harness run X.fmu --check-reference` and `harness test` on FMUs that carry FMI-LS-REF
//! references: each built here from the packaged Oscillator, its `extra/` files added with
//! the zip crate, its reference the result of a run of the FMU itself.
use crate::common;

use common::harness;
use std::io::{Read, Write};
use std::path::{Path, PathBuf};

const LS: &str = "extra/org.fmi-standard.fmi-ls-ref";

const MANIFEST: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<fmiReferences
    xmlns:fmi-ls="http://fmi-standard.org/fmi-ls-manifest"
    fmi-ls:fmi-ls-name="org.fmi-standard.fmi-ls-ref"
    fmi-ls:fmi-ls-version="1.0.0-alpha.1">
    <Related type="text/csv" source="Osc_out.csv" role="result" description="Output of the default experiment"/>
</fmiReferences>
"#;

/// A force step at 1 s: the run differs from one without it from there on.
const STIMULI: &str = "time,u\n0,0\n1,0\n1,3\n2,3\n";

const EXPERIMENTS: &str = r#"<Experiments>
  <Experiment name="push" startTime="0" stopTime="2" stepSize="0.01">
    <Stimuli source="Osc_in.csv"/>
    <References source="Osc_out.csv"/>
  </Experiment>
</Experiments>
"#;

fn packaged(version: &str) -> PathBuf {
    let dir = common::fmu_dir();
    match version {
        "2.0" => dir.join("Oscillator.fmu"),
        _ => dir.join("fmi3/Oscillator.fmu"),
    }
}

/// `source` copied to `dest` with `files` under the LS-REF folder in place of the ones it
/// carries.
fn with_extra(source: &Path, dest: &Path, files: &[(&str, &str)]) {
    let mut archive = zip::ZipArchive::new(std::fs::File::open(source).unwrap()).unwrap();
    let mut out = zip::ZipWriter::new(std::fs::File::create(dest).unwrap());
    let options = zip::write::SimpleFileOptions::default();
    for i in 0..archive.len() {
        let mut entry = archive.by_index(i).unwrap();
        if entry.name().starts_with(LS) {
            continue;
        }
        let mut bytes = Vec::new();
        entry.read_to_end(&mut bytes).unwrap();
        out.start_file(entry.name(), options).unwrap();
        out.write_all(&bytes).unwrap();
    }
    for (name, text) in files {
        out.start_file(format!("{LS}/{name}"), options).unwrap();
        out.write_all(text.as_bytes()).unwrap();
    }
    out.finish().unwrap();
}

/// A result CSV of `harness run` as a reference: the instance's prefix off its columns.
fn as_reference(result: &Path) -> String {
    let text = std::fs::read_to_string(result).unwrap();
    let (header, rows) = text.split_once('\n').unwrap();
    let header: Vec<&str> = header
        .split(',')
        .map(|c| c.split_once('.').map_or(c, |(_, v)| v))
        .collect();
    format!("{}\n{rows}", header.join(","))
}

/// Runs the harness and returns (exit code, stdout, stderr).
fn run(args: &[&str]) -> (i32, String, String) {
    let output = harness(args);
    (
        output.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&output.stdout).into_owned(),
        String::from_utf8_lossy(&output.stderr).into_owned(),
    )
}

/// The reference of the pushed Oscillator over 2 s, from a run of `fmu` itself.
fn pushed_reference(fmu: &Path, dir: &Path) -> String {
    let input = dir.join("in.csv");
    std::fs::write(&input, STIMULI).unwrap();
    let out = dir.join("own.csv");
    let (code, _, stderr) = run(&[
        "run",
        fmu.to_str().unwrap(),
        "--input",
        input.to_str().unwrap(),
        "--stop-time",
        "2",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    as_reference(&out)
}

/// `text` with the values of `column` from time `from` to `to` moved by `by`: longer than
/// the tube reaches in time, which a single sample is not.
fn perturbed(text: &str, column: &str, (from, to): (f64, f64), by: f64) -> String {
    let mut lines = text.lines();
    let header = lines.next().unwrap();
    let j = header.split(',').position(|c| c == column).unwrap();
    let mut out = format!("{header}\n");
    for line in lines {
        let mut fields: Vec<String> = line.split(',').map(str::to_owned).collect();
        let t: f64 = fields[0].parse().unwrap();
        if t >= from && t <= to {
            fields[j] = (fields[j].parse::<f64>().unwrap() + by).to_string();
        }
        out.push_str(&fields.join(","));
        out.push('\n');
    }
    out
}

#[test]
fn an_fmu_whose_reference_matches_passes_with_its_stimuli_applied() {
    for version in ["2.0", "3.0"] {
        let dir = tempfile::tempdir().unwrap();
        let reference = pushed_reference(&packaged(version), dir.path());
        let fmu = dir.path().join("Osc.fmu");
        with_extra(
            &packaged(version),
            &fmu,
            &[
                ("experiments.xml", EXPERIMENTS),
                ("Osc_in.csv", STIMULI),
                ("Osc_out.csv", &reference),
            ],
        );
        let junit = dir.path().join("junit.xml");
        let out = dir.path().join("run.csv");
        let (code, stdout, stderr) = run(&[
            "run",
            fmu.to_str().unwrap(),
            "--check-reference",
            "-o",
            out.to_str().unwrap(),
            "--junit",
            junit.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "FMI {version}: {stdout}{stderr}");
        assert!(
            stdout.contains("reference push: pass (3 signals, 0 failed)"),
            "{stdout}"
        );
        assert!(
            stdout.contains("  x: pass: largest deviation 0.000e0"),
            "{stdout}"
        );
        // The experiment's stop time, not the DefaultExperiment's 10 s.
        assert!(stdout.contains("201 rows"), "{stdout}");
        let report = std::fs::read_to_string(&junit).unwrap();
        assert!(report.contains("tests=\"4\" failures=\"0\""), "{report}");
        assert!(report.contains("name=\"reference push: x\""), "{report}");

        // Without the stimuli the run no longer matches: they are applied.
        let unpushed = dir.path().join("Unpushed.fmu");
        with_extra(
            &packaged(version),
            &unpushed,
            &[
                (
                    "experiments.xml",
                    &EXPERIMENTS
                        .replace("Osc_in.csv", "Osc_out.csv")
                        .replace("<Stimuli source=\"Osc_out.csv\"/>\n", ""),
                ),
                ("Osc_out.csv", &reference),
            ],
        );
        let (code, stdout, _) = run(&[
            "run",
            unpushed.to_str().unwrap(),
            "--check-reference",
            "-o",
            out.to_str().unwrap(),
        ]);
        assert_eq!(code, 3, "FMI {version}: {stdout}");
        assert!(stdout.contains("x: FAIL"), "{stdout}");
    }
}

#[test]
fn a_perturbed_reference_fails_naming_the_signal_and_the_time() {
    let dir = tempfile::tempdir().unwrap();
    let own = dir.path().join("own.csv");
    let (code, _, stderr) = run(&[
        "run",
        packaged("2.0").to_str().unwrap(),
        "-o",
        own.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    let reference = perturbed(&as_reference(&own), "v", (4.0, 5.0), 0.5);
    let fmu = dir.path().join("Osc.fmu");
    with_extra(
        &packaged("2.0"),
        &fmu,
        &[
            ("fmi-ls-manifest.xml", MANIFEST),
            ("Osc_out.csv", &reference),
        ],
    );
    let junit = dir.path().join("junit.xml");
    let (code, stdout, _) = run(&[
        "run",
        fmu.to_str().unwrap(),
        "--check-reference",
        "-o",
        dir.path().join("run.csv").to_str().unwrap(),
        "--junit",
        junit.to_str().unwrap(),
    ]);
    assert_eq!(code, 3, "{stdout}");
    assert!(
        stdout.contains("reference DefaultExperiment: FAIL (3 signals, 1 failed)"),
        "{stdout}"
    );
    assert!(stdout.contains("  x: pass"), "{stdout}");
    let line = stdout.lines().find(|l| l.contains("v: FAIL")).unwrap();
    assert!(line.contains("of 1001 samples outside the tube"), "{line}");
    let worst: f64 = line
        .split("the worst at t = ")
        .nth(1)
        .and_then(|rest| rest.split(" s").next())
        .and_then(|t| t.parse().ok())
        .unwrap_or_else(|| panic!("no time in {line}"));
    assert!((4.0..=5.0).contains(&worst), "{line}");
    let report = std::fs::read_to_string(&junit).unwrap();
    assert!(report.contains("failures=\"1\""), "{report}");
    assert!(report.contains("<failure message=\"v: FAIL: "), "{report}");

    // A wider tube from the command line takes the perturbation in.
    let (code, stdout, _) = run(&[
        "run",
        fmu.to_str().unwrap(),
        "--check-reference",
        "--reference-rel-tol",
        "0.5",
        "-o",
        dir.path().join("run.csv").to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stdout}");
}

#[test]
fn a_manifest_naming_a_missing_csv_is_refused_clearly() {
    let dir = tempfile::tempdir().unwrap();
    let fmu = dir.path().join("Osc.fmu");
    with_extra(&packaged("3.0"), &fmu, &[("fmi-ls-manifest.xml", MANIFEST)]);
    let (code, stdout, stderr) = run(&[
        "run",
        fmu.to_str().unwrap(),
        "--check-reference",
        "--reference-time-tol",
        "2",
    ]);
    assert_eq!(code, 1, "{stdout}{stderr}");
    // The command line's problem and the FMU's, at once.
    assert!(
        stderr.contains("--reference-time-tol: 2 is not a number from 0 to 1"),
        "{stderr}"
    );
    assert!(
        stderr.contains(&format!(
            "{LS}/fmi-ls-manifest.xml: <Related source=\"Osc_out.csv\"> (line 6): no such file \
             in the FMU (looked for {LS}/Osc_out.csv and Osc_out.csv)"
        )),
        "{stderr}"
    );
    assert!(
        stderr.contains("Osc.fmu: its FMI-LS-REF references cannot be used"),
        "{stderr}"
    );
    assert!(
        !stderr.contains("panicked") && !stderr.contains("backtrace"),
        "{stderr}"
    );
    // Nothing was flown.
    assert!(!stdout.contains("rows"), "{stdout}");

    // An FMU without references cannot be checked against them either.
    let plain = dir.path().join("Plain.fmu");
    with_extra(&packaged("2.0"), &plain, &[]);
    let (code, _, stderr) = run(&["run", plain.to_str().unwrap(), "--check-reference"]);
    assert_eq!(code, 1);
    assert!(
        stderr.contains("carries no FMI-LS-REF references"),
        "{stderr}"
    );
}

#[test]
fn a_test_folder_checks_the_fmus_that_carry_references() {
    let dir = tempfile::tempdir().unwrap();
    let own = dir.path().join("own.csv");
    let (code, _, stderr) = run(&[
        "run",
        packaged("2.0").to_str().unwrap(),
        "-o",
        own.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    let reference = as_reference(&own);
    let folder = dir.path().join("folder");
    std::fs::create_dir(&folder).unwrap();
    with_extra(
        &packaged("2.0"),
        &folder.join("Osc.fmu"),
        &[
            ("fmi-ls-manifest.xml", MANIFEST),
            ("Osc_out.csv", &reference),
        ],
    );
    with_extra(
        &packaged("2.0"),
        &folder.join("Strayed.fmu"),
        &[
            ("fmi-ls-manifest.xml", MANIFEST),
            ("Osc_out.csv", &perturbed(&reference, "x", (2.0, 3.0), -1.0)),
        ],
    );
    // Without references: flown, no reference case.
    with_extra(&packaged("2.0"), &folder.join("Plain.fmu"), &[]);
    let out_dir = dir.path().join("out");
    let junit = dir.path().join("junit.xml");
    let (code, stdout, _) = run(&[
        "test",
        folder.to_str().unwrap(),
        "--junit",
        junit.to_str().unwrap(),
        "--out-dir",
        out_dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 3, "{stdout}");
    assert!(
        stdout.contains("3 scenarios: 2 passed, 1 failed"),
        "{stdout}"
    );
    let report = std::fs::read_to_string(&junit).unwrap();
    // Osc: verdict + 3 signals; Plain: verdict; Strayed: verdict + 3 signals, x failed.
    assert!(
        report.contains("tests=\"9\" failures=\"1\" errors=\"0\""),
        "{report}"
    );
    let verdicts = std::fs::read_to_string(out_dir.join("verdicts.toml")).unwrap();
    assert!(
        verdicts.contains("reference DefaultExperiment: x"),
        "{verdicts}"
    );
    assert!(verdicts.contains("x: FAIL"), "{verdicts}");
}

/// Every FMU `cargo xtask fmus` packages, in both FMI versions, carries references written
/// from its own runs, and the harness finds its runs inside them: a test folder of the
/// shipped FMUs passes, a test case per reference signal.
#[test]
fn every_packaged_fmu_carries_references_its_runs_match() {
    let fmus = fmu_metadata::workspace_fmus(&common::workspace_root()).unwrap();
    for (version, fmi, dir) in [
        ("2.0", fmu_metadata::Fmi::V2, common::fmu_dir()),
        ("3.0", fmu_metadata::Fmi::V3, common::fmu_dir().join("fmi3")),
    ] {
        let scratch = tempfile::tempdir().unwrap();
        let folder = scratch.path().join("fmus");
        std::fs::create_dir(&folder).unwrap();
        let shipped: Vec<&str> = fmus
            .iter()
            .filter(|f| f.ships(fmi))
            .map(|f| f.model_identifier.as_str())
            .collect();
        assert!(shipped.len() >= 6, "FMI {version}: {shipped:?}");
        for id in &shipped {
            let fmu = dir.join(format!("{id}.fmu"));
            let mut archive = zip::ZipArchive::new(std::fs::File::open(&fmu).unwrap()).unwrap();
            for file in [
                "fmi-ls-manifest.xml",
                "experiments.xml",
                &format!("{id}_out.csv"),
            ] {
                assert!(
                    archive.by_name(&format!("{LS}/{file}")).is_ok(),
                    "FMI {version}: {} lacks {LS}/{file}: run `cargo xtask fmus`",
                    fmu.display()
                );
            }
            // The experiment is the FMU's DefaultExperiment.
            let references = cosim::reference::read(&fmu).unwrap().unwrap();
            let (_, description) = fmi_import::read_description(&fmu).unwrap();
            let default = description.default_experiment.unwrap();
            let experiment = &references.experiments[0];
            assert_eq!(
                (
                    experiment.start_time,
                    experiment.stop_time,
                    experiment.step_size
                ),
                (default.start_time, default.stop_time, default.step_size),
                "FMI {version}: {id}"
            );
            std::fs::copy(&fmu, folder.join(format!("{id}.fmu"))).unwrap();
        }
        let junit = scratch.path().join("junit.xml");
        let (code, stdout, stderr) = run(&[
            "test",
            folder.to_str().unwrap(),
            "--junit",
            junit.to_str().unwrap(),
            "--out-dir",
            scratch.path().join("out").to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "FMI {version}: {stdout}{stderr}");
        let passes = stdout
            .lines()
            .filter(|l| l.starts_with("reference DefaultExperiment: pass"))
            .count();
        assert_eq!(passes, shipped.len(), "FMI {version}: {stdout}");
        let report = std::fs::read_to_string(&junit).unwrap();
        assert!(report.contains("failures=\"0\" errors=\"0\""), "{report}");
        for id in &shipped {
            assert!(
                report.contains(&format!(
                    "classname=\"{id}\" name=\"reference DefaultExperiment:"
                )),
                "FMI {version}: no reference case of {id}"
            );
        }
    }
}

#[test]
fn each_experiment_of_an_fmu_is_flown_into_a_results_file_of_its_own() {
    let dir = tempfile::tempdir().unwrap();
    let pushed = pushed_reference(&packaged("2.0"), dir.path());
    let own = dir.path().join("rest.csv");
    let (code, _, stderr) = run(&[
        "run",
        packaged("2.0").to_str().unwrap(),
        "--stop-time",
        "1",
        "-o",
        own.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    let experiments = r#"<Experiments>
  <Experiment name="push" startTime="0" stopTime="2" stepSize="0.01">
    <Stimuli source="Osc_in.csv"/>
    <References source="Osc_out.csv"/>
  </Experiment>
  <Experiment name="at rest" stopTime="1">
    <References source="rest_out.csv"/>
  </Experiment>
</Experiments>
"#;
    let fmu = dir.path().join("Osc.fmu");
    with_extra(
        &packaged("2.0"),
        &fmu,
        &[
            ("experiments.xml", experiments),
            ("Osc_in.csv", STIMULI),
            ("Osc_out.csv", &pushed),
            ("rest_out.csv", &as_reference(&own)),
        ],
    );
    let out = dir.path().join("run.csv");
    let junit = dir.path().join("junit.xml");
    let (code, stdout, stderr) = run(&[
        "run",
        fmu.to_str().unwrap(),
        "--check-reference",
        "-o",
        out.to_str().unwrap(),
        "--junit",
        junit.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stdout}{stderr}");
    assert!(stdout.contains("reference push: pass"), "{stdout}");
    assert!(stdout.contains("reference at rest: pass"), "{stdout}");
    // The second experiment's stop time and no stimuli; its step the DefaultExperiment's.
    assert!(dir.path().join("run-push.csv").is_file());
    let rest = std::fs::read_to_string(dir.path().join("run-at_rest.csv")).unwrap();
    assert_eq!(rest.lines().count(), 102, "{}", &rest[..200]);
    let report = std::fs::read_to_string(&junit).unwrap();
    assert!(report.contains("tests=\"8\" failures=\"0\""), "{report}");
    assert!(report.contains("name=\"verdict (at rest)\""), "{report}");
}
