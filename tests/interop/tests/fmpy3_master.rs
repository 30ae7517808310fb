//! The paper scenario flown through FMI 3.0 (fmpy's FMU3Slave over target/fmu/fmi3/, in
//! tests/interop/python/fmpy3_master.py) against the Rust harness flying the FMI 2.0 pair.
//!
//! Tolerance: none. The FMI 3.0 and 2.0 layers sit on the same declarations and the same
//! model code in the same library; the masters exchange the same values in the same order
//! at the same communication points. Every recorded value must be bit-identical.
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
