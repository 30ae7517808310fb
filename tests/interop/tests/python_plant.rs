//! A third-party plant: a rigid-body lander written in Python from docs/interface.md alone
//! (tests/interop/python/plant/LanderPlantPy.py), packaged by pythonfmu when the test runs,
//! flown with LanderGnc in fmpy and in the harness.
//!
//! pythonfmu (0.7) lists the outputs in ModelStructure without a `dependencies` attribute,
//! which in FMI 2.0 means every output depends on every input: with LanderGnc's direct
//! feedthrough that is an algebraic loop, and the harness refuses it. Every output of this
//! plant is a state, so the test declares `dependencies=""` for them, as the plant's author
//! would if pythonfmu let them.
//!
//! Environment: pythonfmu's binary calls the Python C API without linking libpython. In
//! fmpy the hosting interpreter provides it; the harness is a native process, so it runs in
//! a child process (src/bin/fly_paper_with_plant.rs) started with the venv's libpython
//! preloaded and PYTHONHOME set (tests/interop/python/embedding_env.py prints both).
// std's transcendental functions make the error measures (powi, hypot) here, outside any FMU (the
// workspace clippy.toml forbids them for the FMUs' sake).
#![allow(clippy::disallowed_methods)]
use interop_tests::compare::compare;
use interop_tests::{python, read_trajectory, scenario, scratch, system_json, write_json};
use std::path::{Path, PathBuf};
use std::process::Command;

fn build_plant(dir: &Path) -> PathBuf {
    let fmu = python::build_fmu("pythonfmu", "plant/LanderPlantPy.py", dir);
    declare_outputs_independent_of_inputs(&fmu);
    fmu
}

/// Rewrites the FMU's modelDescription.xml so that every output listed in ModelStructure
/// depends on no input (see the module comment).
fn declare_outputs_independent_of_inputs(fmu: &Path) {
    python::rewrite_model_description(fmu, |text| {
        assert!(
            text.contains("<Unknown ") && !text.contains("dependencies="),
            "pythonfmu's ModelStructure changed; revisit this rewrite:\n{text}"
        );
        text.replace("<Unknown ", r#"<Unknown dependencies="" "#)
    });
}

/// Hover at the terminal target reached: within 0.5 m of 150 m altitude and 1 m of the
/// vertical through the site, nearly at rest.
fn assert_hovering_at_150_m(trajectory: &cosim::master::Trajectory, who: &str) {
    let last = |name: &str| *trajectory.column(name).unwrap().last().unwrap();
    let (north, up, east) = (
        last("plant.r_nue[1]"),
        last("plant.r_nue[2]"),
        last("plant.r_nue[3]"),
    );
    let speed = (1..=3)
        .map(|i| last(&format!("plant.v_nue[{i}]")).powi(2))
        .sum::<f64>()
        .sqrt();
    println!(
        "{who}: end at r_nue = [{north:.3}, {up:.3}, {east:.3}] m, |v| = {speed:.4} m/s, t = {} s",
        trajectory.times.last().unwrap()
    );
    assert!((up - 150.0).abs() < 0.5, "{who}: altitude {up}");
    assert!(north.hypot(east) < 1.0, "{who}: horizontal {north}, {east}");
    assert!(speed < 0.05, "{who}: speed {speed}");
    assert!(trajectory.values.iter().all(|x| x.is_finite()));
}

#[test]
fn lander_gnc_lands_a_python_plant_in_fmpy_and_in_the_harness_identically() {
    // GIVEN the Python plant packaged by pythonfmu and the paper scenario wired to it
    let dir = scratch("interop-python-plant-");
    let plant_fmu = build_plant(dir.path());
    // (the connections are resolved against LanderPlant, whose interface the Python plant
    // copies name for name: this process cannot load pythonfmu's binary, see above)
    let mut system = system_json(&scenario("paper"));
    let plant = &mut system["instances"][1];
    assert_eq!(plant["name"], "plant");
    plant["fmu"] = serde_json::json!(plant_fmu);

    // WHEN fmpy flies it (Gauss-Seidel, as the harness) ...
    let spec = write_json(&system, dir.path());
    let fmpy_csv = dir.path().join("fmpy.csv");
    python::run("fmpy_master.py", [spec.as_os_str(), fmpy_csv.as_os_str()]);
    let fmpy = read_trajectory(&fmpy_csv);
    // ... and the harness, in a process set up to host pythonfmu's binary
    let harness_csv = dir.path().join("harness.csv");
    let output = Command::new(env!("CARGO_BIN_EXE_fly_paper_with_plant"))
        .arg(&plant_fmu)
        .arg(&harness_csv)
        .envs(python::embedding_env())
        .output()
        .expect("cannot run fly_paper_with_plant");
    assert!(
        output.status.success(),
        "the harness could not fly the Python plant:\n{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
    let harness = read_trajectory(&harness_csv);

    // THEN LanderGnc brings the Python plant to the 150 m hover in both masters ...
    assert_hovering_at_150_m(&fmpy, "fmpy");
    assert_hovering_at_150_m(&harness, "harness");
    // ... along the same trajectory: same binaries, same ordering, same time arithmetic,
    // and Python's float arithmetic is IEEE double as Rust's: bit-identical.
    assert_eq!(fmpy.times, harness.times);
    let comparison = compare(&harness, &fmpy, 0, &harness.names);
    println!("fmpy vs harness with the Python plant:\n{comparison}");
    assert!(comparison.identical(), "{comparison}");
}
