//! The harness as a master for any system, not only the shipped one: SSP packages and SSDs
//! from anywhere, SSD connectors checked before the run, and every bad `--set` of the command
//! line reported at once. The master's own refusals are tested in cosim/tests.
use crate::common;

use cosim::master::{MasterError, Simulation, Trajectory};
use cosim::system::SystemDescription;
use lander::scenarios;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

fn paper_ssd() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/paper.ssd")
}

/// `dir/SystemStructure.ssd` with `ssd` as text and both FMUs under `dir/resources/`.
fn unpacked_package(dir: &Path, ssd: &str) {
    fs::create_dir_all(dir.join("resources")).unwrap();
    fs::write(dir.join("SystemStructure.ssd"), ssd).unwrap();
    for fmu in ["LanderGnc.fmu", "LanderPlant.fmu"] {
        fs::copy(common::fmu_dir().join(fmu), dir.join("resources").join(fmu)).unwrap();
    }
}

fn fly(mut system: SystemDescription, fmu_dir: &Path) -> Trajectory {
    system.stop_time = 2.0;
    let mut simulation = Simulation::new(system, fmu_dir).unwrap_or_else(|e| panic!("{e}"));
    let mut trajectory = Trajectory {
        names: simulation.column_names().to_vec(),
        ..Default::default()
    };
    simulation.run(&mut trajectory).unwrap();
    trajectory
}

fn bits(t: &Trajectory) -> Vec<u64> {
    t.values.iter().map(|v| v.to_bits()).collect()
}

/// The problems `Simulation::new` reports, as one text.
fn refused(system: SystemDescription) -> String {
    match Simulation::new(system, &common::fmu_dir()) {
        Err(error @ MasterError::Resolve { .. }) => error.to_string(),
        Err(other) => panic!("wrong error: {other}"),
        Ok(_) => panic!("a broken system was accepted"),
    }
}

#[test]
fn an_ssp_package_flies_the_same_trajectory_as_the_toml() {
    // GIVEN the shipped SSD and both FMUs zipped as an SSP package
    let temp = tempfile::tempdir().unwrap();
    let unpacked = temp.path().join("unpacked");
    unpacked_package(&unpacked, &fs::read_to_string(paper_ssd()).unwrap());
    let package = temp.path().join("Lander.ssp");
    common::zip_dir(&unpacked, &package);
    fs::remove_dir_all(&unpacked).unwrap();
    // WHEN it is loaded with an FMU directory that holds nothing
    let system = scenarios::load(package.to_str().unwrap()).unwrap_or_else(|e| panic!("{e:#}"));
    let empty = tempfile::tempdir().unwrap();
    let from_package = fly(system, empty.path());
    // THEN it flies the FMUs inside it, bit for bit as the TOML scenario
    let from_toml = fly(scenarios::load("paper").unwrap(), &common::fmu_dir());
    assert_eq!(from_package.names, from_toml.names);
    assert!(!from_toml.is_empty());
    assert!(
        bits(&from_package) == bits(&from_toml),
        "trajectories differ"
    );
}

#[test]
fn a_file_that_is_not_an_ssp_package_is_refused_by_name() {
    let temp = tempfile::tempdir().unwrap();
    let path = temp.path().join("broken.ssp");
    fs::write(&path, "<not a zip/>").unwrap();
    let error = scenarios::load(path.to_str().unwrap())
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("broken.ssp") && error.contains("zip"),
        "{error}"
    );
}

#[test]
fn the_cli_runs_an_ssp_and_a_relative_ssd_from_another_directory() {
    // GIVEN an unpacked package below a working directory and an FMU directory with nothing
    let work = tempfile::tempdir().unwrap();
    unpacked_package(
        &work.path().join("pkg"),
        &fs::read_to_string(paper_ssd()).unwrap(),
    );
    common::zip_dir(&work.path().join("pkg"), &work.path().join("pkg.ssp"));
    let empty = tempfile::tempdir().unwrap();
    for scenario in ["pkg/SystemStructure.ssd", "pkg.ssp"] {
        // WHEN the harness runs it by a path relative to that directory
        let output = Command::new(env!("CARGO_BIN_EXE_harness"))
            .current_dir(work.path())
            .env_remove("LANDER_FMU_DIR")
            .args(["--fmu-dir"])
            .arg(empty.path())
            .args(["run", scenario, "--record", "plant.r_nue", "-o", "out.csv"])
            .output()
            .unwrap();
        // THEN it finds the FMUs beside the SSD and flies to the end
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(output.status.success(), "{scenario}: {stderr}");
        let stdout = String::from_utf8_lossy(&output.stdout);
        assert!(
            stdout.contains("verdict: completed at t = 172.00 s"),
            "{scenario}: {stdout}"
        );
    }
}

#[test]
fn connections_are_checked_against_the_ssds_declared_connectors() {
    let text = fs::read_to_string(paper_ssd()).unwrap();
    let temp = tempfile::tempdir().unwrap();
    let load = |text: String| {
        let path = temp.path().join("edited.ssd");
        fs::write(&path, text).unwrap();
        scenarios::load(path.to_str().unwrap()).unwrap()
    };
    // A connection end that no connector declares, with the likely one suggested.
    let misspelt = text.replacen(
        r#"startConnector="mass" endElement="gnc" endConnector="mass""#,
        r#"startConnector="mass" endElement="gnc" endConnector="mas""#,
        1,
    );
    assert_ne!(misspelt, text);
    let error = refused(load(misspelt));
    assert!(
        error.contains("'mas' is not a declared connector of component 'gnc'")
            && error.contains("did you mean 'mass'"),
        "{error}"
    );
    // A connector declared with the wrong type and one the FMU does not have.
    let wrong = text
        .replacen(
            r#"<ssd:Connector name="mass" kind="input"><ssc:Real/>"#,
            r#"<ssd:Connector name="mass" kind="input"><ssc:Integer/>"#,
            1,
        )
        .replacen(
            r#"<ssd:Connector name="thrust_cmd" kind="output">"#,
            r#"<ssd:Connector name="thrust_cmd" kind="output"/><ssd:Connector name="thrust_cnd" kind="output">"#,
            1,
        );
    let error = refused(load(wrong));
    assert!(
        error.contains("connector 'mass' is declared Integer but the FMU's variable is Real"),
        "{error}"
    );
    assert!(
        error.contains("'thrust_cnd' is not a variable of model 'LanderGnc'")
            && error.contains("did you mean 'thrust_cmd'"),
        "{error}"
    );
}

#[test]
fn the_cli_reports_every_bad_set_at_once_and_an_fmu_error_once() {
    let harness = |args: &[&str]| {
        let output = Command::new(env!("CARGO_BIN_EXE_harness"))
            .env("LANDER_FMU_DIR", common::fmu_dir())
            .env_remove("RUST_LOG")
            .args(args)
            .output()
            .unwrap();
        assert!(!output.status.success(), "{args:?} succeeded");
        // Refusals before the run go to stderr, a run's error verdict to stdout: read both.
        String::from_utf8_lossy(&output.stderr).into_owned()
            + &String::from_utf8_lossy(&output.stdout)
    };
    let out = tempfile::tempdir().unwrap();
    let csv = out.path().join("run.csv");
    let csv = csv.to_str().unwrap();
    let stderr = harness(&[
        "run",
        "paper",
        "-o",
        csv,
        "--set",
        "gcn.phi_cmd=1",
        "--set",
        "gnc.phi_cmdd=1",
        "--set",
        "gnc.mass=900",
    ]);
    assert!(stderr.contains("did you mean 'gnc'"), "{stderr}");
    assert!(stderr.contains("did you mean 'phi_cmd'"), "{stderr}");
    assert!(stderr.contains("connected from 'plant.mass'"), "{stderr}");
    // A value outside its declared range: refused before the run, naming both.
    let stderr = harness(&[
        "run",
        "paper",
        "-o",
        csv,
        "--set",
        "gnc.control_bandwidth=0",
    ]);
    let line = "'control_bandwidth' = 0 is below its declared min 5e-324";
    assert_eq!(stderr.matches(line).count(), 1, "{stderr}");
    // An FMU refusing parameters that are each within range but not together: its log line
    // appears once, in the error.
    let stderr = harness(&["run", "paper", "-o", csv, "--set", "gnc.thrust_min=2000"]);
    let line = "parameter thrust_max = 1600: must be >= thrust_min";
    assert_eq!(stderr.matches(line).count(), 1, "{stderr}");
}
