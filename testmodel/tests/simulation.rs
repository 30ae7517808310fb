//! Running the Oscillator through its exported C functions: results against the analytic
//! solution, the early stop, warnings, model errors, Reset, threads, logging.
// std's transcendental functions here are a reference independent of the libm the model uses.
#![allow(clippy::disallowed_methods)]
use crate::common;

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
    // A warning is not a failure; its repeat is counted, not logged, and leaves OK.
    assert_eq!(fmu.step(H, H), fmi2OK, "a repeated warning");
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

// ---- Both versions, through the kit's driver ----

use common::{Driver, Interface, Osc, Status, Version};

/// The analytic solution, as above, for each version.
fn outputs_follow_the_analytic_solution_in_each_version<D: Osc>() {
    let fmu = D::open(false);
    assert_eq!(fmu.set_real(vr::X0, 0.5), Status::Ok);
    assert_eq!(fmu.set_real(vr::K, 4.0), Status::Ok);
    assert_eq!(fmu.set_real(vr::C, 0.4), Status::Ok);
    fmu.initialize();
    assert_eq!(fmu.set_real(vr::U, 2.0), Status::Ok);
    let mut t = 0.0;
    for _ in 0..500 {
        let step = fmu.step(t, H);
        assert_eq!(step.status, Status::Ok, "{:?}", fmu.messages());
        assert!(!step.ended_early && !step.terminated);
        assert_eq!(step.last_successful_time, t + H);
        t += H;
        let expected = analytic_x(t, 0.5, 4.0, 0.4, 2.0);
        assert!((fmu.real(vr::X) - expected).abs() < 1e-9, "t = {t}");
    }
    assert_eq!(fmu.integer(vr::STEP_COUNT), 500);
    assert_eq!(fmu.real(vr::OMEGA_N), 2.0);
    assert_eq!(fmu.real(vr::MASS), 1.0);
}

/// The step containing t = pi/2 ends there and the FMU asks to terminate. FMI 2.0
/// (§4.2.2): `fmi2Discard`, then `fmi2Terminated` and `fmi2LastSuccessfulTime`, and the
/// instance is in StepFailed. FMI 3.0 (§4.2.1): the step succeeded (`fmi3OK`) with
/// `earlyReturn` (the master allowed it), `terminateSimulation` and `lastSuccessfulTime`
/// at the crossing; `fmi3Discard` would mean the step was not carried out.
fn threshold_crossing_ends_the_step_at_the_crossing<D: Osc>() {
    let fmu = D::open(false);
    fmu.set_real(vr::C, 0.0);
    fmu.set_boolean(vr::STOP_AT_THRESHOLD, true);
    fmu.initialize();
    let mut t = 0.0;
    let last = loop {
        let step = fmu.step(t, H);
        if step.ended_early {
            break step;
        }
        assert_eq!(step.status, Status::Ok, "{:?}", fmu.messages());
        assert!(!step.terminated);
        t += H;
        assert!(t < 2.0, "no stop: {:?}", fmu.messages());
    };
    let expected = match D::VERSION {
        Version::Fmi2 => Status::Discard,
        Version::Fmi3 => Status::Ok,
    };
    assert_eq!(last.status, expected);
    assert!(last.terminated);
    let stop = last.last_successful_time;
    assert!(
        (stop - std::f64::consts::FRAC_PI_2).abs() < 1e-9,
        "stop {stop}"
    );
    assert!(t < stop && stop <= t + H);
    assert!(fmu.real(vr::X).abs() < 1e-9);
    match D::VERSION {
        // StepFailed: only Terminate (and the status functions) go on.
        Version::Fmi2 => {
            assert_eq!(fmu.step(stop, H).status, Status::Error);
            assert!(fmu
                .last_message()
                .contains("illegal call in state StepFailed"));
        }
        // Still Step Mode, but the run is over: a master that steps on anyway is refused
        // (the importer must end the run with fmi3Terminate), from any point.
        Version::Fmi3 => {
            for from in [t + H, stop] {
                assert_eq!(fmu.step(from, H).status, Status::Error);
                assert!(
                    fmu.last_message().contains("terminateSimulation"),
                    "{}",
                    fmu.last_message()
                );
            }
        }
    }
    assert_eq!(fmu.terminate(), Status::Ok);
}

/// A falling-only crossing ignores the first (rising) crossing of a threshold, in each
/// version (the enumeration is an FMI 2.0 Integer, an FMI 3.0 Int64).
fn crossing_direction_selects_the_crossing_in_each_version<D: Osc>() {
    let fmu = D::open(false);
    fmu.set_real(vr::X0, -1.0);
    fmu.set_real(vr::C, 0.0);
    fmu.set_real(vr::THRESHOLD, 0.5);
    fmu.set_boolean(vr::STOP_AT_THRESHOLD, true);
    assert_eq!(fmu.set_enumeration(vr::CROSSING, 2), Status::Ok);
    fmu.initialize();
    assert_eq!(fmu.get_enumeration(vr::CROSSING), (Status::Ok, 2));
    let mut t = 0.0;
    let stop = loop {
        let step = fmu.step(t, H);
        if step.ended_early {
            break step.last_successful_time;
        }
        t += H;
        assert!(t < 6.0);
    };
    // x = -cos t rises through 0.5 at 2pi/3 and falls through it at 4pi/3.
    assert!(
        (stop - 4.0 * std::f64::consts::PI / 3.0).abs() < 1e-9,
        "stop {stop}"
    );
}

/// A coarse sub-step warns, with the version's function name, and is no failure.
fn coarse_sub_steps_give_a_warning_in_each_version<D: Osc>() {
    let fmu = D::open(false);
    fmu.set_real(vr::K, 1e4);
    fmu.set_integer(vr::SUBSTEPS, 1);
    fmu.initialize();
    assert_eq!(fmu.step(0.0, H).status, Status::Warning);
    let last = fmu.logger().all().pop().unwrap();
    assert_eq!(last.status, fmi2Warning, "the same number in both versions");
    assert_eq!(last.category.as_deref(), Some("logStatusWarning"));
    assert!(last
        .message()
        .starts_with(&format!("{}: sub-step 0.01 s is coarse", D::f("DoStep"))));
    assert_eq!(
        fmu.step(H, H).status,
        Status::Ok,
        "its repeat is counted, not logged"
    );
}

/// A model error in ExitInitializationMode: Error, the model's reason, Reset recovers.
fn invalid_parameter_fails_initialization_and_reset_recovers_in_each_version<D: Osc>() {
    let fmu = D::open(false);
    fmu.set_boolean(vr::STOP_AT_THRESHOLD, true);
    fmu.set_real(vr::THRESHOLD, 1.0);
    assert_eq!(fmu.enter_initialization_mode(0.0, None), Status::Ok);
    assert_eq!(fmu.exit_initialization_mode(), Status::Error);
    assert_eq!(
        fmu.last_message(),
        format!(
            "{}: parameter threshold = 1: equals x0 while stop_at_threshold is set: the model \
             would stop at once",
            D::f("ExitInitializationMode")
        )
    );
    assert_eq!(fmu.set_real(vr::U, 1.0), Status::Error, "state Error");
    assert_eq!(fmu.reset(), Status::Ok);
    fmu.initialize();
    assert!(
        !fmu.boolean(vr::STOP_AT_THRESHOLD),
        "Reset restores the start values"
    );
    assert_eq!(fmu.step(0.0, H).status, Status::Ok);
}

both!(
    outputs_follow_the_analytic_solution_in_each_version,
    threshold_crossing_ends_the_step_at_the_crossing,
    crossing_direction_selects_the_crossing_in_each_version,
    coarse_sub_steps_give_a_warning_in_each_version,
    invalid_parameter_fails_initialization_and_reset_recovers_in_each_version,
);

/// FMI 3.0 Model Exchange: a master's own RK4 over the FMU's derivatives follows the
/// analytic solution, and the state event of the threshold (located by bisection on the
/// event indicator) ends the simulation at pi/2 through fmi3UpdateDiscreteStates.
#[test]
fn fmi3_model_exchange_integrates_and_stops_at_the_state_event() {
    let fmu = common::Fmi3::open_as(Interface::ModelExchange, "me", false);
    fmu.set_real(vr::C, 0.0);
    Driver::set_boolean(&fmu, vr::STOP_AT_THRESHOLD, true);
    Driver::initialize(&fmu);
    let update = fmu.update_discrete_states();
    assert_eq!(update.status, fmi_testkit::fmi3_ffi::fmi3OK);
    assert!(!update.terminate_simulation, "no event at the start");
    assert_eq!(
        fmu.enter_continuous_time_mode(),
        fmi_testkit::fmi3_ffi::fmi3OK
    );
    let (_, mut x) = fmu.continuous_states(2);
    assert_eq!(x, vec![1.0, 0.0]);
    let eval = |t: f64, x: &[f64]| {
        fmu.set_time(t);
        assert_eq!(fmu.set_continuous_states(x), fmi_testkit::fmi3_ffi::fmi3OK);
        let (_, dx) = fmu.derivatives(2);
        let (_, z) = fmu.event_indicators(1);
        (dx, z[0])
    };
    let rk4 = |t: f64, x: &[f64], h: f64| {
        let at = |k: &[f64], s: f64| vec![x[0] + s * k[0], x[1] + s * k[1]];
        let k1 = eval(t, x).0;
        let k2 = eval(t + h / 2.0, &at(&k1, h / 2.0)).0;
        let k3 = eval(t + h / 2.0, &at(&k2, h / 2.0)).0;
        let k4 = eval(t + h, &at(&k3, h)).0;
        (0..2)
            .map(|i| x[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]))
            .collect::<Vec<f64>>()
    };
    let h = 0.001;
    let mut t = 0.0;
    loop {
        let x1 = rk4(t, &x, h);
        if eval(t + h, &x1).1 > 0.0 {
            t += h;
            x = x1;
            assert!((x[0] - t.cos()).abs() < 1e-9, "t = {t}");
            let (status, enter, terminate) = fmu.completed_integrator_step();
            assert_eq!(status, fmi_testkit::fmi3_ffi::fmi3OK);
            assert!(!enter && !terminate);
            continue;
        }
        let (mut lo, mut hi) = (0.0, h);
        while hi - lo > 1e-13 {
            let mid = 0.5 * (lo + hi);
            if eval(t + mid, &rk4(t, &x, mid)).1 > 0.0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        x = rk4(t, &x, hi);
        t += hi;
        eval(t, &x);
        break;
    }
    assert_eq!(fmu.enter_event_mode(), fmi_testkit::fmi3_ffi::fmi3OK);
    let update = fmu.update_discrete_states();
    assert_eq!(
        update.status,
        fmi_testkit::fmi3_ffi::fmi3OK,
        "{:?}",
        fmu.messages()
    );
    assert!(update.terminate_simulation);
    assert!((t - std::f64::consts::FRAC_PI_2).abs() < 1e-9, "t = {t}");
    assert_eq!(Driver::terminate(&fmu), Status::Ok);
}
