//! What a hostile or merely unusual master can do to the export layer, through the C ABI:
//! states of the other interface, reserved header bytes, stale handles whose memory the
//! allocator has reused, an over-long step, bounds at the declared min and max, extreme
//! numbers in log lines. Each refusal leaves the instance usable.
mod common;

use common::{vr, Plant, FUNCTIONS};
use fmi_testkit::fmi2::*;
use fmi_testkit::Instance;

fn model_exchange() -> Instance {
    let guid = fmi2_export::guid::<fmu_plant::LanderPlant>();
    Instance::new_as(&FUNCTIONS, "me", &guid, false, fmi2ModelExchange).expect("instantiated")
}

#[test]
fn a_serialized_state_of_the_other_interface_is_refused_by_name() {
    // GIVEN a serialized state of a Co-Simulation instance after a step
    let cs = Plant::new();
    cs.init();
    assert_eq!(cs.step(0.0, 0.1), fmi2OK);
    let state = cs.get_state();
    let bytes = cs.serialize(state);
    // WHEN a Model Exchange instance is asked to deserialize it
    let me = model_exchange();
    assert_eq!(me.initialize(), fmi2OK, "{:?}", me.messages());
    let (status, _) = me.deserialize(&bytes);
    // THEN it is refused, naming both interfaces, and the instance goes on
    assert_eq!(status, fmi2Error);
    let message = me.last_message();
    assert!(
        message.contains("state of a Co-Simulation instance; this instance is Model Exchange"),
        "{message}"
    );
    let mine = me.get_state();
    assert_eq!(me.set_state(mine), fmi2OK, "{:?}", me.messages());
    // AND the reverse direction is refused the same way
    let me_bytes = me.serialize(mine);
    let (status, _) = Instance::deserialize(&cs, &me_bytes);
    assert_eq!(status, fmi2Error);
    assert!(
        cs.last_message().contains("Model Exchange instance"),
        "{}",
        cs.last_message()
    );
}

#[test]
fn a_nonzero_reserved_header_byte_is_refused() {
    let plant = Plant::new();
    plant.init();
    let state = plant.get_state();
    let mut bytes = plant.serialize(state);
    // byte 11 of the header is reserved; the checksum covers the payload only
    bytes[11] = 1;
    let (status, _) = Instance::deserialize(&plant, &bytes);
    assert_eq!(status, fmi2Error);
    assert!(
        plant.last_message().contains("reserved header byte 11"),
        "{}",
        plant.last_message()
    );
    bytes[11] = 0;
    let (status, _) = Instance::deserialize(&plant, &bytes);
    assert_eq!(status, fmi2OK, "{:?}", plant.messages());
}

#[test]
fn a_stale_instance_handle_is_refused_when_its_memory_is_reused() {
    let guid = fmi2_export::guid::<fmu_plant::LanderPlant>();
    let mut stale = Vec::new();
    // GIVEN instances freed one after the other, each new one where the allocator puts it
    // (often the memory of the one freed just before)
    for _ in 0..32 {
        let fresh = Instance::instantiate(&FUNCTIONS, "fresh", &guid);
        // WHEN the master calls through the handles of the freed ones
        for &old in &stale {
            // SAFETY: a stale handle is what a buggy master passes; the FMU must refuse it
            // without reading memory through it.
            let status = unsafe { (FUNCTIONS.enter_initialization_mode)(old) };
            // THEN each call is refused and the live instance is untouched
            assert_eq!(status, fmi2Error);
            assert_ne!(old, fresh.component(), "handles are never reused");
        }
        assert!(fresh.messages().is_empty(), "{:?}", fresh.messages());
        assert_eq!(
            fresh.setup_experiment(0.0, None),
            fmi2OK,
            "still Instantiated"
        );
        stale.push(fresh.component());
    }
}

#[test]
fn a_freed_fmu_state_handle_is_refused_when_its_memory_is_reused() {
    let plant = Plant::new();
    plant.init();
    let first = plant.get_state();
    plant.free_state(first);
    // the allocator may hand the freed state's memory to the next one
    let second = plant.get_state();
    assert_ne!(first, second, "handles are never reused");
    assert_eq!(Instance::set_state(&plant, first), fmi2Error);
    assert!(plant
        .last_message()
        .contains("was not created by this instance (or was freed)"));
    plant.set_state(second);
}

#[test]
fn an_over_long_step_is_refused_and_the_instance_steps_on() {
    let plant = Plant::new();
    plant.init();
    // 1e5 s in RK4 sub-steps of 0.01 s: ten million sub-steps, more than one step may take
    assert_eq!(plant.step(0.0, 1e5), fmi2Error);
    assert!(
        plant.last_message().contains("RK4 sub-steps"),
        "{}",
        plant.last_message()
    );
    // the refusal changed nothing: the instance is not in state Error
    assert_eq!(plant.step(0.0, 0.1), fmi2OK, "{:?}", plant.messages());
    assert!((plant.last_successful_time() - 0.1).abs() < 1e-12);
}

/// FMI's `min` and `max` are inclusive: every declared bound of a real parameter or input
/// is a value a set accepts (an exclusive bound is written as the nearest admitted value).
#[test]
fn every_declared_real_bound_is_accepted_by_a_set() {
    let description = fmi2_export::model_description::<fmu_plant::LanderPlant>();
    let mut checked = 0;
    for sv in &description.model_variables.variables {
        let Some(real) = &sv.real else { continue };
        use model_description::Causality;
        if !matches!(sv.causality, Some(Causality::Parameter | Causality::Input)) {
            continue;
        }
        for bound in [real.min, real.max].into_iter().flatten() {
            let plant = Plant::new();
            let status = plant.set_real(vr(&sv.name), bound);
            assert_eq!(
                status,
                fmi2OK,
                "{} = {bound}: {:?}",
                sv.name,
                plant.messages()
            );
            checked += 1;
        }
    }
    assert!(checked >= 10, "only {checked} bounds");
}

#[test]
fn extreme_values_in_log_lines_are_short() {
    let plant = Plant::new();
    plant.init();
    assert_eq!(plant.step(0.0, 1.0), fmi2OK);
    // a step of the smallest positive double does not advance the time from 1 s
    assert_eq!(plant.step(1.0, 5e-324), fmi2Error);
    let message = plant.last_message();
    assert!(message.contains("5e-324"), "{message}");
    assert!(
        message.len() < 200,
        "{} characters: {message}",
        message.len()
    );
}
