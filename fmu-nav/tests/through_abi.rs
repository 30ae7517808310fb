//! LanderNav through its exported C functions, as a master drives it (the workspace's test
//! kit): the identity with direct feedthrough, reads that never change the sequence,
//! FMU-state save/restore and serialization, parameters refused together. What every FMU
//! owes (description drift, bounds, refusals at the set) is tests/conformance.rs.
// std's transcendental functions here make test inputs and references, outside the model.
#![allow(clippy::disallowed_methods)]
use fmi_testkit::fmi2::*;
use fmi_testkit::{fmi2_functions, Fmi2Functions, Instance};
use fmu_nav::LanderNav;

static FUNCTIONS: Fmi2Functions = fmi2_functions!(fmu_nav);
const H: f64 = 0.01;

fn vr(name: &str) -> u32 {
    fmi2_export::variables::<LanderNav>()
        .iter()
        .find(|v| v.name() == name)
        .unwrap_or_else(|| panic!("no variable {name}"))
        .value_reference
}

const SIGNALS: [&str; 14] = [
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
    "mass",
];

fn true_vrs() -> Vec<u32> {
    SIGNALS
        .iter()
        .map(|s| match s.split_once('[') {
            Some((base, rest)) => vr(&format!("{base}_true[{rest}")),
            None => vr(&format!("{s}_true")),
        })
        .collect()
}

fn estimate_vrs() -> Vec<u32> {
    SIGNALS.iter().map(|s| vr(s)).collect()
}

/// The true signals at step `k`: moving, with a unit quaternion.
fn truth(k: usize) -> Vec<f64> {
    let s = k as f64 * H;
    let half = 0.2 * (0.3 * s).sin();
    vec![
        s.sin(),
        800.0 - 2.0 * s,
        -0.0,
        0.1,
        -2.0,
        0.01 * s,
        half.cos(),
        0.6 * half.sin(),
        0.0,
        0.8 * half.sin(),
        0.01,
        -0.02 * s,
        0.003,
        900.0 - 0.4 * s,
    ]
}

fn instance() -> Instance {
    Instance::instantiate(&FUNCTIONS, "nav", &fmi2_export::guid::<LanderNav>())
}

fn set_real(fmu: &Instance, name: &str, value: f64) {
    assert_eq!(
        fmu.set_real(vr(name), value),
        fmi2OK,
        "{name}: {:?}",
        fmu.messages()
    );
}

fn set_integer(fmu: &Instance, name: &str, value: i32) {
    assert_eq!(
        fmu.set_integer(vr(name), value),
        fmi2OK,
        "{name}: {:?}",
        fmu.messages()
    );
}

/// Every kind of error switched on, with latencies.
fn noisy() -> Instance {
    let fmu = instance();
    fmu.enter_init();
    set_integer(&fmu, "seed", 42);
    set_integer(&fmu, "max_latency_steps", 4);
    set_real(&fmu, "r_nue_noise_sigma", 0.5);
    set_real(&fmu, "r_nue_bias[2]", 1.0);
    set_real(&fmu, "r_nue_random_walk", 0.2);
    set_real(&fmu, "r_nue_quantum", 0.01);
    set_integer(&fmu, "r_nue_latency", 2);
    set_real(&fmu, "v_nue_random_walk", 0.05);
    set_integer(&fmu, "v_nue_latency", 4);
    set_real(&fmu, "attitude_noise_sigma", 1e-3);
    set_real(&fmu, "attitude_bias[3]", 2e-3);
    set_real(&fmu, "omega_body_noise_sigma", 1e-4);
    set_real(&fmu, "omega_body_quantum", 1e-5);
    set_real(&fmu, "mass_bias", 5.0);
    set_real(&fmu, "mass_random_walk", 0.5);
    set_integer(&fmu, "mass_latency", 1);
    assert_eq!(
        fmu.exit_initialization_mode(),
        fmi2OK,
        "{:?}",
        fmu.messages()
    );
    fmu
}

fn get_all(fmu: &Instance) -> Vec<u64> {
    let (status, values) = fmu.get_reals(&estimate_vrs());
    assert_eq!(status, fmi2OK, "{:?}", fmu.messages());
    values.iter().map(|v| v.to_bits()).collect()
}

/// Steps `k0..k1`, setting the truth before each step; the estimates at each point.
fn fly(fmu: &Instance, k0: usize, k1: usize) -> Vec<Vec<u64>> {
    let mut out = Vec::new();
    for k in k0..k1 {
        assert_eq!(fmu.set_reals(&true_vrs(), &truth(k)), fmi2OK);
        out.push(get_all(fmu));
        assert_eq!(fmu.do_step(k as f64 * H, H), fmi2OK, "{:?}", fmu.messages());
    }
    out
}

#[test]
fn by_default_the_outputs_are_the_inputs_bit_for_bit_with_direct_feedthrough() {
    let fmu = instance();
    fmu.enter_init();
    // In initialization mode already.
    let odd = [
        -0.0, 5e-324, -1.5e300, 0.1, -2.0, 0.0, 0.0, -0.0, 0.0, 0.0, 1e-7, -0.0, 3.0, 900.0,
    ];
    assert_eq!(fmu.set_reals(&true_vrs(), &odd), fmi2OK);
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(get_all(&fmu), bits(&odd));
    assert_eq!(fmu.exit_initialization_mode(), fmi2OK);
    for k in 0..100 {
        // A new input shows at once, without a step.
        let x = truth(k);
        assert_eq!(fmu.set_reals(&true_vrs(), &x), fmi2OK);
        assert_eq!(get_all(&fmu), bits(&x), "step {k}");
        assert_eq!(fmu.do_step(k as f64 * H, H), fmi2OK);
    }
}

#[test]
fn reads_between_steps_never_change_the_errors() {
    // GIVEN two identical noisy instances; one is read many times with other inputs set
    // in between, the other only once per step
    let (read, bare) = (noisy(), noisy());
    for k in 0..200 {
        for _ in 0..3 {
            assert_eq!(read.set_reals(&true_vrs(), &truth(k + 77)), fmi2OK);
            get_all(&read);
        }
        for fmu in [&read, &bare] {
            assert_eq!(fmu.set_reals(&true_vrs(), &truth(k)), fmi2OK);
        }
        // THEN both show the same estimates, bit for bit
        assert_eq!(get_all(&read), get_all(&bare), "step {k}");
        for fmu in [&read, &bare] {
            assert_eq!(fmu.do_step(k as f64 * H, H), fmi2OK);
        }
    }
}

#[test]
fn the_errors_are_on_and_reproducible_from_the_seed() {
    let (a, b) = (noisy(), noisy());
    let run_a = fly(&a, 0, 100);
    assert_eq!(run_a, fly(&b, 0, 100));
    // Not the identity: every estimate except the quaternion's zero element differs
    // from its truth somewhere along the run.
    for (i, name) in SIGNALS.iter().enumerate() {
        let differs = run_a
            .iter()
            .enumerate()
            .any(|(k, row)| f64::from_bits(row[i]) != truth(k)[i]);
        assert!(
            differs || *name == "q_body_to_nue[3]",
            "{name} has no error"
        );
    }
}

#[test]
fn save_restore_and_serialization_reproduce_the_continuation_bit_for_bit() {
    // GIVEN a noisy run of 30 steps, its state saved and serialized there
    let fmu = noisy();
    fly(&fmu, 0, 30);
    let state = fmu.get_state();
    let bytes = fmu.serialize(state);
    // WHEN it continues 50 steps, then is restored and replays them
    let continuation = fly(&fmu, 30, 80);
    assert_eq!(fmu.set_state(state), fmi2OK, "{:?}", fmu.messages());
    let replay = fly(&fmu, 30, 80);
    // THEN the replay is the continuation, bit for bit
    assert_eq!(replay, continuation);
    assert_eq!(fmu.free_state(state), fmi2OK);
    // AND a fresh instance (other seed, no latency) given the serialized state continues
    // the same way: the draws, the walk and the latency history are all in it
    let other = instance();
    other.enter_init();
    set_integer(&other, "seed", 1);
    assert_eq!(other.exit_initialization_mode(), fmi2OK);
    let (status, restored) = other.deserialize(&bytes);
    assert_eq!(status, fmi2OK, "{:?}", other.messages());
    assert_eq!(other.set_state(restored), fmi2OK, "{:?}", other.messages());
    assert_eq!(fly(&other, 30, 80), continuation);
    assert_eq!(other.free_state(restored), fmi2OK);
}

#[test]
fn a_latency_beyond_its_bound_fails_initialization_naming_the_variable() {
    let fmu = instance();
    fmu.enter_init();
    set_integer(&fmu, "max_latency_steps", 3);
    set_integer(&fmu, "omega_body_latency", 4);
    assert_eq!(fmu.exit_initialization_mode(), fmi2Error);
    let messages = fmu.messages().join("\n");
    assert!(
        messages.contains("omega_body_latency") && messages.contains("max_latency_steps"),
        "{messages}"
    );
    // A bound past the cap is refused at the set.
    let fresh = instance();
    fresh.enter_init();
    assert_eq!(
        fresh.set_integer(vr("max_latency_steps"), 10_001),
        fmi2Error
    );
    assert!(
        fresh.last_message().contains("max_latency_steps"),
        "{:?}",
        fresh.messages()
    );
}

#[test]
fn initialization_mode_already_shows_the_errors_of_the_first_interval() {
    // GIVEN noise and a bias set in initialization mode, and an input
    let fmu = instance();
    fmu.enter_init();
    set_integer(&fmu, "seed", 9);
    set_real(&fmu, "r_nue_noise_sigma", 0.5);
    set_real(&fmu, "mass_bias", -2.0);
    assert_eq!(fmu.set_reals(&true_vrs(), &truth(0)), fmi2OK);
    // WHEN read before and after fmi2ExitInitializationMode
    let before = get_all(&fmu);
    assert_eq!(fmu.exit_initialization_mode(), fmi2OK);
    let after = get_all(&fmu);
    // THEN both show the same erroneous estimates
    assert_eq!(before, after);
    assert_eq!(f64::from_bits(after[13]), truth(0)[13] - 2.0);
    assert_ne!(f64::from_bits(after[0]), truth(0)[0]);
}

#[test]
fn degenerate_inputs_with_every_error_on_give_finite_outputs() {
    // GIVEN every kind of error on, and inputs a master may pass: a zero quaternion, huge
    // and subnormal values
    let fmu = noisy();
    let degenerate = [
        1e300, -1e300, 5e-324, 0.0, -0.0, 1e-300, 0.0, 0.0, 0.0, 0.0, -1e300, 0.0, 1e300, 0.0,
    ];
    for k in 0..50 {
        assert_eq!(fmu.set_reals(&true_vrs(), &degenerate), fmi2OK);
        // THEN every read succeeds with finite values, the zero quaternion stays zero (no
        // division by its norm), and every step succeeds
        let (status, values) = fmu.get_reals(&estimate_vrs());
        assert_eq!(status, fmi2OK, "{:?}", fmu.messages());
        assert!(values.iter().all(|v| v.is_finite()), "step {k}: {values:?}");
        assert_eq!(&values[6..10], &[0.0; 4], "step {k}");
        assert_eq!(fmu.do_step(k as f64 * H, H), fmi2OK, "{:?}", fmu.messages());
    }
}
