//! LanderGnc through its exported C functions: table defaults, timing, degenerate inputs,
//! parameters refused together, FMU-state save/restore. What every FMU owes (description
//! drift, bounds) is tests/conformance.rs.
// std's transcendental functions here are a reference independent of the libm the model uses.
#![allow(clippy::disallowed_methods)]
use crate::fmi;

use fmi::{vr, Gnc};
use fmi2_export::Causality;
use fmi_testkit::fmi2::*;
use fmu_gnc::LanderGnc;

const UPRIGHT: [f64; 4] = [1.0, 0.0, 0.0, 0.0];

#[test]
fn the_interface_names_are_all_declared() {
    let names: Vec<_> = fmi2_export::variables::<LanderGnc>()
        .iter()
        .map(|v| v.name())
        .collect();
    for required in [
        "r_nue[1]",
        "v_nue[3]",
        "q_body_to_nue[4]",
        "omega_body[2]",
        "mass",
        "thrust_cmd",
        "torque_cmd_body[3]",
        "control_law",
        "phi_cmd",
        "phi_cmd_time",
        "a_cmd_nue[2]",
        "q_ref[4]",
        "phi_b",
        "err_roll",
        "err_yaw",
        "err_pitch",
        "tilt_error",
        "guidance_phase",
        "time_to_go",
    ] {
        assert!(
            names.iter().any(|n| n == required),
            "INTERFACE name {required} missing"
        );
    }
    let inputs = fmi2_export::variables::<LanderGnc>()
        .iter()
        .filter(|v| v.causality == Causality::Input)
        .count();
    assert_eq!(inputs, 14);
}

#[test]
fn hover_then_descent_with_direct_feedthrough() {
    let gnc = Gnc::new();
    // The inputs below are no flight: they ignore the commands (and the torque read for
    // the tilted attitude stays the last one shown, at its limit).
    assert_eq!(gnc.set_boolean(vr::INPUT_MONITOR, false), fmi2OK);
    assert_eq!(gnc.set_reals(&[vr::SATURATION_TIME], &[1e6]), fmi2OK);
    assert_eq!(gnc.initialize(), fmi2OK);
    // GIVEN upright at rest on the hover target
    gnc.set_navigation([0.0, 800.0, 0.0], [0.0; 3], UPRIGHT, [0.0; 3], 900.0);
    let (status, out) = gnc.get_reals(&[vr::THRUST_CMD]);
    assert_eq!(status, fmi2OK);
    assert!(
        (out[0] - 900.0 * 1.62).abs() < 1e-9,
        "hover thrust {}",
        out[0]
    );
    // WHEN the attitude input changes, THEN the torque output follows without a step
    let tilted = [(0.05f64).cos(), 0.0, 0.0, (0.05f64).sin()];
    gnc.set_navigation([0.0, 800.0, 0.0], [0.0; 3], tilted, [0.0; 3], 900.0);
    let (_, torque) = gnc.get_reals(&vr::TORQUE_CMD_BODY);
    assert!(
        torque[2] < -1.0,
        "pitch torque against a +z tilt: {torque:?}"
    );
    // WHEN stepping with a master that accumulates t += h
    let mut t = 0.0;
    for _ in 0..1200 {
        gnc.set_navigation([0.0, 800.0, 0.0], [0.0; 3], UPRIGHT, [0.0; 3], 900.0);
        assert_eq!(gnc.do_step(t, 0.01), fmi2OK);
        t += 0.01;
    }
    // THEN at t = 11.99999999999979 the descent has started, with tgo = 130 s
    assert!(t < 12.0);
    gnc.set_navigation([0.0, 800.0, 0.0], [0.0; 3], UPRIGHT, [0.0; 3], 900.0);
    let (_, tgo) = gnc.get_reals(&[vr::TIME_TO_GO]);
    assert_eq!(gnc.get_integer(vr::GUIDANCE_PHASE), 2);
    assert!((tgo[0] - 130.0).abs() < 1e-9);
    // AND the command accelerates downward: thrust below weight
    let (_, thrust) = gnc.get_reals(&[vr::THRUST_CMD]);
    assert!(thrust[0] < 900.0 * 1.62, "{}", thrust[0]);
}

#[test]
fn degenerate_first_inputs_warn_and_command_safe_outputs() {
    let gnc = Gnc::new();
    assert_eq!(gnc.initialize(), fmi2OK);
    // GIVEN a master that zeroes every input before the first exchange
    gnc.set_navigation([0.0; 3], [0.0; 3], [0.0; 4], [0.0; 3], 0.0);
    let (status, out) = gnc.get_reals(&[vr::THRUST_CMD, 101, 102, 103]);
    // THEN the get warns, and the outputs are minimum thrust and zero torque
    assert_eq!(status, fmi2Warning);
    assert_eq!(out, vec![720.0, 0.0, 0.0, 0.0]);
    // (the step meets the same fault: counted, not logged again, so OK)
    assert_eq!(gnc.do_step(0.0, 0.01), fmi2OK);
    assert!(gnc.messages().iter().any(|m| m.contains("q_body_to_nue")));
    // AND with real inputs the next step is fine
    gnc.set_navigation([0.0, 800.0, 0.0], [0.0; 3], UPRIGHT, [0.0; 3], 900.0);
    assert_eq!(gnc.do_step(0.01, 0.01), fmi2OK);
    let (status, out) = gnc.get_reals(&vr::ALL_REAL_OUTPUTS);
    assert_eq!(status, fmi2OK);
    assert!(out.iter().all(|x| x.is_finite()));
}

#[test]
fn bad_parameters_are_refused_at_initialization_naming_them() {
    // GIVEN thrust_min above thrust_max, each within its own bounds
    let gnc = Gnc::new();
    let thrust_min = 211;
    assert_eq!(gnc.set_reals(&[thrust_min], &[2000.0]), fmi2OK);
    // THEN initialization refuses it, naming the declared variable (not the Rust field)
    assert_eq!(gnc.initialize(), fmi2Error);
    assert!(
        gnc.messages()
            .iter()
            .any(|m| m.contains("parameter thrust_max = 1600")),
        "{:?}",
        gnc.messages()
    );
}

fn scenario_inputs(k: usize) -> ([f64; 3], [f64; 3], [f64; 4], [f64; 3]) {
    // A made-up but smooth navigation history with tilt and rates, distinct at every step.
    let s = k as f64 * 0.01;
    let half = 0.1 * (0.3 * s).sin();
    (
        [0.5 * s.sin(), 800.0 - 0.2 * s * s, 0.1 * s],
        [0.5 * s.cos(), -0.4 * s, 0.1],
        [half.cos(), 0.3 * half.sin(), 0.0, 0.95 * half.sin()],
        [0.01 * s.cos(), 0.02, -0.01],
    )
}

fn run(gnc: &Gnc, from: usize, to: usize) -> Vec<Vec<f64>> {
    let mut outputs = Vec::new();
    for k in from..to {
        let (r, v, q, w) = scenario_inputs(k);
        gnc.set_navigation(r, v, q, w, 900.0 - k as f64 * 0.01);
        let (status, out) = gnc.get_reals(&vr::ALL_REAL_OUTPUTS);
        assert_eq!(status, fmi2OK);
        outputs.push(out);
        assert_eq!(gnc.do_step(k as f64 * 0.01, 0.01), fmi2OK);
    }
    outputs
}

fn bits(runs: &[Vec<f64>]) -> Vec<u64> {
    runs.iter().flatten().map(|x| x.to_bits()).collect()
}

#[test]
fn fmu_state_save_restore_and_serialization_are_bit_exact() {
    save_restore_and_serialization_are_bit_exact(false);
}

#[test]
fn a_shaped_manoeuvre_in_progress_is_saved_restored_and_serialized_bit_exactly() {
    save_restore_and_serialization_are_bit_exact(true);
}

/// The phi_rate_limit and phi_accel_limit parameters.
const PHI_PROFILE_LIMITS: [u32; 2] = [230, 231];

fn save_restore_and_serialization_are_bit_exact(shaped: bool) {
    let gnc = Gnc::new();
    // The made-up navigation history is no flight: it ignores the commands.
    assert_eq!(gnc.set_boolean(vr::INPUT_MONITOR, false), fmi2OK);
    assert_eq!(gnc.set_integer(vr::CONTROL_LAW, 1), fmi2OK);
    assert_eq!(gnc.set_reals(&[vr::PHI_CMD], &[2.6]), fmi2OK);
    if shaped {
        // a manoeuvre of about 3 s from 12 s: in progress when the replays end
        assert_eq!(gnc.set_reals(&PHI_PROFILE_LIMITS, &[1.0, 1.0]), fmi2OK);
    }
    assert_eq!(gnc.initialize(), fmi2OK);
    // GIVEN a run up to just before the phase change and phi_cmd step at 12 s
    run(&gnc, 0, 1190);
    let saved = gnc.get_state();
    // WHEN the run goes on across guidance cycles, the phase change and the phi_cmd step
    // (and the start of the shaped manoeuvre)
    let first = run(&gnc, 1190, 1260);
    // AND the state is restored and the same inputs replayed
    assert_eq!(gnc.set_state(saved), fmi2OK);
    let second = run(&gnc, 1190, 1260);
    // THEN every output is bit-identical
    assert_eq!(bits(&first), bits(&second));

    // AND a serialized copy, restored into a fresh instance, replays bit-identically too
    let bytes = gnc.serialize(saved);
    let other = Gnc::new();
    assert_eq!(other.set_boolean(vr::INPUT_MONITOR, false), fmi2OK);
    if shaped {
        assert_eq!(other.set_reals(&PHI_PROFILE_LIMITS, &[1.0, 1.0]), fmi2OK);
    }
    assert_eq!(other.initialize(), fmi2OK);
    let (status, restored) = other.deserialize(&bytes);
    assert_eq!(status, fmi2OK);
    assert_eq!(other.set_state(restored), fmi2OK);
    let third = run(&other, 1190, 1260);
    assert_eq!(bits(&first), bits(&third));
    assert_eq!(gnc.free_state(saved), fmi2OK);
    assert_eq!(other.free_state(restored), fmi2OK);
}

/// The norm stated in a "used normalised" warning, if any.
fn stated_norm(messages: &[String]) -> Option<f64> {
    let m = messages.iter().find(|m| m.contains("used normalised"))?;
    let after = m.split("has norm ").nth(1)?;
    after.split(',').next()?.parse().ok()
}

#[test]
fn a_quaternion_far_from_unit_norm_is_normalised_with_a_warning_stating_its_norm() {
    // GIVEN a tilted attitude, as a unit quaternion and scaled far from unit norm either way,
    // up to components whose squares overflow
    let unit = [0.6, 0.0, 0.0, 0.8];
    let outputs = |scale: f64| {
        let gnc = Gnc::new();
        assert_eq!(gnc.initialize(), fmi2OK);
        let q = unit.map(|c| c * scale);
        gnc.set_navigation([0.0, 800.0, 0.0], [0.0; 3], q, [0.0; 3], 900.0);
        let (status, out) = gnc.get_reals(&vr::ALL_REAL_OUTPUTS);
        (status, out, gnc.messages())
    };
    let (status, reference, messages) = outputs(1.0);
    assert_eq!(status, fmi2OK, "{messages:?}");
    assert_eq!(stated_norm(&messages), None);
    for scale in [1e300, 1e160, 3.0, 1.01, 0.98, 1e-3, 2e-6] {
        // WHEN the GNC reads it
        let (status, out, messages) = outputs(scale);
        // THEN the get warns, stating the norm
        assert_eq!(status, fmi2Warning, "scale {scale}");
        let norm = stated_norm(&messages).unwrap_or_else(|| panic!("{messages:?}"));
        assert!((norm / scale - 1.0).abs() < 1e-15, "{norm} for {scale}");
        // AND commands as for the unit quaternion
        for (a, b) in out.iter().zip(&reference) {
            assert!(
                (a - b).abs() <= 1e-12 * (1.0 + b.abs()),
                "scale {scale}: {a} vs {b}"
            );
        }
    }
    // AND a quaternion within the tolerance of unit norm is used silently
    let (status, _, _) = outputs(1.0 + 0.5 * fmu_gnc::controller::QUATERNION_NORM_TOLERANCE);
    assert_eq!(status, fmi2OK);
}
