//! The paper scenario flown by a master written with fmpy's FMU2Slave
//! (tests/interop/python/fmpy_master.py), against the Rust harness.
//!
//! Tolerance: none. Both masters load the same FMU binaries, exchange in the same
//! Gauss-Seidel order, set the same inputs with the same values, compute the same
//! communication points (t_k = start + k h, one IEEE multiplication each, in Python as in
//! Rust) and record every output; the FMUs are deterministic functions of those calls. So
//! every recorded value must be bit-identical, and any difference is a real divergence in
//! the masters' semantics, not rounding.
use cosim::master::Trajectory;
use interop_tests::compare::compare;
use interop_tests::{
    paper_with_navigation_errors, python, read_trajectory, run_harness, scenario, scratch,
    write_system_json,
};

/// `system` flown by fmpy_master.py; asserts that it records the same rows, times and columns
/// as `reference` and that every value is bit-identical.
fn fmpy_flies_it_like_the_harness(
    system: &cosim::system::SystemDescription,
    reference: &Trajectory,
    title: &str,
) {
    let dir = scratch("interop-fmpy-master-");
    let spec = write_system_json(system, dir.path());
    let csv = dir.path().join("fmpy.csv");
    python::run("fmpy_master.py", [spec.as_os_str(), csv.as_os_str()]);
    let fmpy = read_trajectory(&csv);

    assert_eq!(fmpy.len(), reference.len(), "row count");
    assert_eq!(fmpy.times, reference.times, "communication points");
    let mut names = reference.names.clone();
    names.sort();
    let mut fmpy_names = fmpy.names.clone();
    fmpy_names.sort();
    assert_eq!(fmpy_names, names, "both record every output");
    let comparison = compare(reference, &fmpy, 0, &reference.names);
    println!("{title}:\n{comparison}");
    assert!(
        comparison.identical(),
        "expected bit-identical trajectories:\n{comparison}"
    );
}

#[test]
fn fmpy_gauss_seidel_loop_flies_the_paper_scenario_bit_identically_to_the_harness() {
    // GIVEN the paper scenario as the harness flies it by default
    let system = scenario("paper");
    let reference = run_harness(system.clone(), Default::default());

    // WHEN fmpy flies the same system with the harness's ordering
    // THEN the same rows at the same times, and every value equal
    fmpy_flies_it_like_the_harness(
        &system,
        &reference,
        "fmpy FMU2Slave loop vs harness (Gauss-Seidel)",
    );
    // The flight did happen: the lander ends hovering at 150 m.
    let altitude = reference.column("plant.r_nue[2]").unwrap();
    assert!((altitude.last().unwrap() - 150.0).abs() < 0.5);
}

#[test]
fn fmpy_flies_plant_nav_gnc_with_seeded_navigation_errors_bit_identically_to_the_harness() {
    // GIVEN the three-FMU loop (nav, gnc, plant) with every navigation error on, seeded
    let system = paper_with_navigation_errors(20261201);
    let reference = run_harness(system.clone(), Default::default());
    // (the errors are really there: the GNC never sees the true state)
    for (estimate, truth) in [
        ("nav.r_nue[2]", "plant.r_nue[2]"),
        ("nav.v_nue[1]", "plant.v_nue[1]"),
        ("nav.q_body_to_nue[1]", "plant.q_body_to_nue[1]"),
        ("nav.omega_body[3]", "plant.omega_body[3]"),
        ("nav.mass", "plant.mass"),
    ] {
        let (e, t) = (
            reference.column(estimate).unwrap(),
            reference.column(truth).unwrap(),
        );
        let equal = e.iter().zip(&t).filter(|(a, b)| a == b).count();
        assert!(
            equal * 100 < e.len(),
            "{estimate} equals {truth} in {equal} of {} rows",
            e.len()
        );
    }

    // WHEN fmpy flies the same system, THEN every value of every unit is bit-identical
    fmpy_flies_it_like_the_harness(
        &system,
        &reference,
        "fmpy FMU2Slave loop vs harness, plant -> nav -> gnc with navigation errors",
    );
}

#[test]
fn fmpy_flies_the_full_fidelity_landing_bit_identically_to_the_harness() {
    // GIVEN the four-FMU loop (sensors, filter, gnc, plant) with every effect on, through
    // the touchdown on the gear and the settling after it
    let system = scenario("full-fidelity");
    let reference = run_harness(system.clone(), Default::default());
    // (the GNC flies on the filter's estimate, and the lander does land on its footpads)
    let (estimate, truth) = (
        reference.column("filter.r_nue[2]").unwrap(),
        reference.column("plant.r_nue[2]").unwrap(),
    );
    assert!(estimate.iter().zip(&truth).filter(|(a, b)| a == b).count() * 100 < estimate.len());
    assert_eq!(
        reference.column("plant.settled").unwrap().last(),
        Some(&1.0)
    );

    // WHEN fmpy flies the same system, THEN every value of every unit is bit-identical
    fmpy_flies_it_like_the_harness(
        &system,
        &reference,
        "fmpy FMU2Slave loop vs harness (full fidelity: sensors, filter, gnc, plant)",
    );
}
