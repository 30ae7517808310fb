//! Support of the interoperability tests (tests/interop/tests/*.rs): run a system in the Rust
//! harness in-process, hand the same system to a Python master (tests/interop/python) through
//! the workspace venv, and compare the two trajectories at every communication point.
//!
//! The FMUs are those `cargo xtask fmus` packaged (the system-tests crate resolves where);
//! these helpers panic with a message saying what to run: they serve tests only.
#![deny(unsafe_code)]

pub mod compare;
pub mod python;

use cosim::master::{Conventions, Simulation, Trajectory};
use cosim::system::{ParamValue, SystemDescription};
use std::path::{Path, PathBuf};

pub use system_tests::{fmu_dir, fmu_path, workspace_root};

/// The paper scenario with LanderNav between the plant and the GNC
/// (harness/scenarios/paper-nav.toml), with every kind of navigation error switched on in
/// every signal group (white noise, bias, random walk, quantisation, latency), seeded: the
/// estimates the GNC flies on differ from the truth at every step, so two masters agree on
/// them only if they drive LanderNav's draws and history identically.
pub fn paper_with_navigation_errors(seed: i64) -> SystemDescription {
    let mut system = scenario(
        workspace_root()
            .join("harness/scenarios/paper-nav.toml")
            .to_str()
            .expect("a UTF-8 workspace path"),
    );
    let nav = system
        .instances
        .iter_mut()
        .find(|i| i.name == "nav")
        .expect("paper-nav.toml has a nav instance");
    let real = |name: &str, x: f64| (name.to_string(), ParamValue::Real(x));
    let integer = |name: &str, i: i64| (name.to_string(), ParamValue::Integer(i));
    nav.parameters = vec![
        integer("seed", seed),
        integer("max_latency_steps", 3),
        real("r_nue_noise_sigma", 0.3),
        real("r_nue_bias[2]", 0.5),
        real("r_nue_random_walk", 0.02),
        real("r_nue_quantum", 0.01),
        integer("r_nue_latency", 1),
        real("v_nue_noise_sigma", 0.03),
        real("v_nue_bias[1]", -0.02),
        real("v_nue_random_walk", 0.002),
        real("v_nue_quantum", 0.001),
        integer("v_nue_latency", 2),
        real("attitude_noise_sigma", 5e-4),
        real("attitude_bias[3]", 1e-3),
        real("attitude_random_walk", 1e-4),
        integer("attitude_latency", 1),
        real("omega_body_noise_sigma", 2e-4),
        real("omega_body_random_walk", 1e-5),
        real("omega_body_quantum", 1e-5),
        real("mass_noise_sigma", 0.5),
        real("mass_bias", 3.0),
        integer("mass_latency", 3),
    ];
    system
}

/// The SSP package `cargo xtask fmus` writes beside the FMUs.
pub fn ssp_path() -> PathBuf {
    let path = fmu_dir().join("LanderDescent.ssp");
    assert!(
        path.is_file(),
        "{} is missing: run `cargo xtask fmus` first (or `cargo xtask test`, which does)",
        path.display()
    );
    path
}

/// A built-in scenario of the harness, or a scenario file (`.toml`, `.ssd`).
pub fn scenario(name_or_path: &str) -> SystemDescription {
    lander::scenarios::load(name_or_path).unwrap_or_else(|e| panic!("scenario {name_or_path}: {e}"))
}

/// Flies `system` in the harness with `conventions`; FMU paths relative to the packaged FMUs.
pub fn run_harness(system: SystemDescription, conventions: Conventions) -> Trajectory {
    let mut simulation = Simulation::new(system, &fmu_dir())
        .unwrap_or_else(|e| panic!("harness cannot load the system: {e}"));
    simulation.set_conventions(conventions);
    let mut trajectory = Trajectory {
        names: simulation.column_names().to_vec(),
        ..Default::default()
    };
    let end = simulation
        .run(&mut trajectory)
        .unwrap_or_else(|e| panic!("harness run failed: {e:#}"));
    println!(
        "harness: {} rows of {} columns, ended {end:?}",
        trajectory.len(),
        trajectory.names.len()
    );
    trajectory
}

/// The system as JSON for the Python masters: instances in exchange order with their FMU's
/// absolute path and their parameters, and the scalar connections the harness resolved.
pub fn system_json(system: &SystemDescription) -> serde_json::Value {
    let simulation = Simulation::new(system.clone(), &fmu_dir())
        .unwrap_or_else(|e| panic!("harness cannot load the system: {e}"));
    let instances: Vec<_> = system
        .instances
        .iter()
        .map(|instance| {
            let parameters: Vec<_> = instance
                .parameters
                .iter()
                .map(|(name, value)| {
                    let value = match value {
                        ParamValue::Real(x) => serde_json::json!(x),
                        ParamValue::Integer(i) => serde_json::json!(i),
                        ParamValue::Boolean(b) => serde_json::json!(b),
                        ParamValue::String(s) => serde_json::json!(s),
                    };
                    serde_json::json!([name, value])
                })
                .collect();
            serde_json::json!({
                "name": instance.name,
                "fmu": cosim::master::fmu_path(&fmu_dir(), &instance.fmu),
                "parameters": parameters,
            })
        })
        .collect();
    serde_json::json!({
        "start_time": system.start_time,
        "stop_time": system.stop_time,
        "step_size": system.step_size,
        "instances": instances,
        "connections": simulation.scalar_connections(),
    })
}

/// Writes [`system_json`] to `dir/system.json` and returns the path.
pub fn write_system_json(system: &SystemDescription, dir: &Path) -> PathBuf {
    write_json(&system_json(system), dir)
}

/// Writes a system's JSON to `dir/system.json` and returns the path.
pub fn write_json(json: &serde_json::Value, dir: &Path) -> PathBuf {
    let path = dir.join("system.json");
    let text = serde_json::to_string_pretty(json).expect("JSON of a system");
    std::fs::write(&path, text).unwrap_or_else(|e| panic!("cannot write {}: {e}", path.display()));
    path
}

/// Reads a CSV a Python master wrote (the harness's format).
pub fn read_trajectory(path: &Path) -> Trajectory {
    cosim::results::read_csv(path).unwrap_or_else(|e| panic!("{}: {e:#}", path.display()))
}

/// A scratch folder removed on drop.
pub fn scratch(prefix: &str) -> tempfile::TempDir {
    tempfile::Builder::new()
        .prefix(prefix)
        .tempdir()
        .expect("cannot create a temporary folder")
}

/// `LanderDescent.ssp` unzipped into a scratch folder, and the system its
/// `SystemStructure.ssd` describes, with the component FMUs from its `resources/`.
pub fn unpacked_ssp() -> (tempfile::TempDir, SystemDescription) {
    let path = ssp_path();
    let dir = scratch("interop-ssp-");
    let file = std::fs::File::open(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    zip::ZipArchive::new(file)
        .and_then(|mut archive| archive.extract(dir.path()))
        .unwrap_or_else(|e| panic!("cannot unzip {}: {e}", path.display()));
    let ssd = dir.path().join("SystemStructure.ssd");
    let system = scenario(ssd.to_str().expect("a UTF-8 temporary path"));
    (dir, system)
}
