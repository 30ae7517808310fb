//! fmpy's own SSP runner (`simulate_ssp`) on `LanderDescent.ssp`, against the harness flying
//! the same SystemStructure.ssd with fmpy's conventions.
//!
//! fmpy 0.3's `simulate_ssp` cannot do what the harness does by default: it only runs
//! fixed-step Jacobi, it starts with every connector at 0.0 (no exchange in initialization
//! mode, so LanderGnc's first inputs are degenerate and it answers them with a warning and
//! safe outputs), it accumulates time (`t += h`, reaching 171.99999999998855 after 17200
//! steps and so stepping once more), and it records after stepping. Rather than loosening
//! the tolerance, the harness reproduces those conventions
//! (`Ordering::Jacobi` + `Conventions::FMPY_SIMULATE_SSP`), and the trajectories must then
//! be bit-identical.
use cosim::master::Conventions;
use cosim::system::Ordering;
use interop_tests::compare::{assert_identical_after_steps, compare};
use interop_tests::{python, read_trajectory, run_harness, scratch, ssp_path, unpacked_ssp};

#[test]
fn simulate_ssp_flies_the_packaged_system_bit_identically_to_the_harness_in_its_conventions() {
    // GIVEN the system of the SSP package, flown by the harness the way fmpy flies it
    let (_unpacked, mut system) = unpacked_ssp();
    system.ordering = Ordering::Jacobi;
    let reference = run_harness(system.clone(), Conventions::FMPY_SIMULATE_SSP);

    // WHEN fmpy's simulate_ssp flies the package, with the SSD's inline parameter values
    let dir = scratch("interop-fmpy-ssp-");
    let csv = dir.path().join("simulate_ssp.csv");
    python::run("fmpy_ssp.py", [ssp_path().as_os_str(), csv.as_os_str()]);
    let fmpy = read_trajectory(&csv);

    // THEN one row after every step, under the same accumulated time labels, with
    // bit-identical values (fmpy labels the row after the step from t_k with t_k, the
    // harness records it at the next point; the helper pairs them)
    assert_eq!(
        fmpy.len(),
        17201,
        "fmpy steps while the accumulated t < 172"
    );
    assert_eq!(fmpy.times[..], reference.times[..fmpy.len()]);
    let mut after_steps = fmpy.clone();
    after_steps.times = reference.times[1..].to_vec();
    assert_identical_after_steps(
        "fmpy simulate_ssp vs harness (Jacobi, fmpy conventions)",
        &reference,
        &after_steps,
    );
    let altitude = reference.column("plant.r_nue[2]").unwrap();
    assert!((altitude.last().unwrap() - 150.0).abs() < 0.5);

    // AND the conventions are what makes it so: the harness's own Jacobi run differs.
    let own = run_harness(system, Conventions::default());
    let differs = compare(&own, &after_steps, 1, &fmpy.names);
    println!(
        "for contrast, harness Jacobi with its own conventions vs simulate_ssp: largest \
         difference {:.3e}",
        differs.max_abs()
    );
    assert!(!differs.identical());
}
