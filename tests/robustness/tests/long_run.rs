//! The short version of the long run (the 10-million-step one is the `long-run` binary):
//! finite outputs, a unit quaternion to 1e-12, the plant's angular momentum conserved,
//! bit-exact restores of serialized states along the way, and flat memory.
use robustness_tests::instance::Fmu;
use robustness_tests::long_run;
use robustness_tests::package::Lander;

const STEPS: usize = 300_000;

/// Relative drift of the tumbling plant's angular momentum (NUE) allowed over the run: RK4
/// with 0.01 s steps at |omega| = 0.7 rad/s keeps it near 1e-12 per 1e5 steps; the bound
/// leaves a factor of 100.
const MAX_ANGULAR_MOMENTUM_DRIFT: f64 = 1e-9;

fn check(lander: Lander) -> long_run::Report {
    let fmu = Fmu::load(lander).expect("packaged FMU");
    let report = long_run::run(&fmu, STEPS, 10).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(report.steps, STEPS);
    assert!(report.max_quaternion_norm_error <= 1e-12, "{report:?}");
    assert_eq!(report.restores, 9, "{report:?}");
    let (min, max) = (
        report.rss_kib.iter().min().unwrap(),
        report.rss_kib.iter().max().unwrap(),
    );
    assert!(max - min <= 64, "VmRSS not flat: {report:?}");
    report
}

/// One test for both FMUs: resident memory is per process, so they must not run side by side.
#[test]
fn both_fmus_run_300k_steps_with_their_invariants() {
    plant_tumbles_torque_free_conserving_angular_momentum();
    check(Lander::Gnc);
}

fn plant_tumbles_torque_free_conserving_angular_momentum() {
    let report = check(Lander::Plant);
    assert!(
        report.max_angular_momentum_drift <= MAX_ANGULAR_MOMENTUM_DRIFT,
        "{report:?}"
    );
    // The tumble really happens: a body at rest would conserve it trivially.
    assert!(report.max_angular_momentum_drift > 0.0, "{report:?}");
}
