//! LanderFilter through its exported C functions, as a master drives it (the workspace's test
//! kit), fed with error-free measurements of a descent: an estimate that follows the truth,
//! the body rate's feedthrough, FMU-state save/restore and serialization, parameters refused
//! together. What every FMU owes (description drift, bounds, non-finite values) is
//! tests/conformance.rs.
//!
//! LanderSensors is not linked here: two FMU crates in one binary would share one set of
//! `fmi2*` symbols.
use fmi_testkit::fmi2::*;
use fmi_testkit::{fmi2_functions, Fmi2Functions, Instance};
use fmu_filter::model::rotation::matrix;
use fmu_filter::model::FilterParameters;
use fmu_filter::LanderFilter;
use nalgebra::Vector3;

static FUNCTIONS: Fmi2Functions = fmi2_functions!(fmu_filter);
const H: f64 = 0.01;

fn vr(name: &str) -> u32 {
    fmi2_export::variables::<LanderFilter>()
        .iter()
        .find(|v| v.name() == name)
        .unwrap_or_else(|| panic!("no variable {name}"))
        .value_reference
}

fn vrs(names: &[String]) -> Vec<u32> {
    names.iter().map(|n| vr(n)).collect()
}

fn elements(base: &str, n: usize) -> Vec<String> {
    (1..=n).map(|i| format!("{base}[{i}]")).collect()
}

/// The Real inputs in the order they are set.
fn real_inputs() -> Vec<String> {
    let mut v = elements("accel_body_meas", 3);
    v.extend(elements("gyro_body_meas", 3));
    v.push("altimeter_range".into());
    v.extend(elements("velocimeter_los_velocity", 3));
    v
}

const VALID: [&str; 4] = [
    "altimeter_valid",
    "velocimeter_valid_1",
    "velocimeter_valid_2",
    "velocimeter_valid_3",
];

/// The estimate: position, velocity, attitude, rate, covariance diagonal, NIS.
fn outputs() -> Vec<String> {
    let mut v = elements("r_nue", 3);
    v.extend(elements("v_nue", 3));
    v.extend(elements("q_body_to_nue", 4));
    v.extend(elements("omega_body", 3));
    v.extend(elements("covariance_diag", 15));
    v.extend(["nis_altimeter".to_string(), "nis_velocimeter".to_string()]);
    v
}

/// The true state at step `k`: a slow upright descent from 800 m at constant velocity,
/// rolling about the thrust axis.
struct Truth {
    r_nue_m: [f64; 3],
    v_nue_mps: [f64; 3],
    q_body_to_nue: [f64; 4],
}

fn truth(k: usize) -> Truth {
    let t = k as f64 * H;
    let half = 0.01 * t;
    Truth {
        r_nue_m: [2.0 * t, 800.0 - 8.0 * t, 0.0],
        v_nue_mps: [2.0, -8.0, 0.0],
        q_body_to_nue: [libm::cos(half), 0.0, libm::sin(half), 0.0],
    }
}

/// Error-free measurements of the truth at step `k`, as LanderSensors with every error off:
/// (Real inputs in `real_inputs` order, validity flags). Upright, the altimeter reads the
/// altitude.
fn measure(k: usize) -> (Vec<f64>, [bool; 4]) {
    let t = truth(k);
    let mut reals = vec![0.0, 1.62, 0.0, 0.0, 0.02, 0.0, t.r_nue_m[1]];
    let rotation = matrix(&t.q_body_to_nue);
    for b in FilterParameters::default().velocimeter_beams_body() {
        reals.push(Vector3::from(t.v_nue_mps).dot(&(rotation * Vector3::from(b))));
    }
    (reals, [true; 4])
}

fn instance() -> Instance {
    Instance::instantiate(&FUNCTIONS, "filter", &fmi2_export::guid::<LanderFilter>())
}

fn started() -> Instance {
    let fmu = instance();
    fmu.enter_init();
    for (i, x) in [0.0, 805.0, 3.0].iter().enumerate() {
        assert_eq!(fmu.set_real(vr(&format!("r0_nue[{}]", i + 1)), *x), fmi2OK);
    }
    for (i, x) in [2.0, -8.0, 0.0].iter().enumerate() {
        assert_eq!(fmu.set_real(vr(&format!("v0_nue[{}]", i + 1)), *x), fmi2OK);
    }
    assert_eq!(
        fmu.exit_initialization_mode(),
        fmi2OK,
        "{:?}",
        fmu.messages()
    );
    fmu
}

/// Feeds the measurements of steps `k0..k1`; the outputs (bits) read at each point.
fn fly(fmu: &Instance, k0: usize, k1: usize) -> Vec<Vec<u64>> {
    let mut out = Vec::new();
    for k in k0..k1 {
        let (reals, valid) = measure(k);
        assert_eq!(fmu.set_reals(&vrs(&real_inputs()), &reals), fmi2OK);
        for (name, v) in VALID.iter().zip(valid) {
            assert_eq!(fmu.set_boolean(vr(name), v), fmi2OK);
        }
        let (status, values) = fmu.get_reals(&vrs(&outputs()));
        assert_eq!(status, fmi2OK, "{:?}", fmu.messages());
        out.push(values.iter().map(|v| v.to_bits()).collect());
        assert_eq!(fmu.do_step(k as f64 * H, H), fmi2OK, "{:?}", fmu.messages());
    }
    out
}

#[test]
fn the_estimate_follows_the_truth_within_its_covariance() {
    let fmu = started();
    let run = fly(&fmu, 0, 2000);
    let last = run.last().unwrap();
    let y: Vec<f64> = last.iter().map(|b| f64::from_bits(*b)).collect();
    let t = truth(1999);
    // Up and the velocity are observed: within 4 sigma of the truth, and tighter than at the start.
    let sigma = |i: usize| y[13 + i].sqrt();
    assert!(
        (y[1] - t.r_nue_m[1]).abs() < 4.0 * sigma(1),
        "{} vs {}",
        y[1],
        t.r_nue_m[1]
    );
    for i in 0..3 {
        assert!(
            (y[3 + i] - t.v_nue_mps[i]).abs() < 4.0 * sigma(3 + i),
            "v {i}"
        );
        assert!(sigma(3 + i) < 0.1, "velocity sigma {i}: {}", sigma(3 + i));
    }
    assert!(sigma(1) < 1.0, "{}", sigma(1));
    assert!(y.iter().all(|v| v.is_finite()));
    // The NIS outputs are those of the last step's update.
    assert!(y[28] > 0.0 && y[29] > 0.0);
    assert_eq!(fmu.get_integer(vr("altimeter_dof")), 1);
    assert_eq!(fmu.get_integer(vr("velocimeter_dof")), 3);
    assert_eq!(fmu.get_integer(vr("measurements_rejected")), 0);
}

#[test]
fn the_body_rate_is_the_gyro_less_the_bias_estimate_at_once() {
    let fmu = started();
    let gyro = vrs(&elements("gyro_body_meas", 3));
    assert_eq!(fmu.set_reals(&gyro, &[0.1, -0.2, 0.3]), fmi2OK);
    let (_, bias) = fmu.get_reals(&vrs(&elements("gyro_bias_estimate", 3)));
    let (_, omega) = fmu.get_reals(&vrs(&elements("omega_body", 3)));
    for i in 0..3 {
        assert_eq!(omega[i], [0.1, -0.2, 0.3][i] - bias[i]);
    }
}

#[test]
fn save_restore_and_serialization_reproduce_the_continuation_bit_for_bit() {
    let fmu = started();
    fly(&fmu, 0, 30);
    let state = fmu.get_state();
    let bytes = fmu.serialize(state);
    let continuation = fly(&fmu, 30, 80);
    assert_eq!(fmu.set_state(state), fmi2OK, "{:?}", fmu.messages());
    assert_eq!(fly(&fmu, 30, 80), continuation);
    assert_eq!(fmu.free_state(state), fmi2OK);
    let other = started();
    let (status, restored) = other.deserialize(&bytes);
    assert_eq!(status, fmi2OK, "{:?}", other.messages());
    assert_eq!(other.set_state(restored), fmi2OK, "{:?}", other.messages());
    assert_eq!(fly(&other, 30, 80), continuation);
    assert_eq!(other.free_state(restored), fmi2OK);
}

#[test]
fn a_non_unit_initial_attitude_or_a_zero_terrain_normal_fails_initialization_by_name() {
    let fmu = instance();
    fmu.enter_init();
    assert_eq!(fmu.set_real(vr("q0_body_to_nue[1]"), 0.5), fmi2OK);
    let (status, values) = fmu.get_reals(&vrs(&outputs()));
    assert_eq!(status, fmi2Warning);
    assert!(values.iter().all(|v| v.is_finite()));
    assert_eq!(fmu.exit_initialization_mode(), fmi2Error);
    assert!(
        fmu.messages().join("\n").contains("q0_body_to_nue"),
        "{:?}",
        fmu.messages()
    );

    let fmu = instance();
    fmu.enter_init();
    for i in 1..=3 {
        assert_eq!(
            fmu.set_real(vr(&format!("terrain_slope_normal_nue[{i}]")), 0.0),
            fmi2OK
        );
    }
    assert_eq!(fmu.exit_initialization_mode(), fmi2Error);
    assert!(
        fmu.messages()
            .join("\n")
            .contains("terrain_slope_normal_nue"),
        "{:?}",
        fmu.messages()
    );
}
