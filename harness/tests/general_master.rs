//! The harness as a master for any system, not only the shipped one: SSP packages and SSDs from
//! anywhere, SSD connectors and parameter types checked before the run, algebraic loops and
//! values set on connected inputs refused, each problem named with a suggestion.
mod common;

use cosim::master::{MasterError, Simulation, Trajectory};
use cosim::system::{Connection, InstanceDesc, ParamValue, SystemDescription};
use harness::scenarios;
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
fn missing_fmus_are_all_named_with_where_they_were_looked_for() {
    let empty = tempfile::tempdir().unwrap();
    let error = match Simulation::new(scenarios::load("paper").unwrap(), empty.path()) {
        Err(error) => error.to_string(),
        Ok(_) => panic!("ran without FMUs"),
    };
    for expected in [
        "instance 'gnc'",
        "instance 'plant'",
        "LanderGnc.fmu",
        "--fmu-dir",
        "LANDER_FMU_DIR",
    ] {
        assert!(error.contains(expected), "{expected}: {error}");
    }
}

#[test]
fn a_gnc_wired_to_itself_is_an_algebraic_loop_named_in_the_error() {
    // GIVEN one GNC whose thrust command feeds its own mass input (every GNC output depends
    // on every input in its ModelStructure)
    let mut system = scenarios::load("paper").unwrap();
    system.instances.retain(|i| i.name == "gnc");
    system.connections = vec![Connection {
        from: "gnc.thrust_cmd".into(),
        to: "gnc.mass".into(),
    }];
    // WHEN it is resolved THEN it is refused, naming the cycle
    let error = refused(system);
    assert!(
        error.contains("algebraic loop: gnc.thrust_cmd -> gnc.mass ~> gnc.thrust_cmd"),
        "{error}"
    );
}

#[test]
fn a_declared_feedthrough_loop_is_accepted_under_jacobi_ordering_where_every_link_is_delayed() {
    // GIVEN the loop through the plant's delivered thrust that Gauss-Seidel refuses
    let mut system = scenarios::load("paper").unwrap();
    for c in &mut system.connections {
        if c.to == "gnc.mass" {
            c.from = "plant.thrust_actual".into();
        }
    }
    let mut gauss_seidel = system.clone();
    gauss_seidel.ordering = cosim::system::Ordering::GaussSeidel;
    assert!(refused(gauss_seidel).contains("algebraic loop"));
    // WHEN it is resolved for Jacobi ordering THEN it is accepted and flies its first second
    system.ordering = cosim::system::Ordering::Jacobi;
    system.stop_time = 1.0;
    let mut simulation = Simulation::new(system, &common::fmu_dir()).unwrap();
    let mut trajectory = cosim::master::Trajectory::default();
    simulation.run(&mut trajectory).unwrap();
    assert_eq!(trajectory.len(), 101);
}

#[test]
fn a_loop_through_the_plants_feedthrough_output_is_refused_and_the_paper_loop_is_not() {
    // GIVEN the paper loop with the GNC's mass taken from the plant's delivered thrust, an
    // output that depends on the thrust command
    let mut system = scenarios::load("paper").unwrap();
    for c in &mut system.connections {
        if c.to == "gnc.mass" {
            c.from = "plant.thrust_actual".into();
        }
    }
    let error = refused(system);
    assert!(error.contains("algebraic loop"), "{error}");
    assert!(
        error.contains("plant.thrust_actual -> gnc.mass")
            && error.contains("gnc.thrust_cmd -> plant.thrust_cmd"),
        "{error}"
    );
    // The paper loop itself runs: the plant's navigation outputs depend on no input.
    Simulation::new(scenarios::load("paper").unwrap(), &common::fmu_dir())
        .unwrap_or_else(|e| panic!("{e}"));
}

#[test]
fn a_value_set_on_a_connected_input_is_refused() {
    // GIVEN the paper loop, where gnc.mass comes from plant.mass
    let mut simulation =
        Simulation::new(scenarios::load("paper").unwrap(), &common::fmu_dir()).unwrap();
    // WHEN a value is set on it THEN it is refused, naming the connection
    let error = simulation
        .set_parameter("gnc", "mass", ParamValue::Real(900.0))
        .unwrap_err()
        .to_string();
    assert!(error.contains("connected from 'plant.mass'"), "{error}");
    // and so is the same value in the scenario, before anything runs
    let mut system = scenarios::load("paper").unwrap();
    system.set_parameter("gnc", "mass", ParamValue::Real(900.0));
    assert!(refused(system).contains("connected from 'plant.mass'"));
    // while an unconnected parameter is accepted
    simulation
        .set_parameter("gnc", "phi_cmd", ParamValue::Real(0.5))
        .unwrap();
}

#[test]
fn parameter_types_and_names_are_checked_before_the_run_all_at_once() {
    let mut system = scenarios::load("paper").unwrap();
    system.set_parameter("gnc", "control_law", ParamValue::Real(1.5));
    system.set_parameter("gnc", "phi_cmd", ParamValue::Boolean(true));
    system.set_parameter("plant", "m0", ParamValue::String("heavy".into()));
    system.set_parameter("gnc", "control_bandwith", ParamValue::Real(0.5));
    let error = refused(system);
    assert!(
        error.contains("'control_law'") && error.contains("the Real 1.5"),
        "{error}"
    );
    assert!(
        error.contains("'phi_cmd' is Real") && error.contains("the Boolean true"),
        "{error}"
    );
    assert!(
        error.contains("'m0'") && error.contains("\"heavy\""),
        "{error}"
    );
    assert!(
        error.contains("(did you mean 'control_bandwidth'?)"),
        "{error}"
    );
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
fn an_unknown_instance_in_a_connection_gets_a_suggestion() {
    let mut system = scenarios::load("paper").unwrap();
    system.instances.push(InstanceDesc {
        name: "plant2".into(),
        fmu: "LanderPlant.fmu".into(),
        parameters: vec![],
        connectors: None,
        model_exchange: None,
    });
    system.connections.push(Connection {
        from: "plant2.mass".into(),
        to: "gcn.mass".into(),
    });
    // validate() already refuses the unknown instance; the master says the same with a hint.
    let error = refused(system);
    assert!(error.contains("did you mean 'gnc'"), "{error}");
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
