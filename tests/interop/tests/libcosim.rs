//! The closed loop in libcosim (libcosimpy), built through its API and from the SSP package,
//! against the harness flying the same system with libcosim's conventions.
//!
//! libcosim's fixed-step algorithm is Jacobi (every slave steps, then every output is
//! transferred), initializes by exchanging in initialization mode (so the first step already
//! sees the plant's initial state and the controller's answer, as the harness does), keeps
//! time in integer nanoseconds (the FMUs see t_k = k h_ns / 1e9 and h_k = t_{k+1} - t_k,
//! which differs from 0.01 by rounding) and records after stepping. The harness reproduces
//! that (`Ordering::Jacobi` + `Conventions::LIBCOSIM`) rather than the comparison loosening
//! its tolerance: the trajectories must be bit-identical.
//!
//! libcosim (0.x, as wrapped by libcosimpy 0.0.6) ignores FMI 2.0 Enumeration variables, so
//! it cannot set LanderGnc's `control_law`; the paper scenario uses its start value (2,
//! decoupled), and the API script refuses any other value rather than dropping it.
use cosim::master::Conventions;
use cosim::system::Ordering;
use interop_tests::compare::{assert_identical_after_steps, compare};
use interop_tests::{
    paper_with_navigation_errors, python, read_trajectory, run_harness, scenario, scratch,
    unpacked_ssp, write_system_json,
};

fn ns_arg(seconds: f64) -> String {
    seconds.to_string()
}

#[test]
fn libcosim_built_through_its_api_flies_the_paper_scenario_bit_identically() {
    // GIVEN the paper scenario, flown by the harness the way libcosim flies it
    let mut system = scenario("paper");
    system.ordering = Ordering::Jacobi;
    let reference = run_harness(system.clone(), Conventions::LIBCOSIM);

    // WHEN libcosim flies it, slaves and connections made through its API
    let dir = scratch("interop-libcosim-api-");
    let spec = write_system_json(&system, dir.path());
    let csv = dir.path().join("libcosim.csv");
    python::run(
        "libcosim_master.py",
        ["api".as_ref(), spec.as_os_str(), csv.as_os_str()],
    );
    let libcosim = read_trajectory(&csv);

    // THEN every output after every step is the same number
    assert_eq!(libcosim.len(), 17200);
    assert_identical_after_steps(
        "libcosim (API) vs harness (Jacobi, libcosim conventions)",
        &reference,
        &libcosim,
    );
    // AND the time arithmetic matters: with the harness's step counter it is not identical.
    let own = run_harness(system, Conventions::default());
    let differs = compare(&own, &libcosim, 1, &libcosim.names);
    println!(
        "for contrast, harness Jacobi with its own time grid vs libcosim: largest difference \
         {:.3e} ({} values differ)",
        differs.max_abs(),
        differs
            .columns
            .iter()
            .map(|c| c.differing_rows)
            .sum::<usize>()
    );
}

#[test]
fn libcosim_loading_the_ssp_package_flies_it_bit_identically() {
    // GIVEN the SSP package, flown by the harness the way libcosim flies it
    let (unpacked, mut system) = unpacked_ssp();
    system.ordering = Ordering::Jacobi;
    let reference = run_harness(system.clone(), Conventions::LIBCOSIM);

    // WHEN libcosim builds the execution from the package's SystemStructure.ssd
    let dir = scratch("interop-libcosim-ssp-");
    let csv = dir.path().join("libcosim.csv");
    python::run(
        "libcosim_master.py",
        [
            "ssp".as_ref(),
            unpacked.path().as_os_str(),
            csv.as_os_str(),
            ns_arg(system.stop_time).as_ref(),
            ns_arg(system.step_size).as_ref(),
        ],
    );
    let libcosim = read_trajectory(&csv);

    // THEN the inline parameter values were applied and every value is the same
    assert_eq!(libcosim.len(), 17200);
    assert_identical_after_steps(
        "libcosim (SSP) vs harness (Jacobi, libcosim conventions)",
        &reference,
        &libcosim,
    );
}

/// Three FMUs (plant -> nav -> gnc) with seeded navigation errors: LanderNav draws its errors
/// per communication interval and scales the random walk with the step libcosim gives it
/// (h_k from integer nanoseconds), so the same seed must give the same estimates here too.
#[test]
fn libcosim_flies_plant_nav_gnc_with_seeded_navigation_errors_bit_identically() {
    // GIVEN the three-FMU loop with every navigation error on, flown as libcosim flies it
    let mut system = paper_with_navigation_errors(7);
    system.ordering = Ordering::Jacobi;
    let reference = run_harness(system.clone(), Conventions::LIBCOSIM);
    let (estimate, truth) = (
        reference.column("nav.r_nue[2]").unwrap(),
        reference.column("plant.r_nue[2]").unwrap(),
    );
    assert!(estimate.iter().zip(&truth).filter(|(e, t)| e == t).count() * 100 < truth.len());

    // WHEN libcosim flies it through its API
    let dir = scratch("interop-libcosim-nav-");
    let spec = write_system_json(&system, dir.path());
    let csv = dir.path().join("libcosim.csv");
    python::run(
        "libcosim_master.py",
        ["api".as_ref(), spec.as_os_str(), csv.as_os_str()],
    );
    let libcosim = read_trajectory(&csv);

    // THEN every output of the three units after every step is the same number
    assert_eq!(libcosim.len(), 17200);
    assert_identical_after_steps(
        "libcosim (API, three FMUs, navigation errors) vs harness (Jacobi, libcosim conventions)",
        &reference,
        &libcosim,
    );
}
