//! Running the Oscillator through its exported C functions: results against the analytic
//! solution, the early stop, warnings, model errors, Reset, threads, logging.
mod common;

use common::{analytic_x, vr, Fmu};
use fmi_testkit::fmi2::*;
use fmu_testmodel as fmu;

const H: f64 = 0.01;

/// GIVEN an underdamped oscillator with a constant force WHEN stepped for 5 s THEN x
/// follows the closed-form solution (RK4 with 8 sub-steps of 1.25 ms: error ~1e-11).
#[test]
fn outputs_follow_the_analytic_solution() {
    let fmu = Fmu::new(false);
    assert_eq!(fmu.set_real(vr::X0, 0.5), fmi2OK);
    assert_eq!(fmu.set_real(vr::K, 4.0), fmi2OK);
    assert_eq!(fmu.set_real(vr::C, 0.4), fmi2OK);
    fmu.init();
    assert_eq!(fmu.set_real(vr::U, 2.0), fmi2OK);
    let mut t = 0.0;
    for _ in 0..500 {
        assert_eq!(fmu.step(t, H), fmi2OK);
        t += H;
        let expected = analytic_x(t, 0.5, 4.0, 0.4, 2.0);
        assert!((fmu.get_real(vr::X) - expected).abs() < 1e-9, "t = {t}");
    }
    assert_eq!(fmu.get_integer(vr::STEP_COUNT), 500);
    assert_eq!(fmu.get_real(vr::OMEGA_N), 2.0);
    assert_eq!(fmu.get_real(vr::MASS), 1.0);
}

/// Initial unknowns in initialization mode follow the parameters set before.
#[test]
fn initial_unknowns_follow_parameters_in_initialization_mode() {
    let fmu = Fmu::new(false);
    fmu.setup(0.0, None);
    fmu.enter_init();
    assert_eq!(fmu.set_real(vr::X0, -3.0), fmi2OK);
    assert_eq!(fmu.set_real(vr::K, 9.0), fmi2OK);
    assert_eq!(fmu.get_real(vr::X), -3.0);
    assert_eq!(fmu.get_real(vr::OMEGA_N), 3.0);
}

/// GIVEN stop_at_threshold with x0 = 1, k = 1, c = 0 and threshold 0 WHEN stepping THEN the
/// step containing t = pi/2 ends early with fmi2Discard, LastSuccessfulTime = pi/2,
/// Terminated = true, and the state machine is in StepFailed (only Terminate goes on).
#[test]
fn threshold_crossing_stops_with_discard_at_the_crossing_time() {
    let fmu = Fmu::new(true);
    fmu.set_real(vr::C, 0.0);
    fmu.set_boolean(vr::STOP_AT_THRESHOLD, true);
    fmu.init();
    let mut t = 0.0;
    let status = loop {
        let status = fmu.step(t, H);
        if status != fmi2OK {
            break status;
        }
        t += H;
        assert!(!fmu.terminated());
        assert_eq!(fmu.last_successful_time(), t);
    };
    assert_eq!(status, fmi2Discard);
    let stop = fmu.last_successful_time();
    assert!(
        (stop - std::f64::consts::FRAC_PI_2).abs() < 1e-9,
        "stop {stop}"
    );
    assert!(t < stop && stop <= t + H);
    assert!(fmu.terminated());
    assert!(fmu.get_real(vr::X).abs() < 1e-9);
    let discard = fmu
        .records()
        .into_iter()
        .find(|r| r.status == fmi2Discard)
        .expect("discard logged with debug logging on");
    assert_eq!(discard.category, "logStatusDiscard");
    assert!(discard
        .message
        .starts_with("fmi2DoStep: step ended early at t = "));
    assert_eq!(fmu.step(stop, H), fmi2Error);
    assert!(fmu
        .last_message()
        .contains("illegal call in state StepFailed"));
    assert_eq!(unsafe { fmu::fmi2Terminate(fmu.c) }, fmi2OK);
}

/// A falling-only crossing ignores the first (rising) crossing of a negative threshold.
#[test]
fn crossing_direction_selects_the_crossing() {
    let fmu = Fmu::new(false);
    fmu.set_real(vr::X0, -1.0);
    fmu.set_real(vr::C, 0.0);
    fmu.set_real(vr::THRESHOLD, 0.5);
    fmu.set_boolean(vr::STOP_AT_THRESHOLD, true);
    assert_eq!(fmu.set_integer(vr::CROSSING, 2), fmi2OK);
    fmu.init();
    let mut t = 0.0;
    while fmu.step(t, H) == fmi2OK {
        t += H;
    }
    // x = -cos t rises through 0.5 at 2pi/3 and falls through it at 4pi/3.
    let stop = fmu.last_successful_time();
    assert!(
        (stop - 4.0 * std::f64::consts::PI / 3.0).abs() < 1e-9,
        "stop {stop}"
    );
}

#[test]
fn coarse_sub_steps_give_a_warning() {
    let fmu = Fmu::new(false);
    fmu.set_real(vr::K, 1e4);
    fmu.set_integer(vr::SUBSTEPS, 1);
    fmu.init();
    assert_eq!(fmu.step(0.0, H), fmi2Warning);
    let last = fmu.records().pop().unwrap();
    assert_eq!(last.status, fmi2Warning);
    assert_eq!(last.category, "logStatusWarning");
    assert!(last
        .message
        .starts_with("fmi2DoStep: sub-step 0.01 s is coarse"));
    assert_eq!(fmu.step(H, H), fmi2Warning, "a warning is not a failure");
}

/// A model error in ExitInitializationMode: fmi2Error, state Error, Reset recovers.
#[test]
fn invalid_parameter_fails_initialization_and_reset_recovers() {
    let fmu = Fmu::new(false);
    fmu.set_boolean(vr::STOP_AT_THRESHOLD, true);
    fmu.set_real(vr::THRESHOLD, 1.0);
    fmu.setup(0.0, None);
    fmu.enter_init();
    assert_eq!(fmu.exit_init(), fmi2Error);
    assert_eq!(
        fmu.last_message(),
        "fmi2ExitInitializationMode: parameter threshold = 1: equals x0 while \
         stop_at_threshold is set: the model would stop at once"
    );
    assert_eq!(fmu.step(0.0, H), fmi2Error);
    assert!(fmu.last_message().contains("illegal call in state Error"));
    assert_eq!(unsafe { fmu::fmi2Reset(fmu.c) }, fmi2OK);
    fmu.init();
    assert_eq!(fmu.step(0.0, H), fmi2OK);
}

/// A model error in DoStep (the state overflows): fmi2Error, state Error.
#[test]
fn diverging_state_is_a_step_error() {
    let fmu = Fmu::new(false);
    fmu.set_real(vr::X0, 1e10);
    fmu.init();
    fmu.set_real(vr::K, 1e300);
    assert_eq!(fmu.step(0.0, H), fmi2Error);
    assert!(fmu
        .last_message()
        .starts_with("fmi2DoStep: state diverged at t = 0 s"));
    assert_eq!(fmu.set_real(vr::K, 1.0), fmi2Error);
    assert!(fmu.last_message().contains("illegal call in state Error"));
}

/// GIVEN an instance that ran, was re-parameterised and terminated WHEN reset THEN it is
/// indistinguishable from a fresh one: same start values, time 0, same trajectory.
#[test]
fn reset_returns_to_the_freshly_instantiated_state() {
    let run = |fmu: &Fmu| -> Vec<u64> {
        fmu.init();
        (0..50)
            .map(|i| {
                assert_eq!(fmu.step(i as f64 * H, H), fmi2OK);
                fmu.get_real(vr::X).to_bits()
            })
            .collect()
    };
    let fresh = run(&Fmu::new(false));

    let fmu = Fmu::new(false);
    fmu.set_real(vr::X0, 7.0);
    fmu.set_string(vr::LABEL, "changed");
    fmu.init();
    fmu.set_real(vr::K, 3.0);
    fmu.step(0.0, H);
    unsafe { fmu::fmi2Terminate(fmu.c) };
    assert_eq!(unsafe { fmu::fmi2Reset(fmu.c) }, fmi2OK);
    // Get is illegal in Instantiated: prove the state, then look in initialization mode.
    assert_eq!(fmu.step(0.0, H), fmi2Error);
    assert!(fmu
        .last_message()
        .contains("illegal call in state Instantiated"));
    fmu.setup(0.0, None);
    fmu.enter_init();
    assert_eq!(fmu.get_real(vr::X0), 1.0);
    assert_eq!(fmu.get_real(vr::K), 1.0);
    assert_eq!(fmu.get_string(vr::LABEL), "oscillator");
    assert_eq!(fmu.get_integer(vr::STEP_COUNT), 0);
    unsafe { fmu::fmi2Reset(fmu.c) };
    assert_eq!(run(&fmu), fresh);
}

/// Masters accumulate t += h; a point within 1e-9 relative of the FMU's time is accepted
/// and the FMU continues from the master's own t + h.
#[test]
fn accumulated_rounding_in_the_communication_point_is_accepted() {
    let fmu = Fmu::new(false);
    fmu.init();
    let mut t = 0.0;
    for _ in 0..1200 {
        assert_eq!(fmu.step(t, H), fmi2OK);
        t += H;
    }
    assert_ne!(t, 12.0, "the premise: accumulation drifts");
    assert_eq!(fmu.last_successful_time(), t);
    assert_eq!(fmu.step(12.0, H), fmi2OK, "within the tolerance");
    assert_eq!(fmu.last_successful_time(), 12.0 + H);
}

#[test]
fn stop_time_is_honoured_with_tolerance() {
    let fmu = Fmu::new(false);
    fmu.setup(0.0, Some(0.03));
    fmu.enter_init();
    fmu.exit_init();
    let mut t = 0.0;
    for _ in 0..3 {
        assert_eq!(fmu.step(t, H), fmi2OK);
        t += H;
    }
    assert_eq!(fmu.step(t, H), fmi2Error);
    assert_eq!(
        fmu.last_message(),
        format!(
            "fmi2DoStep: step to {} (currentCommunicationPoint {t} + communicationStepSize \
             0.01) passes the stop time 0.03 given to fmi2SetupExperiment",
            t + H
        )
    );
}

/// Two instances driven at once from two threads give bit-identical results to serial runs.
#[test]
fn instances_on_two_threads_match_serial_runs() {
    fn run(k: f64) -> Vec<u64> {
        let fmu = Fmu::named(&format!("k{k}"), false);
        fmu.set_real(vr::K, k);
        fmu.init();
        (0..2000)
            .map(|i| {
                fmu.set_real(vr::U, (i as f64 * 0.01).sin());
                assert_eq!(fmu.step(i as f64 * H, H), fmi2OK);
                fmu.get_real(vr::X).to_bits()
            })
            .collect()
    }
    let serial = [run(2.0), run(5.0)];
    let parallel = std::thread::scope(|s| {
        let a = s.spawn(|| run(2.0));
        let b = s.spawn(|| run(5.0));
        [a.join().unwrap(), b.join().unwrap()]
    });
    assert_eq!(serial, parallel);
    assert_ne!(serial[0], serial[1]);
}

#[test]
fn strings_are_copied_in_and_out() {
    let fmu = Fmu::new(false);
    assert_eq!(fmu.set_string(vr::LABEL, "lander ü"), fmi2OK);
    fmu.init();
    assert_eq!(fmu.get_string(vr::LABEL), "lander ü");
}

#[test]
fn types_platform_and_version() {
    let text =
        |p: *const std::ffi::c_char| unsafe { std::ffi::CStr::from_ptr(p) }.to_str().unwrap();
    assert_eq!(text(unsafe { fmu::fmi2GetTypesPlatform() }), "default");
    assert_eq!(text(unsafe { fmu::fmi2GetVersion() }), "2.0");
}
