//! The short version of the long run (the 10-million-step one is the `long-run` binary):
//! finite outputs, a unit quaternion to 1e-12, the plant's angular momentum conserved,
//! bit-exact restores of serialized states along the way, and flat memory. LanderNav runs
//! with every error on (the estimate differs from the truth at every step) and with every
//! error off (it equals the truth bit for bit at every step). LanderSensors: validity flags 0
//! or 1, an invalid measurement reads 0, the altimeter always valid and every beam both
//! valid and invalid along the run. LanderFilter: the covariance diagonal positive and
//! finite, degrees of freedom within their ranges, no gate rejection (gating off), and the
//! estimate near the truth.
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
    // From the third sample on: the first restores size the serialized-state buffers and
    // the allocator's arenas once (up to 128 KiB). Resident pages still move by a page
    // table's worth (72 KiB seen on a loaded machine); the smallest leak, one 16-byte
    // allocation per step, adds 3.3 MiB over the 210,000 steps these seven samples span.
    let settled = &report.rss_kib[2..];
    let (min, max) = (settled.iter().min().unwrap(), settled.iter().max().unwrap());
    assert!(max - min <= 256, "VmRSS not flat: {report:?}");
    report
}

/// One test for all FMUs: resident memory is per process, so they must not run side by side.
#[test]
fn every_fmu_runs_300k_steps_with_its_invariants() {
    plant_tumbles_torque_free_conserving_angular_momentum();
    check(Lander::Gnc);
    nav_with_errors_on_never_passes_the_truth_through();
    nav_with_errors_off_is_the_identity();
    sensors_flag_their_measurements();
    filter_keeps_a_sound_covariance_and_tracks_the_truth();
}

/// Fewer steps for the two FMUs that draw or filter at every step.
const MEASUREMENT_STEPS: usize = 100_000;

fn sensors_flag_their_measurements() {
    let fmu = Fmu::load(Lander::Sensors).expect("packaged FMU");
    let report = long_run::run(&fmu, MEASUREMENT_STEPS, 10).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(report.steps, MEASUREMENT_STEPS);
    assert_eq!(report.restores, 9, "{report:?}");
    // 100 m to 1,100 m, tilted by at most 0.2 rad: always within the altimeter's 2,000 m.
    assert_eq!(report.valid_counts[0], report.probed_steps, "{report:?}");
    // Each beam leaves its 1,000 m range high up and drops 5 % of its samples.
    for &n in &report.valid_counts[1..] {
        assert!(
            n > report.probed_steps / 4 && n < report.probed_steps,
            "{report:?}"
        );
    }
}

fn filter_keeps_a_sound_covariance_and_tracks_the_truth() {
    let fmu = Fmu::load(Lander::Filter).expect("packaged FMU");
    let report = long_run::run(&fmu, MEASUREMENT_STEPS, 10).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(report.steps, MEASUREMENT_STEPS);
    assert_eq!(report.restores, 9, "{report:?}");
    assert!(report.max_quaternion_norm_error <= 1e-12, "{report:?}");
    assert!(report.covariance_min > 0.0, "{report:?}");
    assert!(report.covariance_max.is_finite(), "{report:?}");
    // The altimeter holds the altitude to metres, the velocimeter the velocity to
    // centimetres per second (after the first second's convergence from 1 m/s).
    assert!(report.max_altitude_error_m < 5.0, "{report:?}");
    assert!(report.max_velocity_error_mps < 1.0, "{report:?}");
    // Updates happened: the altimeter at (nearly) every point, the beams with every count.
    assert!(
        report.valid_counts[0] > report.probed_steps * 9 / 10,
        "{report:?}"
    );
    assert!(
        report.valid_counts[4] > report.probed_steps / 2,
        "{report:?}"
    );
}

fn nav_with_errors_on_never_passes_the_truth_through() {
    let report = check(Lander::Nav);
    assert_eq!(report.probed_steps, STEPS - 9 * 100, "{report:?}");
    assert_eq!(report.identity_steps, 0, "{report:?}");
}

/// Fewer steps: the identity has no state that could drift.
fn nav_with_errors_off_is_the_identity() {
    const OFF_STEPS: usize = 30_000;
    let fmu = Fmu::load(Lander::Nav).expect("packaged FMU");
    let report = long_run::run_with(&fmu, OFF_STEPS, 10, &[]).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(report.steps, OFF_STEPS);
    assert_eq!(report.restores, 9, "{report:?}");
    assert!(report.probed_steps > OFF_STEPS / 2, "{report:?}");
    assert_eq!(report.identity_steps, report.probed_steps, "{report:?}");
    assert!(report.max_quaternion_norm_error <= 1e-12, "{report:?}");
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
