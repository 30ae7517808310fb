//! The paper scenario flown through FMI 3.0 (fmpy's FMU3Slave over target/fmu/fmi3/, in
//! tests/interop/python/fmpy3_master.py) against the Rust harness flying the FMI 2.0 pair.
//!
//! The FMI 3.0 master exchanges in Co-Simulation Event Mode (`eventModeUsed`): FMI 3.0 allows
//! no get after a set in Step Mode, and LanderGnc's outputs depend on its inputs at the same
//! instant. In Step Mode alone the command lags one step: the harness's Jacobi loop.
//!
//! Tolerance: none. The FMI 3.0 and 2.0 layers sit on the same declarations and the same
//! model code in the same library; the masters exchange the same values in the same order
//! at the same communication points. Every recorded value must be bit-identical.
use cosim::system::Ordering;
use interop_tests::compare::compare;
use interop_tests::{python, read_trajectory, run_harness, scenario, scratch, write_system_json};

#[test]
fn fmi3_fmu3slave_loop_flies_the_paper_scenario_bit_identically_to_the_fmi2_pair() {
    // GIVEN the paper scenario as the harness flies it with the FMI 2.0 FMUs
    let system = scenario("paper");
    let reference = run_harness(system.clone(), Default::default());

    // WHEN fmpy flies the same system through FMI 3.0
    let dir = scratch("interop-fmpy3-master-");
    let spec = write_system_json(&system, dir.path());
    let csv = dir.path().join("fmpy3.csv");
    python::run("fmpy3_master.py", [spec.as_os_str(), csv.as_os_str()]);
    let fmi3 = read_trajectory(&csv);

    // THEN the same rows at the same times, every value equal
    assert_eq!(fmi3.len(), reference.len(), "row count");
    assert_eq!(fmi3.times, reference.times, "communication points");
    let mut names = reference.names.clone();
    names.sort();
    let mut fmi3_names = fmi3.names.clone();
    fmi3_names.sort();
    assert_eq!(fmi3_names, names, "both record every output");
    let comparison = compare(&reference, &fmi3, 0, &reference.names);
    println!("fmpy FMU3Slave loop (FMI 3.0) vs harness (FMI 2.0):\n{comparison}");
    assert!(
        comparison.identical(),
        "expected bit-identical trajectories:\n{comparison}"
    );
}

/// Step Mode alone (no unit uses Event Mode) can only set inputs, step, and read outputs
/// after the step: LanderGnc's command reaches the plant one step late. That loop is the
/// harness's Jacobi loop, every row bit-identical, the last included (neither exchanges
/// again at the end).
#[test]
fn fmi3_step_mode_alone_delays_the_command_one_step_like_the_harness_jacobi_loop() {
    // GIVEN the paper scenario flown by the harness with the FMI 2.0 pair, both orderings
    let system = scenario("paper");
    let gauss_seidel = run_harness(system.clone(), Default::default());
    let mut jacobi_system = system.clone();
    jacobi_system.ordering = Ordering::Jacobi;
    let jacobi = run_harness(jacobi_system, Default::default());

    // WHEN fmpy flies it through FMI 3.0 in Step Mode only
    let dir = scratch("interop-fmpy3-step-mode-");
    let spec = write_system_json(&system, dir.path());
    let csv = dir.path().join("fmpy3-step-mode.csv");
    python::run(
        "fmpy3_master.py",
        [spec.as_os_str(), csv.as_os_str(), "--step-mode".as_ref()],
    );
    let fmi3 = read_trajectory(&csv);

    // THEN it is the Jacobi loop, bit for bit
    assert_eq!(fmi3.times, jacobi.times, "communication points");
    let comparison = compare(&jacobi, &fmi3, 0, &jacobi.names);
    println!("fmpy FMU3Slave, Step Mode only (FMI 3.0) vs harness Jacobi (FMI 2.0):\n{comparison}");
    assert!(
        comparison.identical(),
        "expected bit-identical trajectories:\n{comparison}"
    );
    // AND not the Gauss-Seidel loop: the delay changes the flight
    let delayed = compare(&gauss_seidel, &fmi3, 0, &["plant.r_nue[2]".to_string()]);
    println!(
        "one step of delay vs Gauss-Seidel: plant.r_nue[2] differs by up to {:.3e} m",
        delayed.max_abs()
    );
    assert!(delayed.max_abs() > 0.0);
}
