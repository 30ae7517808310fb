//! Restored FMU states through the FMI 3.0 C functions: a buffer resealed with a valid
//! header and checksum is accepted only if the plant could have reached the state it holds
//! (the checks the FMI 2.0 layer makes); a refusal names the field and leaves the instance
//! as it was. Also: communication points a corrupt or crafted time cannot sneak past.
use crate::fmi3_common;

use fmi3_common::Plant;
use fmi_export::snapshot::{reseal, HEADER_LEN};
use fmi_testkit::fmi3_ffi::*;

/// The status of a step (its out-arguments are not what these tests look at).
fn step(plant: &Plant, t: f64, h: f64) -> fmi3Status {
    plant.do_step(t, h).status
}

fn set(plant: &Plant, name: &str, values: &[f64]) {
    assert_eq!(plant.set(name, values), fmi3OK, "{}", plant.last_message());
}

fn set_int(plant: &Plant, name: &str, value: i32) {
    let s = plant.set_int32(&[fmi3_common::vr(name)], &[value]);
    assert_eq!(s, fmi3OK, "{}", plant.last_message());
}

/// `bytes` with every payload occurrence of `value` (raw f64) replaced by `by`, resealed.
fn with_all(bytes: &[u8], value: f64, by: f64, expected: usize) -> Vec<u8> {
    let mut payload = bytes[HEADER_LEN..].to_vec();
    let mut found = 0;
    for i in 0..=payload.len() - 8 {
        if payload[i..i + 8] == value.to_le_bytes() {
            payload[i..i + 8].copy_from_slice(&by.to_le_bytes());
            found += 1;
        }
    }
    assert_eq!(found, expected, "occurrences of {value}");
    reseal(bytes, &payload)
}

/// A plant after five steps of 0.1 s, with distinctive values in its state.
fn flying() -> Plant {
    let plant = Plant::co_simulation(false);
    set(&plant, "omega0_body", &[0.011, 0.0, 0.02]);
    set(&plant, "isp", &[301.25]);
    plant.init();
    set(&plant, "thrust_cmd", &[1200.0]);
    for k in 0..5 {
        assert_eq!(step(&plant, f64::from(k) * 0.1, 0.1), fmi3OK);
    }
    plant
}

#[test]
fn a_genuine_state_round_trips() {
    let plant = flying();
    let bytes = plant.genuine();
    let mass = plant.get("mass", 1);
    assert_eq!(step(&plant, 0.5, 0.1), fmi3OK);
    assert_eq!(plant.restore(&bytes), fmi3OK, "{}", plant.last_message());
    assert_eq!(plant.get("mass", 1), mass);
}

#[test]
fn crafted_state_values_are_refused_by_name_and_leave_the_instance_as_it_was() {
    let plant = flying();
    let bytes = plant.genuine();
    let mass = plant.get("mass", 1)[0];
    let q = plant.get("q_body_to_nue", 4);
    let cases = [
        (with_all(&bytes, mass, 500.0, 1), "mass"),
        (with_all(&bytes, mass, f64::NAN, 1), "not finite"),
        (with_all(&bytes, q[0], 2.0 * q[0], 1), "q_body_to_nue"),
        // A Float64 parameter outside its declared bounds: the layer's own check.
        (
            with_all(&bytes, 301.25, -301.25, 1),
            "isp = -301.25: outside (0, inf)",
        ),
        // Times: the communication point after five steps, stored once by this layer.
        (with_all(&bytes, 0.5, f64::NAN, 2), "time = NaN: not finite"),
        (with_all(&bytes, 0.5, -1e300, 2), "time"),
    ];
    for (crafted, field) in cases {
        let before = plant.get("mass", 1);
        assert_eq!(plant.restore(&crafted), fmi3Error, "{field}");
        let message = plant.last_message();
        assert!(
            message.starts_with("fmi3DeserializeFMUState: FMU state refused")
                && message.contains(field),
            "{field}: {message}"
        );
        // The instance goes on as before.
        assert_eq!(plant.get("mass", 1), before);
        assert_eq!(step(&plant, 0.5, 0.1), fmi3OK);
        assert_eq!(plant.restore(&bytes), fmi3OK);
    }
}

/// The payload position of the only byte that differs between two genuine states.
fn differing_byte(a: &[u8], b: &[u8]) -> usize {
    assert_eq!(a.len(), b.len());
    let at: Vec<usize> = (HEADER_LEN..a.len()).filter(|&i| a[i] != b[i]).collect();
    assert_eq!(at.len(), 1, "{at:?}");
    at[0]
}

#[test]
fn a_restored_enumeration_value_that_is_no_item_is_refused_by_name() {
    // GIVEN genuine states before initialization (where the plant itself does not yet
    // validate its parameters) with translation_model flat (1) and spherical (2)
    let plant = Plant::co_simulation(false);
    let flat = plant.genuine();
    set_int(&plant, "translation_model", 2);
    let spherical = plant.genuine();
    // WHEN the value of a resealed buffer is 7 (postcard: zigzag varint, 14)
    let at = differing_byte(&flat, &spherical);
    let mut crafted = flat.clone();
    crafted[at] = 14;
    let crafted = reseal(&crafted, &crafted[HEADER_LEN..]);
    // THEN it is refused, naming the variable and the items
    assert_eq!(plant.restore(&crafted), fmi3Error);
    let message = plant.last_message();
    assert!(
        message.contains("FMU state refused: translation_model = 7: not an item of"),
        "{message}"
    );
    // AND a genuine one is accepted
    assert_eq!(plant.restore(&flat), fmi3OK, "{}", plant.last_message());
}

#[test]
fn a_step_from_a_restored_time_that_overflows_is_refused() {
    // GIVEN a state crafted at t = 1.5e308 (finite and after the start: admissible)
    let plant = flying();
    let crafted = with_all(&plant.genuine(), 0.5, 1.5e308, 2);
    assert_eq!(plant.restore(&crafted), fmi3OK, "{}", plant.last_message());
    // WHEN the master steps by as much again, THEN the end time (infinite) is refused
    assert_eq!(step(&plant, 1.5e308, 1.5e308), fmi3Error);
    assert!(
        plant
            .last_message()
            .contains("does not advance a finite time"),
        "{}",
        plant.last_message()
    );
    // AND so are points that do not match, or are not numbers
    for t in [f64::NAN, f64::INFINITY, 0.5] {
        assert_eq!(step(&plant, t, 0.1), fmi3Error, "{t}");
    }
}

#[test]
fn model_exchange_set_time_refuses_a_time_that_is_not_finite_or_before_the_start() {
    let plant = Plant::model_exchange();
    assert_eq!(plant.enter_initialization_mode(10.0, None), fmi3OK);
    assert_eq!(plant.exit_initialization_mode(), fmi3OK);
    assert_eq!(plant.enter_continuous_time_mode(), fmi3OK);
    for t in [f64::NAN, f64::NEG_INFINITY, 9.0, -1e300] {
        assert_eq!(plant.set_time(t), fmi3Error, "{t}");
    }
    assert!(
        plant.last_message().contains("before the start time 10"),
        "{}",
        plant.last_message()
    );
    assert_eq!(plant.set_time(10.5), fmi3OK);
}

/// Found by the FMI 3.0 `restored_state` fuzz target (input `7b0b0f0400ff5f`: two payload
/// bytes of a genuine state after initialization edited, then resealed): the state put the
/// instance in FMI 2.0's StepFailed, a state no FMI 3.0 instance may be in. A restored
/// state must be one the version and interface can be in.
#[test]
fn a_restored_state_of_a_step_mode_fmi3_does_not_have_is_refused() {
    let plant = Plant::co_simulation(true);
    plant.init();
    let genuine = plant.genuine();
    let mut payload = genuine[HEADER_LEN..].to_vec();
    let len = payload.len();
    payload[0x0f0b % len] = 0x04;
    payload[0xff00 % len] = 0x5f;
    let crafted = reseal(&genuine, &payload);
    let (status, state) = plant.deserialize(&crafted);
    if status == fmi3OK {
        // Accepted: the instance must still answer as an FMI 3.0 instance.
        plant.set_state(state);
        plant.free_state(state);
        assert_eq!(
            plant.get_float64(&[fmi3_common::vr("mass")], 1).0,
            fmi3OK,
            "{}",
            plant.log()
        );
    }
    assert_eq!(plant.restore(&genuine), fmi3OK, "{}", plant.log());
}
