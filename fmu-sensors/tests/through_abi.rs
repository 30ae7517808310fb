//! LanderSensors through its exported C functions, as a master drives it (the workspace's test
//! kit): measurements of the truth with direct feedthrough, reads that never change the sequence, reproducibility from the seed,
//! FMU-state save/restore and serialization, refused inputs and parameters refused
//! together. What every FMU owes (description drift, bounds) is tests/conformance.rs.
use fmi_testkit::fmi2::*;
use fmi_testkit::{fmi2_functions, Fmi2Functions, Instance};
use fmu_sensors::LanderSensors;

static FUNCTIONS: Fmi2Functions = fmi2_functions!(fmu_sensors);
const H: f64 = 0.01;

fn vr(name: &str) -> u32 {
    fmi2_export::variables::<LanderSensors>()
        .iter()
        .find(|v| v.name() == name)
        .unwrap_or_else(|| panic!("no variable {name}"))
        .value_reference
}

fn vrs(names: &[&str]) -> Vec<u32> {
    names.iter().map(|n| vr(n)).collect()
}

const INPUTS: [&str; 16] = [
    "r_nue[1]",
    "r_nue[2]",
    "r_nue[3]",
    "v_nue[1]",
    "v_nue[2]",
    "v_nue[3]",
    "q_body_to_nue[1]",
    "q_body_to_nue[2]",
    "q_body_to_nue[3]",
    "q_body_to_nue[4]",
    "omega_body[1]",
    "omega_body[2]",
    "omega_body[3]",
    "specific_force_body[1]",
    "specific_force_body[2]",
    "specific_force_body[3]",
];

const OUTPUTS: [&str; 10] = [
    "accel_body_meas[1]",
    "accel_body_meas[2]",
    "accel_body_meas[3]",
    "gyro_body_meas[1]",
    "gyro_body_meas[2]",
    "gyro_body_meas[3]",
    "altimeter_range",
    "velocimeter_los_velocity[1]",
    "velocimeter_los_velocity[2]",
    "velocimeter_los_velocity[3]",
];

const VALID: [&str; 4] = [
    "altimeter_valid",
    "velocimeter_valid_1",
    "velocimeter_valid_2",
    "velocimeter_valid_3",
];

/// The truth at step `k`: descending upright, slowly rolling about the thrust axis.
fn truth(k: usize) -> Vec<f64> {
    let s = k as f64 * H;
    let half = 0.05 * s;
    vec![
        10.0 + s,
        800.0 - 5.0 * s,
        -3.0,
        1.0,
        -5.0,
        0.0,
        libm::cos(half),
        0.0,
        libm::sin(half),
        0.0,
        0.0,
        0.1,
        0.0,
        0.0,
        1.62,
        0.0,
    ]
}

fn instance() -> Instance {
    Instance::instantiate(&FUNCTIONS, "sensors", &fmi2_export::guid::<LanderSensors>())
}

fn set_real(fmu: &Instance, name: &str, value: f64) {
    assert_eq!(
        fmu.set_real(vr(name), value),
        fmi2OK,
        "{name}: {:?}",
        fmu.messages()
    );
}

/// The defaults with a seed and dropouts.
fn noisy(seed: i32) -> Instance {
    let fmu = instance();
    fmu.enter_init();
    assert_eq!(fmu.set_integer(vr("seed"), seed), fmi2OK);
    set_real(&fmu, "altimeter_dropout_probability", 0.1);
    set_real(&fmu, "velocimeter_dropout_probability", 0.1);
    assert_eq!(
        fmu.exit_initialization_mode(),
        fmi2OK,
        "{:?}",
        fmu.messages()
    );
    fmu
}

/// Outputs (bits) and validity flags.
fn get_all(fmu: &Instance) -> (Vec<u64>, Vec<bool>) {
    let (status, values) = fmu.get_reals(&vrs(&OUTPUTS));
    assert_eq!(status, fmi2OK, "{:?}", fmu.messages());
    let valid = VALID.iter().map(|n| fmu.get_boolean(vr(n))).collect();
    (values.iter().map(|v| v.to_bits()).collect(), valid)
}

fn fly(fmu: &Instance, k0: usize, k1: usize) -> Vec<(Vec<u64>, Vec<bool>)> {
    (k0..k1)
        .map(|k| {
            assert_eq!(fmu.set_reals(&vrs(&INPUTS), &truth(k)), fmi2OK);
            let out = get_all(fmu);
            assert_eq!(fmu.do_step(k as f64 * H, H), fmi2OK, "{:?}", fmu.messages());
            out
        })
        .collect()
}

#[test]
fn with_the_defaults_the_measurements_are_near_the_truth_at_once() {
    let fmu = instance();
    fmu.enter_init();
    assert_eq!(fmu.exit_initialization_mode(), fmi2OK);
    for k in 0..50 {
        let x = truth(k);
        assert_eq!(fmu.set_reals(&vrs(&INPUTS), &x), fmi2OK);
        let (bits, valid) = get_all(&fmu);
        let y: Vec<f64> = bits.iter().map(|b| f64::from_bits(*b)).collect();
        assert!(valid.iter().all(|v| *v), "step {k}: {valid:?}");
        // Specific force and rate within a few sigma of bias and noise.
        assert!(
            (y[1] - 1.62).abs() < 0.05 && (y[4] - 0.1).abs() < 1e-3,
            "{y:?}"
        );
        // Upright: the altimeter reads the altitude (0.1 m + 0.1 % noise).
        assert!((y[6] - x[1]).abs() < 5.0, "step {k}: {} vs {}", y[6], x[1]);
        assert_eq!(fmu.do_step(k as f64 * H, H), fmi2OK);
    }
}

#[test]
fn reads_between_steps_never_change_the_measurements() {
    let (read, bare) = (noisy(5), noisy(5));
    for k in 0..100 {
        for _ in 0..3 {
            assert_eq!(read.set_reals(&vrs(&INPUTS), &truth(k + 50)), fmi2OK);
            get_all(&read);
        }
        for fmu in [&read, &bare] {
            assert_eq!(fmu.set_reals(&vrs(&INPUTS), &truth(k)), fmi2OK);
        }
        assert_eq!(get_all(&read), get_all(&bare), "step {k}");
        for fmu in [&read, &bare] {
            assert_eq!(fmu.do_step(k as f64 * H, H), fmi2OK);
        }
    }
}

#[test]
fn the_seed_reproduces_the_run_and_another_seed_changes_it() {
    let run = fly(&noisy(1), 0, 100);
    assert_eq!(run, fly(&noisy(1), 0, 100));
    assert_ne!(run, fly(&noisy(2), 0, 100));
    // Dropouts happen, and not always.
    let lost = run.iter().filter(|(_, valid)| !valid[0]).count();
    assert!(lost > 0 && lost < 50, "{lost}");
}

#[test]
fn save_restore_and_serialization_reproduce_the_continuation_bit_for_bit() {
    let fmu = noisy(9);
    fly(&fmu, 0, 30);
    let state = fmu.get_state();
    let bytes = fmu.serialize(state);
    let continuation = fly(&fmu, 30, 80);
    assert_eq!(fmu.set_state(state), fmi2OK, "{:?}", fmu.messages());
    assert_eq!(fly(&fmu, 30, 80), continuation);
    assert_eq!(fmu.free_state(state), fmi2OK);
    let other = noisy(1);
    let (status, restored) = other.deserialize(&bytes);
    assert_eq!(status, fmi2OK, "{:?}", other.messages());
    assert_eq!(other.set_state(restored), fmi2OK, "{:?}", other.messages());
    assert_eq!(fly(&other, 30, 80), continuation);
    assert_eq!(other.free_state(restored), fmi2OK);
}

#[test]
fn a_zero_terrain_normal_fails_initialization_naming_the_variable() {
    let fmu = instance();
    fmu.enter_init();
    for i in 1..=3 {
        set_real(&fmu, &format!("terrain_slope_normal_nue[{i}]"), 0.0);
    }
    assert_eq!(fmu.exit_initialization_mode(), fmi2Error);
    let messages = fmu.messages().join("\n");
    assert!(messages.contains("terrain_slope_normal_nue"), "{messages}");
}

#[test]
fn a_non_unit_quaternion_warns_on_read_and_fails_the_step_never_showing_nan() {
    let fmu = noisy(3);
    let mut x = truth(0);
    x[6] = 0.5;
    assert_eq!(fmu.set_reals(&vrs(&INPUTS), &x), fmi2OK);
    let (status, values) = fmu.get_reals(&vrs(&OUTPUTS));
    assert_eq!(status, fmi2Warning, "{:?}", fmu.messages());
    assert!(values.iter().all(|v| v.is_finite()));
    assert!(
        fmu.last_message().contains("q_body_to_nue"),
        "{:?}",
        fmu.messages()
    );
    assert_ne!(fmu.do_step(0.0, H), fmi2OK);
    assert!(
        fmu.last_message().contains("q_body_to_nue"),
        "{:?}",
        fmu.messages()
    );
    // A NaN input is refused at the set.
    assert_eq!(fmu.set_real(vr("v_nue[2]"), f64::NAN), fmi2Error);
}

#[test]
fn an_altimeter_or_velocimeter_failure_thrown_mid_run_invalidates_its_samples_until_mended() {
    // GIVEN the defaults (no dropouts) and a twin flown without any failure
    let fmu = instance();
    let twin = instance();
    for f in [&fmu, &twin] {
        f.enter_init();
        assert_eq!(f.exit_initialization_mode(), fmi2OK);
    }
    let nominal = fly(&twin, 0, 40);
    assert!(nominal.iter().all(|(_, valid)| valid.iter().all(|&v| v)));
    let mut got = fly(&fmu, 0, 10);
    // WHEN the altimeter fails at step 10, the velocimeter at step 20, both mended at 30
    assert_eq!(fmu.set_boolean(vr("altimeter_available"), false), fmi2OK);
    got.extend(fly(&fmu, 10, 20));
    assert_eq!(fmu.set_boolean(vr("velocimeter_available"), false), fmi2OK);
    got.extend(fly(&fmu, 20, 30));
    assert_eq!(fmu.set_boolean(vr("altimeter_available"), true), fmi2OK);
    assert_eq!(fmu.set_boolean(vr("velocimeter_available"), true), fmi2OK);
    got.extend(fly(&fmu, 30, 40));
    for (k, ((values, valid), (nominal_values, _))) in got.iter().zip(&nominal).enumerate() {
        let altimeter_out = (10..30).contains(&k);
        let velocimeter_out = (20..30).contains(&k);
        // THEN a failed sensor's samples are invalid and read 0
        assert_eq!(valid[0], !altimeter_out, "step {k}");
        assert!(valid[1..].iter().all(|&v| v != velocimeter_out), "step {k}");
        if altimeter_out {
            assert_eq!(values[6], 0);
        }
        if velocimeter_out {
            assert!(values[7..].iter().all(|&v| v == 0), "step {k}");
        }
        // AND every other measurement is the twin's to the bit: a failure draws nothing
        for i in (0..10).filter(|&i| !(altimeter_out && i == 6 || velocimeter_out && i >= 7)) {
            assert_eq!(values[i], nominal_values[i], "step {k}, {}", OUTPUTS[i]);
        }
    }
}
