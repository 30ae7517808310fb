//! LanderPlant through its exported C functions, as a master drives it.
use crate::common;

use common::{navigation_vrs, Plant};
use fmi_testkit::fmi2::*;

const G: f64 = 1.62;

#[test]
fn free_fall_through_the_c_api() {
    // GIVEN the default plant at 800 m, engines off
    let fmu = Plant::new();
    fmu.init();
    assert_eq!(fmu.get("r_nue[2]"), 800.0, "initial output from r0_nue");
    // WHEN stepping 10 s in 0.1 s steps
    for k in 0..100 {
        assert_eq!(fmu.step(k as f64 * 0.1, 0.1), fmi2OK);
    }
    // THEN the outputs are the parabola
    assert!((fmu.get("r_nue[2]") - (800.0 - 0.5 * G * 100.0)).abs() < 1e-9);
    assert!((fmu.get("v_nue[2]") + G * 10.0).abs() < 1e-11);
    assert_eq!(fmu.get("thrust_actual"), 0.0);
    assert_eq!(fmu.get("mass"), 900.0);
}

#[test]
fn hover_through_the_c_api() {
    // GIVEN no mass flow (isp huge) and thrust_cmd = m g
    let fmu = Plant::new();
    fmu.enter_init();
    fmu.set("isp", 1e15);
    assert_eq!(fmu.exit_init(), fmi2OK);
    fmu.set("thrust_cmd", 900.0 * G);
    // WHEN stepping 20 s
    for k in 0..2000 {
        assert_eq!(fmu.step(k as f64 * 0.01, 0.01), fmi2OK);
    }
    // THEN it stays at 800 m
    assert!((fmu.get("r_nue[2]") - 800.0).abs() < 1e-9);
    assert!((fmu.get("thrust_actual") - 900.0 * G).abs() < 1e-12);
}

#[test]
fn a_bad_parameter_fails_exit_initialization_naming_it() {
    let fmu = Plant::new();
    fmu.enter_init();
    fmu.set("m0", 500.0);
    assert_eq!(fmu.exit_init(), fmi2Error);
    let messages = fmu.messages().join("\n");
    assert!(
        messages.contains("m0") && messages.contains("dry_mass"),
        "{messages}"
    );
}

#[test]
fn fmu_state_restore_continues_bit_exactly() {
    // GIVEN a manoeuvring lander, and its FMU state saved (and serialized) at t = 1 s
    let fmu = Plant::new();
    fmu.init();
    fmu.set("thrust_cmd", 1500.0);
    fmu.set("torque_cmd_body[1]", 30.0);
    fmu.set("torque_cmd_body[3]", -12.0);
    for k in 0..100 {
        assert_eq!(fmu.step(k as f64 * 0.01, 0.01), fmi2OK);
    }
    let saved = fmu.get_state();
    let bytes = fmu.serialize(saved);
    let vrs = navigation_vrs();
    let run_on = || {
        for k in 100..300 {
            assert_eq!(fmu.step(k as f64 * 0.01, 0.01), fmi2OK);
        }
        fmu.get_many(&vrs)
    };
    // WHEN continuing three times: directly, after restoring, after deserializing
    let first = run_on();
    fmu.set_state(saved);
    let second = run_on();
    let deserialized = fmu.deserialize(&bytes);
    fmu.set_state(deserialized);
    let third = run_on();
    fmu.free_state(saved);
    fmu.free_state(deserialized);
    // THEN the three continuations are bit-identical, and the state did move
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&first), bits(&second));
    assert_eq!(bits(&first), bits(&third));
    assert!(first[1] > 800.0, "climbing at 1500 N");
}

#[test]
fn communication_step_does_not_change_the_trajectory() {
    // GIVEN the same commands, stepped with 0.1 s and with 0.01 s (sub-step 0.01 s)
    let run = |h: f64| {
        let fmu = Plant::new();
        fmu.init();
        fmu.set("thrust_cmd", 1300.0);
        fmu.set("torque_cmd_body[1]", 5.0);
        fmu.set("torque_cmd_body[2]", 40.0);
        fmu.set("torque_cmd_body[3]", -3.0);
        let n = (10.0 / h).round() as usize;
        for k in 0..n {
            assert_eq!(fmu.step(k as f64 * h, h), fmi2OK);
        }
        fmu.get_many(&navigation_vrs())
    };
    let coarse = run(0.1);
    let fine = run(0.01);
    // THEN both see the same RK4 sub-steps: equal up to round-off
    for (a, b) in coarse.iter().zip(&fine) {
        assert!(
            (a - b).abs() <= 1e-9 * (1.0 + a.abs()),
            "{coarse:?}\n{fine:?}"
        );
    }
    // and a step that does not divide into sub-steps (0.015 s: 0.01 + 0.005) only adds the
    // RK4 truncation error of the shorter sub-steps
    let odd = {
        let fmu = Plant::new();
        fmu.init();
        fmu.set("thrust_cmd", 1300.0);
        fmu.set("torque_cmd_body[1]", 5.0);
        fmu.set("torque_cmd_body[2]", 40.0);
        fmu.set("torque_cmd_body[3]", -3.0);
        let mut t: f64 = 0.0;
        while t < 10.0 - 1e-9 {
            let h = (10.0 - t).min(0.015);
            assert_eq!(fmu.step(t, h), fmi2OK);
            t += h;
        }
        fmu.get_many(&navigation_vrs())
    };
    for (a, b) in odd.iter().zip(&fine) {
        assert!((a - b).abs() <= 1e-7 * (1.0 + a.abs()), "{odd:?}\n{fine:?}");
    }
}

#[test]
fn touchdown_ends_the_step_with_discard_at_the_crossing() {
    // GIVEN a lander 20 m up, descending at 2 m/s, engines at minimum (720 N < weight)
    let fmu = Plant::new();
    fmu.enter_init();
    fmu.set("r0_nue[2]", 20.0);
    fmu.set("v0_nue[2]", -2.0);
    fmu.set("isp", 1e15);
    assert_eq!(fmu.exit_init(), fmi2OK);
    fmu.set("thrust_cmd", 720.0);
    let a = 720.0 / 900.0 - G;
    let t_exact = (-2.0 + (4.0 + 2.0 * -a * 20.0f64).sqrt()) / -a;
    // WHEN stepping with 0.25 s until the FMU refuses
    let mut t = 0.0;
    let status = loop {
        let s = fmu.step(t, 0.25);
        if s != fmi2OK {
            break s;
        }
        t += 0.25;
        assert!(t < 100.0);
    };
    // THEN fmi2Discard, the last successful time is the crossing, and it is terminated
    assert_eq!(status, fmi2Discard);
    assert!((fmu.last_successful_time() - t_exact).abs() < 1e-9);
    assert!(fmu.terminated());
    assert!(fmu.get_boolean("touchdown"));
    assert!((fmu.get("touchdown_time") - t_exact).abs() < 1e-9);
    assert!((fmu.get("touchdown_v_nue[2]") - (-2.0 + a * t_exact)).abs() < 1e-8);
    assert_eq!(fmu.get("touchdown_q_body_to_nue[1]"), 1.0);
    assert_eq!(fmu.get("touchdown_tilt"), 0.0);
    assert!(fmu.get("altitude").abs() < 1e-8);
}

#[test]
fn propellant_exhaustion_raises_the_flag_and_warns() {
    let fmu = Plant::new();
    fmu.enter_init();
    fmu.set("m0", 600.2);
    assert_eq!(fmu.exit_init(), fmi2OK);
    fmu.set("thrust_cmd", 1600.0);
    let mut statuses = Vec::new();
    for k in 0..10 {
        statuses.push(fmu.step(k as f64 * 0.1, 0.1));
    }
    assert!(statuses.contains(&fmi2Warning), "{statuses:?}");
    assert!(fmu.get_boolean("propellant_exhausted"));
    assert_eq!(fmu.get("mass"), 600.0);
    assert_eq!(fmu.get("thrust_actual"), 0.0);
    assert!((fmu.get("propellant_used") - 0.2).abs() < 1e-12);
}

#[test]
fn spherical_model_is_selectable_and_starts_at_the_same_place() {
    let fmu = Plant::new();
    fmu.enter_init();
    fmu.set_integer("translation_model", 2);
    assert_eq!(fmu.exit_init(), fmi2OK);
    assert!((fmu.get("r_nue[2]") - 800.0).abs() < 1e-6);
    assert!((fmu.get("altitude") - 800.0).abs() < 1e-6);
    for k in 0..100 {
        assert_eq!(fmu.step(k as f64 * 0.1, 0.1), fmi2OK);
    }
    // A free fall over 10 s: the same as the flat one to millimetres at this height.
    assert!((fmu.get("r_nue[2]") - (800.0 - 0.5 * G * 100.0)).abs() < 0.1);
}

/// The delivered actuation is computed when first read after a change (not at every get);
/// a stale one would show after a new command, a step, or a get of other outputs between.
#[test]
fn delivered_outputs_follow_every_command_and_step() {
    let fmu = Plant::new();
    fmu.init();
    let limit = fmu.get("rcs_torque_limit");
    for (k, (thrust, torque)) in [(1000.0, 0.5), (1500.0, -3.0), (0.0, 1e6), (1200.0, 0.0)]
        .into_iter()
        .enumerate()
    {
        fmu.set("thrust_cmd", thrust);
        fmu.set("torque_cmd_body[2]", torque);
        // A get of a navigation output first, then the delivered ones.
        assert_eq!(fmu.get("mass"), fmu.get("m0") - fmu.get("propellant_used"));
        assert_eq!(
            fmu.get("torque_actual_body[2]"),
            torque.clamp(-limit, limit),
            "round {k}"
        );
        let thrust_shown = fmu.get("thrust_actual");
        assert!(
            thrust_shown == 0.0 || (thrust_shown - thrust).abs() <= 1e-9 * thrust,
            "round {k}: {thrust_shown} for {thrust}"
        );
        let before_step = fmu.get("engine_torque_body[1]");
        assert_eq!(fmu.step(k as f64, 1.0), fmi2OK);
        assert_eq!(
            fmu.get("torque_actual_body[2]"),
            torque.clamp(-limit, limit)
        );
        assert_eq!(
            fmu.get("engine_torque_body[1]"),
            before_step,
            "no misalignment"
        );
    }
}
