//! Restored FMU states: a buffer with a valid header and checksum is accepted only if the
//! plant could have reached the state it holds; a refusal names the field and leaves the
//! instance as it was. Crafted buffers are built by editing the payload of a genuine one
//! and recomputing its checksum.
use crate::common;

use common::Plant;
use fmi_export::snapshot::HEADER_LEN;
use fmi_testkit::fmi2::*;
use proptest::prelude::*;
use std::ops::Deref;

/// A plant in flight after a few steps, with a tilted, spinning attitude so that its state
/// values are distinctive in the payload.
fn flying() -> Plant {
    let plant = Plant::new();
    plant.set("omega0_body[1]", 0.011);
    plant.set("integration_step", 0.0125);
    plant.set("omega0_body[3]", 0.02);
    plant.init();
    plant.set("thrust_cmd", 1200.0);
    for k in 0..5 {
        assert_eq!(plant.step(f64::from(k) * 0.1, 0.1), fmi2OK);
    }
    plant
}

fn genuine(plant: &Plant) -> Vec<u8> {
    let state = plant.get_state();
    let bytes = plant.serialize(state);
    plant.free_state(state);
    bytes
}

/// `bytes` with its checksum recomputed over the (edited) payload.
fn resealed(mut bytes: Vec<u8>) -> Vec<u8> {
    let crc = crc32fast::hash(&bytes[HEADER_LEN..]);
    bytes[HEADER_LEN - 4..HEADER_LEN].copy_from_slice(&crc.to_le_bytes());
    bytes
}

/// `bytes` with the only payload occurrence of `value` (raw f64) replaced by `by`.
fn replaced(bytes: &[u8], value: f64, by: f64) -> Vec<u8> {
    let needle = value.to_le_bytes();
    let at: Vec<usize> = (HEADER_LEN..=bytes.len() - 8)
        .filter(|&i| bytes[i..i + 8] == needle)
        .collect();
    assert_eq!(
        at.len(),
        1,
        "{value} occurs {} times in the payload",
        at.len()
    );
    let mut edited = bytes.to_vec();
    edited[at[0]..at[0] + 8].copy_from_slice(&by.to_le_bytes());
    resealed(edited)
}

fn deserialize(plant: &Plant, bytes: &[u8]) -> (fmi2Status, fmi2FMUstate) {
    Deref::deref(plant).deserialize(bytes)
}

#[test]
fn a_genuine_state_round_trips() {
    let plant = flying();
    let bytes = genuine(&plant);
    let (status, state) = deserialize(&plant, &bytes);
    assert_eq!(status, fmi2OK, "{:?}", plant.messages());
    plant.set_state(state);
    plant.free_state(state);
}

#[test]
fn crafted_state_values_are_refused_by_name_and_leave_the_instance_as_it_was() {
    let plant = flying();
    let bytes = genuine(&plant);
    let mass = plant.get("mass");
    let qw = plant.get("q_body_to_nue[1]");
    let integration_step = plant.get("integration_step");
    let cases = [
        (replaced(&bytes, mass, 500.0), "mass"),
        (replaced(&bytes, mass, f64::NAN), "not finite"),
        (replaced(&bytes, mass, 2000.0), "mass"),
        (replaced(&bytes, qw, 2.0 * qw), "q_body_to_nue"),
        (
            bytes_with_all(&bytes, integration_step, -1.0),
            "integration_step",
        ),
    ];
    for (crafted, field) in cases {
        plant.clear_log();
        let before = plant.get("mass");
        let (status, state) = deserialize(&plant, &crafted);
        assert_eq!(status, fmi2Error, "{field}");
        assert!(state.is_null());
        let message = plant.last_message();
        assert!(
            message.starts_with("fmi2DeSerializeFMUstate: FMU state refused")
                && message.contains(field),
            "{field}: {message}"
        );
        // The instance goes on as before.
        assert_eq!(plant.get("mass"), before);
        assert_eq!(plant.step(plant.last_successful_time(), 0.1), fmi2OK);
    }
}

#[test]
fn crafted_times_are_refused() {
    let plant = flying();
    let bytes = genuine(&plant);
    // The communication point after five steps of 0.1 s.
    let time = plant.last_successful_time();
    for by in [f64::NAN, f64::INFINITY, -1e300] {
        let crafted = bytes_with_all(&bytes, time, by);
        let (status, _) = deserialize(&plant, &crafted);
        assert_eq!(status, fmi2Error, "time {by}");
        assert!(
            plant.last_message().contains("time"),
            "{}",
            plant.last_message()
        );
    }
}

/// `bytes` with every payload occurrence of `value` replaced (the time is stored twice).
fn bytes_with_all(bytes: &[u8], value: f64, by: f64) -> Vec<u8> {
    let mut edited = bytes.to_vec();
    for i in HEADER_LEN..=bytes.len() - 8 {
        if bytes[i..i + 8] == value.to_le_bytes() {
            edited[i..i + 8].copy_from_slice(&by.to_le_bytes());
        }
    }
    resealed(edited)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]
    /// Random edits of a genuine payload, resealed: each buffer is either refused, or
    /// restores a state from which a get gives finite values (or is refused, e.g. as an
    /// illegal call in the restored layer state) and a step never fails fatally.
    #[test]
    fn a_resealed_random_payload_is_refused_or_behaves(
        edits in proptest::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 1..8),
        whole_doubles in any::<bool>(),
    ) {
        let plant = flying();
        let mut bytes = genuine(&plant);
        let payload = bytes.len() - HEADER_LEN;
        for (at, byte) in edits {
            let i = HEADER_LEN + at.index(payload);
            if whole_doubles && i + 8 <= bytes.len() {
                let extreme = [f64::MAX, -f64::MAX, 1e300, -1.0, 0.0, f64::MIN_POSITIVE];
                let v = extreme[usize::from(byte) % extreme.len()];
                bytes[i..i + 8].copy_from_slice(&v.to_le_bytes());
            } else {
                bytes[i] = byte;
            }
        }
        let bytes = resealed(bytes);
        let (status, state) = deserialize(&plant, &bytes);
        prop_assert!(status == fmi2OK || status == fmi2Error, "{status:?}");
        if status == fmi2OK {
            plant.set_state(state);
            let reals: Vec<u32> = fmi2_export::variables::<fmu_plant::LanderPlant>()
                .iter()
                .filter(|v| v.real(&fmu_plant::LanderPlant::default()).is_some())
                .map(|v| v.value_reference)
                .collect();
            let (get, values) = plant.get_reals(&reals);
            prop_assert!(get != fmi2Fatal, "{:?}", plant.messages());
            if get == fmi2OK || get == fmi2Warning {
                prop_assert!(values.iter().all(|v| v.is_finite()), "{values:?}");
                // The restored time is the one the genuine state held, unless edited: a
                // step from there is accepted or refused, never fatal.
                let step = plant.step(0.5, 0.1);
                prop_assert!(step != fmi2Fatal, "{:?}", plant.messages());
            }
            plant.free_state(state);
        }
    }
}

/// A restored body rate far beyond anything physical (found by the fuzzer: 2.3e77 rad/s)
/// grows RK4's quaternion past where its squared norm overflows: the step and the outputs
/// stay finite (the quaternion is normalised without squaring it first). A rate whose
/// gyroscopic torque omega x (I omega) overflows (found by the fuzzer too) is refused.
#[test]
fn a_restored_body_rate_whose_rotation_overflows_gives_finite_outputs_or_is_refused() {
    for (by, accepted) in [
        (2.3e77, true),
        (1e150, true),
        (-1e300, false),
        (f64::MAX, false),
    ] {
        let plant = Plant::new();
        plant.set("omega0_body[3]", 0.0123);
        plant.init();
        // The parameter and the state hold the rate: both crafted, so they agree.
        let crafted = bytes_with_all(&genuine(&plant), 0.0123, by);
        let (status, state) = deserialize(&plant, &crafted);
        if !accepted {
            assert_eq!(status, fmi2Error, "{by}");
            let message = plant.last_message();
            assert!(
                message.contains("omega") && message.contains("overflows"),
                "{message}"
            );
            continue;
        }
        assert_eq!(status, fmi2OK, "{by}: {:?}", plant.messages());
        plant.set_state(state);
        plant.free_state(state);
        let stepped = plant.step(0.0, 0.01);
        for name in [
            "q_body_to_nue[1]",
            "q_body_to_nue[4]",
            "omega_body[3]",
            "r_nue[2]",
        ] {
            let value = plant.get(name);
            assert!(
                value.is_finite(),
                "{by}: {name} = {value} after a step ({stepped:?})"
            );
        }
    }
}

#[test]
fn a_restored_enumeration_value_that_is_no_item_is_refused_by_name() {
    // GIVEN genuine states before initialization (where the plant itself does not yet
    // validate its parameters) with translation_model flat (1) and spherical (2)
    let plant = Plant::new();
    let flat = genuine(&plant);
    plant.set_integer("translation_model", 2);
    let spherical = genuine(&plant);
    let at: Vec<usize> = (HEADER_LEN..flat.len())
        .filter(|&i| flat[i] != spherical[i])
        .collect();
    assert_eq!(at.len(), 1, "{at:?}");
    // WHEN the value of a resealed buffer is 7 (postcard: zigzag varint, 14)
    let mut crafted = flat.clone();
    crafted[at[0]] = 14;
    let (status, state) = deserialize(&plant, &resealed(crafted));
    // THEN it is refused, naming the variable and the items
    assert_eq!(status, fmi2Error);
    assert!(state.is_null());
    assert!(
        plant
            .last_message()
            .contains("FMU state refused: translation_model = 7: not an item of"),
        "{}",
        plant.last_message()
    );
}

/// Found by the fuzzer (restored_state, -s none): payload edits of a genuine state at t = 0
/// that restore a fast body rate, from which one step grew the rate until omega x (I omega)
/// overflowed and the derivatives read NaN. Such a step is now refused (the state as before
/// it); whatever is accepted reads finite.
#[test]
fn a_step_that_grows_the_body_rate_past_a_representable_gyroscopic_torque_is_refused() {
    use fmi2_export::variable::Access;
    use fmi_export::snapshot::reseal;
    const INPUT: [u8; 76] = [
        0xe3, 0x2a, 0x3f, 0xcd, 0xcd, 0xcd, 0xcd, 0xcd, 0xcd, 0xcd, 0xcd, 0xcd, 0xcd, 0xcd, 0xcd,
        0xcd, 0xcd, 0xcd, 0xcd, 0xcd, 0xcd, 0xcd, 0xcd, 0xcd, 0xcd, 0xcd, 0xcd, 0xcd, 0xcd, 0xcd,
        0xcd, 0xcd, 0xcd, 0xcd, 0xcd, 0xcd, 0xcd, 0xcd, 0xcd, 0xcd, 0xcd, 0xcd, 0xcd, 0xcd, 0xcd,
        0xcd, 0xcd, 0xcd, 0xcd, 0xcd, 0xcd, 0xcd, 0xcd, 0xcd, 0xcd, 0xcd, 0xcd, 0xcd, 0xcd, 0xcd,
        0xcd, 0xcd, 0xcd, 0xcd, 0xcd, 0xcd, 0xcd, 0xcd, 0xcd, 0xcd, 0xcd, 0xcd, 0x52, 0x9e, 0x68,
        0x3f,
    ];
    let plant = Plant::new();
    plant.init();
    let bytes = genuine(&plant);
    let mut payload = bytes[HEADER_LEN..].to_vec();
    // As the fuzz body reads it: (offset lo, offset hi, byte) triples after a mode byte.
    for edit in INPUT[1..].chunks_exact(3) {
        let at = usize::from(u16::from_le_bytes([edit[0], edit[1]])) % payload.len();
        payload[at] = edit[2];
    }
    let (status, state) = deserialize(&plant, &reseal(&bytes, &payload));
    assert!(status == fmi2OK || status == fmi2Error);
    if status != fmi2OK {
        return;
    }
    plant.set_state(state);
    plant.free_state(state);
    let reals: Vec<u32> = fmi2_export::variables::<fmu_plant::LanderPlant>()
        .iter()
        .filter(|v| matches!(v.access, Access::Real { .. }))
        .map(|v| v.value_reference)
        .collect();
    let t = plant.last_successful_time();
    let stepped = plant.step(t, 0.01);
    let values = plant.get_many(&reals);
    assert!(
        values.iter().all(|v| v.is_finite()),
        "step {stepped:?}: {values:?} {:?}",
        plant.messages()
    );
}
