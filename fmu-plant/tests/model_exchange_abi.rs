//! LanderPlant as a Model Exchange FMU through its exported C functions, driven by the test
//! kit's own ME master ([`MeSolver`]: classical RK4 at a fixed step, events by bisection on
//! the event indicators), against the analytic solution and the Co-Simulation interface.
#![allow(unsafe_code)]
use crate::common;

use common::{vr, Plant, FUNCTIONS};
use fmi_testkit::fmi2::*;
use fmi_testkit::{fmi2_me_functions, MeSolver};
use fmu_plant as fmu;

const G: f64 = 1.62;
const NX: usize = 18;
const NZ: usize = 2;

fn model_exchange() -> MeSolver {
    let guid = fmi2_export::guid::<fmu::LanderPlant>();
    MeSolver::instantiate(&FUNCTIONS, fmi2_me_functions!(fmu_plant), &guid, NX, NZ)
}

#[test]
fn free_fall_touches_down_at_the_analytic_time_under_the_kits_solver() {
    // GIVEN the default plant at 800 m, engines off, as a Model Exchange instance
    let mut me = model_exchange();
    me.start();
    assert_eq!(me.x[1], 800.0, "state 2 is the altitude of the flat model");
    // WHEN the solver runs in 0.01 s steps until the FMU ends the run
    let mut terminated = false;
    while !terminated {
        terminated = me.step(0.01);
        if !terminated {
            // THEN the output follows 800 - 0.81 t^2 (RK4 is exact on a parabola)
            let t = me.t;
            let r = me.instance.get_real(vr("r_nue[2]"));
            assert!((r - (800.0 - 0.5 * G * t * t)).abs() < 1e-9, "t = {t}: {r}");
        }
        assert!(me.t < 40.0, "no touchdown");
    }
    // AND the touchdown is at sqrt(800 / 0.81) = 31.42697 s, frozen in the outputs
    let exact = (800.0 / (0.5 * G)).sqrt();
    let get = |name| me.instance.get_real(vr(name));
    assert!((get("touchdown_time") - exact).abs() < 1e-9);
    assert!((get("touchdown_v_nue[2]") + G * exact).abs() < 1e-8);
    assert!(me.instance.get_boolean(vr("touchdown")));
}

#[test]
fn model_exchange_matches_co_simulation_under_thrust_and_torque() {
    // GIVEN the same plant as a CS and as an ME instance, tumbling under constant commands
    let cs = Plant::new();
    cs.enter_init();
    let mut me = model_exchange();
    let settings = [
        ("omega0_body[1]", 0.3),
        ("omega0_body[3]", -0.2),
        ("r0_nue[2]", 5000.0),
        ("thrust_cmd", 1400.0),
        ("torque_cmd_body[2]", 40.0),
    ];
    for (name, value) in settings {
        cs.set(name, value);
        assert_eq!(me.instance.set_real(vr(name), value), fmi2OK);
    }
    assert_eq!(cs.exit_init(), fmi2OK);
    me.start();
    // WHEN both run 5 s at 0.01 s
    for k in 0..500 {
        assert_eq!(cs.step(k as f64 * 0.01, 0.01), fmi2OK);
        assert!(!me.step(0.01));
    }
    // THEN the outputs agree (the same RK4 method; ME without renormalisation)
    for name in [
        "r_nue[1]",
        "r_nue[2]",
        "v_nue[2]",
        "q_body_to_nue[1]",
        "q_body_to_nue[2]",
        "q_body_to_nue[4]",
        "omega_body[1]",
        "omega_body[2]",
        "mass",
    ] {
        let (a, b) = (cs.get(name), me.instance.get_real(vr(name)));
        assert!(
            (a - b).abs() <= 1e-9 * (1.0 + a.abs()),
            "{name}: CS {a} vs ME {b}"
        );
    }
}

#[test]
fn bad_calls_are_refused_with_a_log_line_and_change_nothing() {
    let mut me = model_exchange();
    me.start();
    let c = me.instance.component();
    let before = me.x.clone();
    let mut bad = before.clone();
    bad[3] = f64::NAN;
    let mut x = vec![0.0; NX];
    // SAFETY: a live instance; the lengths are what the calls are told.
    unsafe {
        // a state vector of the wrong length, a non-finite state, a CS step on an ME instance
        assert_eq!(
            fmu::fmi2SetContinuousStates(c, before.as_ptr(), NX - 1),
            fmi2Error
        );
        assert_eq!(fmu::fmi2SetContinuousStates(c, bad.as_ptr(), NX), fmi2Error);
        assert_eq!(fmu::fmi2DoStep(c, 0.0, 0.1, fmi2True), fmi2Error);
        assert_eq!(fmu::fmi2GetContinuousStates(c, x.as_mut_ptr(), NX), fmi2OK);
    }
    assert_eq!(x, before, "refusals change nothing");
    let log = me.instance.messages().join("\n");
    assert!(
        log.contains("fmi2SetContinuousStates: 17 states given, LanderPlant has 18"),
        "{log}"
    );
    assert!(
        log.contains("state 3 (translation_state[4]) = NaN: not finite"),
        "{log}"
    );
    assert!(
        log.contains("fmi2DoStep: illegal call in state ContinuousTimeMode"),
        "{log}"
    );
    // and the instance still works
    assert!(!me.step(0.01));
}

#[test]
fn a_co_simulation_instance_refuses_the_model_exchange_functions() {
    let plant = Plant::new();
    plant.init();
    let x = [0.0; NX];
    // SAFETY: a live instance.
    unsafe {
        assert_eq!(
            fmu::fmi2SetContinuousStates(plant.component(), x.as_ptr(), NX),
            fmi2Error
        );
        assert_eq!(fmu::fmi2EnterEventMode(plant.component()), fmi2Error);
    }
    assert!(plant
        .messages()
        .iter()
        .any(|m| m.contains("fmi2SetContinuousStates: illegal call in state StepComplete")));
}
