//! LanderPlant through its FMI 3.0 C functions, as an FMI 3.0 master calls them: arrays,
//! refusals with their log lines, FMU-state round trips, and the functions of features the
//! FMU lacks.
#![allow(unsafe_code)]

use crate::fmi3_common;

use fmi3_common::{vr, Plant};
use fmi_testkit::fmi3_ffi::*;
use fmi_testkit::Fmi3Step;
use fmu_plant as fmu;

/// A step that must not end early (and, without Event Mode, needs no event handling):
/// status, terminateSimulation, lastSuccessfulTime.
fn step(plant: &Plant, t: f64, h: f64) -> (fmi3Status, bool, f64) {
    let s = step_early(plant, t, h);
    assert!(!s.early_return);
    (s.status, s.terminate_simulation, s.last_successful_time)
}

/// A step, with `earlyReturn` (`eventHandlingNeeded` must stay false: no Event Mode).
fn step_early(plant: &Plant, t: f64, h: f64) -> Fmi3Step {
    let s = plant.do_step(t, h);
    assert!(!s.event_handling_needed);
    s
}

#[test]
fn vectors_are_arrays_and_the_plant_falls() {
    let plant = Plant::co_simulation(false);
    assert_eq!(plant.set("r0_nue", &[10.0, 500.0, -20.0]), fmi3OK);
    plant.init();
    assert_eq!(plant.get("r_nue", 3), [10.0, 500.0, -20.0]);
    assert_eq!(plant.get("q_body_to_nue", 4), [1.0, 0.0, 0.0, 0.0]);
    for k in 0..10 {
        let (status, terminate, last) = step(&plant, k as f64 * 0.1, 0.1);
        assert_eq!((status, terminate), (fmi3OK, false));
        assert!((last - (k + 1) as f64 * 0.1).abs() < 1e-12);
    }
    let r = plant.get("r_nue", 3);
    assert!((r[1] - (500.0 - 0.81)).abs() < 1e-9, "{r:?}");
    // `time` (the independent variable) reads beside the others, as one element
    let vrs = [vr("mass"), fmi3_export::variables::TIME_VR, vr("r_nue")];
    let (status, values) = plant.get_float64(&vrs, 5);
    assert_eq!(status, fmi3OK, "{}", plant.log());
    assert!((values[1] - 1.0).abs() < 1e-12, "{values:?}");
    assert_eq!((values[0], values[3]), (900.0, r[1]));
}

/// FMI 3.0 §4.2: `fmi3Discard` means the step did not succeed; an FMU that ends its own
/// run answers `fmi3OK` with `terminateSimulation`.
#[test]
fn touchdown_returns_ok_with_terminate_early_where_the_master_allows_it() {
    let mut outputs = Vec::new();
    for early_return_allowed in [true, false] {
        // GIVEN a plant in free fall from 0.81 m, which reaches the ground at t = 1 s
        let plant = Plant::co_simulation(early_return_allowed);
        plant.set("r0_nue", &[0.0, 0.81, 0.0]);
        plant.init();
        // WHEN a step of 2 s passes the touchdown
        let Fmi3Step {
            status,
            terminate_simulation: terminate,
            early_return: early,
            last_successful_time: last,
            ..
        } = step_early(&plant, 0.0, 2.0);
        // THEN the step succeeded and the FMU asks to end the run
        assert_eq!(status, fmi3OK, "{}", plant.log());
        assert!(terminate);
        // returning early at the touchdown where allowed; either way the FMU's time stopped
        // there, and lastSuccessfulTime says so (FMI 3.0: the internal time, for any
        // value of earlyReturn)
        assert_eq!(early, early_return_allowed);
        assert!((last - 1.0).abs() < 1e-9, "{last}");
        assert_eq!(
            plant.get_float64(&[fmi3_export::variables::TIME_VR], 1).1,
            [last]
        );
        assert!((plant.get("touchdown_time", 1)[0] - 1.0).abs() < 1e-9);
        assert!(plant.get("altitude", 1)[0].abs() < 1e-9);
        outputs.push((plant.get("v_nue", 3), plant.get("r_nue", 3)));
    }
    // AND the outputs are the event's in both cases
    assert_eq!(outputs[0], outputs[1]);
    assert!((outputs[0].0[1] + 1.62).abs() < 1e-6, "{:?}", outputs[0]);
}

#[test]
fn refused_values_name_the_variable_and_change_nothing() {
    let plant = Plant::co_simulation(false);
    // length of the values does not match the array
    assert_eq!(plant.set("r0_nue", &[1.0, 2.0]), fmi3Error);
    // a bound the parameter check enforces
    assert_eq!(plant.set("m0", &[-5.0]), fmi3Error);
    assert_eq!(plant.set("m0", &[f64::NAN]), fmi3Error);
    plant.init();
    // a fixed parameter after initialization, an output at any time
    assert_eq!(plant.set("m0", &[800.0]), fmi3Error);
    assert_eq!(plant.set("mass", &[800.0]), fmi3Error);
    assert_eq!(plant.get("mass", 1), [900.0], "nothing was written");
    let log = plant.log();
    for expected in [
        "fmi3SetFloat64: nValues = 2, the 1 variables asked for have 3 elements",
        "fmi3SetFloat64: variable m0 (vr 113): value -5 kg is outside (0, inf) kg",
        "fmi3SetFloat64: variable m0 (vr 113): value NaN is not finite",
        "a fixed parameter can only be set before the end of initialization",
        "variable mass (vr 23) cannot be set: an output is computed by the FMU",
    ] {
        assert!(log.contains(expected), "missing {expected:?} in\n{log}");
    }
}

#[test]
fn missing_features_and_the_other_interface_answer_error_with_a_reason() {
    let plant = Plant::co_simulation(false);
    plant.init();
    let mut active = [false];
    let vr = 1u32;
    // Clocks and Configuration Mode are features the kit does not drive: called directly.
    // SAFETY: a live instance and valid arrays.
    unsafe {
        assert_eq!(
            fmu::fmi3GetClock(plant.instance(), &vr, 1, active.as_mut_ptr()),
            fmi3Error
        );
        assert_eq!(fmu::fmi3EnterConfigurationMode(plant.instance()), fmi3Error);
    }
    assert_eq!(plant.set_continuous_states(&[0.0; 18]), fmi3Error);
    let log = plant.log();
    assert!(
        log.contains("fmi3GetClock: not supported: this FMU has no clocks"),
        "{log}"
    );
    assert!(
        log.contains(
            "fmi3SetContinuousStates: not a Co-Simulation function; this instance is Co-Simulation"
        ),
        "{log}"
    );
    assert!(
        log.contains("fmi3EnterConfigurationMode: not supported"),
        "{log}"
    );
}

#[test]
fn a_serialized_fmu_state_restores_the_run_bit_for_bit_and_a_corrupt_one_is_refused() {
    let plant = Plant::co_simulation(false);
    plant.set("omega0_body", &[0.3, -0.2, 0.1]);
    plant.init();
    for k in 0..5 {
        step(&plant, k as f64 * 0.1, 0.1);
    }
    let (status, state) = plant.get_state();
    assert_eq!(status, fmi3OK);
    let (status, bytes) = plant.serialize(state);
    assert_eq!(status, fmi3OK);
    assert_eq!(plant.free_state(state), fmi3OK);
    assert_eq!(&bytes[..8], b"FMI3SNAP");
    for k in 5..10 {
        step(&plant, k as f64 * 0.1, 0.1);
    }
    let reference = plant.get("q_body_to_nue", 4);
    let (status, restored) = plant.deserialize(&bytes);
    assert_eq!(status, fmi3OK);
    assert_eq!(plant.set_state(restored), fmi3OK);
    plant.free_state(restored);
    let mut corrupt = bytes.clone();
    let last = corrupt.len() - 1;
    corrupt[last] ^= 0xff;
    assert_eq!(plant.deserialize(&corrupt).0, fmi3Error);
    for k in 5..10 {
        step(&plant, k as f64 * 0.1, 0.1);
    }
    assert_eq!(plant.get("q_body_to_nue", 4), reference, "bit for bit");
    assert!(plant.log().contains("checksum"), "{}", plant.log());
}

#[test]
fn integers_and_booleans_cross_with_their_checks() {
    let plant = Plant::co_simulation(false);
    let (count, model) = (vr("engine_count"), vr("translation_model"));
    let touchdown = vr("touchdown");
    // engine_count >= 1: 0 is refused, and nothing is written by the refused pair;
    // translation_model (a selector exchanged as Int32) accepts only its items
    assert_eq!(plant.set_int32(&[model, count], &[2, 0]), fmi3Error);
    assert_eq!(plant.set_int32(&[model], &[3]), fmi3Error);
    assert_eq!(
        plant.get_int32(&[model, count]).0,
        fmi3Error,
        "no get before initialization mode"
    );
    plant.init();
    let (status, got) = plant.get_int32(&[model, count]);
    assert_eq!(status, fmi3OK);
    assert_eq!(got, [1, 2], "flat model, two engines: the start values");
    let (status, down) = plant.get_booleans(&[touchdown]);
    assert_eq!(status, fmi3OK);
    assert_eq!(down, [false]);
    assert_eq!(plant.set_booleans(&[touchdown], &[true]), fmi3Error);
    // a Float64 value reference asked for as Int32
    assert_eq!(plant.get_int32(&[vr("mass")]).0, fmi3Error);
    let log = plant.log();
    for expected in [
        "fmi3SetInt32: variable engine_count (vr 130): value 0 is outside [1, inf)",
        "fmi3GetInt32: illegal call in state Instantiated",
        "fmi3SetInt32: variable translation_model (vr 150): value 3 is not an item of enumeration TranslationModel: allowed 1 (flat), 2 (spherical)",
        "fmi3SetBoolean: variable touchdown (vr 34) cannot be set: an output is computed by the FMU",
        "fmi3GetInt32: unknown value reference 23 for type Int32",
    ] {
        assert!(log.contains(expected), "missing {expected:?} in\n{log}");
    }
}

/// One get and one set over many references at once (more than the layer keeps on its
/// stack, `time` among them, arrays and scalars mixed) agree value for value with the
/// one-variable calls; a refused value anywhere in the list changes nothing.
#[test]
fn many_references_in_one_call_match_the_one_variable_calls() {
    let plant = Plant::co_simulation(false);
    assert_eq!(plant.enter_initialization_mode(0.0, None), fmi3OK);
    let names: [(&str, usize); 12] = [
        ("r0_nue", 3),
        ("v0_nue", 3),
        ("m0", 1),
        ("isp", 1),
        ("dry_mass", 1),
        ("omega0_body", 3),
        ("g", 1),
        ("inertia_body", 3),
        ("engine_thrust_max", 1),
        ("engine_thrust_min", 1),
        ("moon_radius", 1),
        ("integration_step", 1),
    ];
    let vrs: Vec<u32> = names.iter().map(|(n, _)| vr(n)).collect();
    let total: usize = names.iter().map(|(_, n)| n).sum();
    // Every value nudged from what the one-variable gets show.
    let mut values: Vec<f64> = names
        .iter()
        .flat_map(|&(n, len)| plant.get(n, len))
        .map(|v| if v == 0.0 { 0.25 } else { v * 1.01 })
        .collect();
    assert_eq!(values.len(), total);
    let status = plant.set_float64(&vrs, &values);
    assert_eq!(status, fmi3OK, "{}", plant.log());
    let one_by_one: Vec<f64> = names
        .iter()
        .flat_map(|&(n, len)| plant.get(n, len))
        .collect();
    assert_eq!(one_by_one, values);
    // AND a get of them all, with `time` in the middle, reads the same
    let mut with_time = vrs.clone();
    with_time.insert(5, fmi3_export::variables::TIME_VR);
    let (status, mut read) = plant.get_float64(&with_time, total + 1);
    assert_eq!(status, fmi3OK, "{}", plant.log());
    let time_at = names[..5].iter().map(|(_, n)| n).sum::<usize>();
    assert_eq!(read.remove(time_at), 0.0, "time");
    assert_eq!(read, values);
    // AND a get or set with one value too few or too many, or an unknown reference among
    // them, is refused naming the fault
    for (n, expect) in [(total - 1, "nValues"), (total + 1, "nValues")] {
        let buffer = vec![0.0; n];
        let (get, set) = (
            plant.get_float64(&vrs, n).0,
            plant.set_float64(&vrs, &buffer),
        );
        assert_eq!((get, set), (fmi3Error, fmi3Error), "{n}");
        assert!(plant.log().contains(expect), "{}", plant.log());
    }
    let mut unknown = vrs.clone();
    unknown[7] = 77_777;
    let get = plant.get_float64(&unknown, total).0;
    assert_eq!(get, fmi3Error);
    assert!(plant.log().contains("77777"), "{}", plant.log());
    // AND a NaN in the last variable refuses the whole call
    let before = values.clone();
    *values.last_mut().unwrap() = f64::NAN;
    let status = plant.set_float64(&vrs, &values);
    assert_eq!(status, fmi3Error);
    let after: Vec<f64> = names
        .iter()
        .flat_map(|&(n, len)| plant.get(n, len))
        .collect();
    assert_eq!(after, before);
}

/// Found by the FMI 3.0 `call_sequence` fuzz target (input `82dd60070700`, minimized:
/// Co-Simulation, `rcs_thruster_force` = f64::MAX, then fmi3EnterInitializationMode): the
/// calculated parameter `rcs_torque_limit` (2 x rcs_thruster_force x rcs_moment_arm) read
/// +inf with fmi3OK, because validation checked force x arm (finite here), not the limit.
/// Now the read is refused (no non-finite value leaves a get) and the end of
/// initialization refuses the parameters, naming the overflow.
#[test]
fn an_rcs_thruster_force_whose_torque_limit_overflows_never_reads_infinite() {
    let plant = Plant::co_simulation(false);
    assert_eq!(plant.set("rcs_thruster_force", &[f64::MAX]), fmi3OK);
    assert_eq!(plant.enter_initialization_mode(0.0, None), fmi3OK);
    let read = |plant: &Plant| {
        let (status, limit) = plant.get_float64(&[vr("rcs_torque_limit")], 1);
        assert!(
            status != fmi3OK || limit[0].is_finite(),
            "rcs_torque_limit = {limit:?} with {status:?}"
        );
    };
    // In initialization mode: a finite value (or a refused get)
    read(&plant);
    // AND leaving it is refused, naming the overflowing limit
    assert_eq!(plant.exit_initialization_mode(), fmi3Error);
    assert!(plant.log().contains("torque limit"), "{}", plant.log());
}
