//! LanderPlant through its FMI 3.0 C functions, as an FMI 3.0 master calls them: arrays,
//! refusals with their log lines, FMU-state round trips, and the functions of features the
//! FMU lacks.
#![allow(unsafe_code)]

use fmi3_export::ffi::*;
use fmu_plant as fmu;
use std::ffi::{c_void, CStr, CString};
use std::sync::Mutex;

/// What `instanceEnvironment` points to: every message the FMU logged.
#[derive(Default)]
struct Sink(Mutex<Vec<(fmi3Status, String)>>);

unsafe extern "C" fn record(
    environment: fmi3InstanceEnvironment,
    status: fmi3Status,
    _category: fmi3String,
    message: fmi3String,
) {
    // SAFETY: the environment is our Sink, the message a NUL-terminated string.
    let sink = unsafe { &*(environment as *const Sink) };
    let text = unsafe { CStr::from_ptr(message) }
        .to_string_lossy()
        .into_owned();
    sink.0.lock().unwrap().push((status, text));
}

struct Plant {
    c: fmi3Instance,
    sink: Box<Sink>,
}

impl Plant {
    fn co_simulation() -> Plant {
        Plant::co_simulation_with(false)
    }

    /// A Co-Simulation instance; `early_return_allowed` as the master chooses it.
    fn co_simulation_with(early_return_allowed: bool) -> Plant {
        let sink = Box::<Sink>::default();
        let token = CString::new(fmi3_export::instantiation_token::<fmu::LanderPlant>()).unwrap();
        // SAFETY: valid strings; the sink outlives the instance.
        let c = unsafe {
            fmu::fmi3InstantiateCoSimulation(
                c"plant".as_ptr(),
                token.as_ptr(),
                std::ptr::null(),
                false,
                false,
                false,
                early_return_allowed,
                std::ptr::null(),
                0,
                &*sink as *const Sink as *mut c_void,
                Some(record),
                None,
            )
        };
        assert!(!c.is_null(), "{:?}", sink.0.lock().unwrap());
        Plant { c, sink }
    }

    fn log(&self) -> String {
        let messages = self.sink.0.lock().unwrap();
        messages
            .iter()
            .map(|(_, m)| m.as_str())
            .collect::<Vec<_>>()
            .join("\n")
    }

    fn vr(name: &str) -> u32 {
        use fmi_model::Model;
        fmu::LanderPlant::declarations()
            .iter()
            .find(|d| d.name == name)
            .unwrap_or_else(|| panic!("no declaration {name}"))
            .value_reference
    }

    fn get(&self, name: &str, n: usize) -> Vec<f64> {
        let mut values = vec![f64::NAN; n];
        let vr = Plant::vr(name);
        // SAFETY: a live instance, n values for an n-element variable.
        let status = unsafe { fmu::fmi3GetFloat64(self.c, &vr, 1, values.as_mut_ptr(), n) };
        assert_eq!(status, fmi3OK, "{}", self.log());
        values
    }

    fn set(&self, name: &str, values: &[f64]) -> fmi3Status {
        let vr = Plant::vr(name);
        // SAFETY: as in `get`.
        unsafe { fmu::fmi3SetFloat64(self.c, &vr, 1, values.as_ptr(), values.len()) }
    }

    fn init(&self) {
        // SAFETY: a live instance.
        unsafe {
            assert_eq!(
                fmu::fmi3EnterInitializationMode(self.c, false, 0.0, 0.0, false, 0.0),
                fmi3OK
            );
            assert_eq!(fmu::fmi3ExitInitializationMode(self.c), fmi3OK);
        }
    }

    fn step(&self, t: f64, h: f64) -> (fmi3Status, bool, f64) {
        let (status, terminate, early, last) = self.step_early(t, h);
        assert!(!early);
        (status, terminate, last)
    }

    /// A step, with `earlyReturn` (`eventHandlingNeeded` must stay false: no Event Mode).
    fn step_early(&self, t: f64, h: f64) -> (fmi3Status, bool, bool, f64) {
        let (mut event, mut terminate, mut early, mut last) = (true, true, true, f64::NAN);
        // SAFETY: a live instance and valid out-parameters.
        let status = unsafe {
            fmu::fmi3DoStep(
                self.c,
                t,
                h,
                true,
                &mut event,
                &mut terminate,
                &mut early,
                &mut last,
            )
        };
        assert!(!event);
        (status, terminate, early, last)
    }
}

impl Drop for Plant {
    fn drop(&mut self) {
        // SAFETY: created by instantiate, freed once.
        unsafe { fmu::fmi3FreeInstance(self.c) };
    }
}

#[test]
fn vectors_are_arrays_and_the_plant_falls() {
    let plant = Plant::co_simulation();
    assert_eq!(plant.set("r0_nue", &[10.0, 500.0, -20.0]), fmi3OK);
    plant.init();
    assert_eq!(plant.get("r_nue", 3), [10.0, 500.0, -20.0]);
    assert_eq!(plant.get("q_body_to_nue", 4), [1.0, 0.0, 0.0, 0.0]);
    for k in 0..10 {
        let (status, terminate, last) = plant.step(k as f64 * 0.1, 0.1);
        assert_eq!((status, terminate), (fmi3OK, false));
        assert!((last - (k + 1) as f64 * 0.1).abs() < 1e-12);
    }
    let r = plant.get("r_nue", 3);
    assert!((r[1] - (500.0 - 0.81)).abs() < 1e-9, "{r:?}");
    // `time` (the independent variable) reads beside the others, as one element
    let vrs = [
        Plant::vr("mass"),
        fmi3_export::variables::TIME_VR,
        Plant::vr("r_nue"),
    ];
    let mut values = [f64::NAN; 5];
    // SAFETY: a live instance, 1 + 1 + 3 values.
    let status = unsafe { fmu::fmi3GetFloat64(plant.c, vrs.as_ptr(), 3, values.as_mut_ptr(), 5) };
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
        let plant = Plant::co_simulation_with(early_return_allowed);
        plant.set("r0_nue", &[0.0, 0.81, 0.0]);
        plant.init();
        // WHEN a step of 2 s passes the touchdown
        let (status, terminate, early, last) = plant.step_early(0.0, 2.0);
        // THEN the step succeeded and the FMU asks to end the run
        assert_eq!(status, fmi3OK, "{}", plant.log());
        assert!(terminate);
        if early_return_allowed {
            // returning at the touchdown
            assert!(early);
            assert!((last - 1.0).abs() < 1e-9, "{last}");
        } else {
            // or, without early return, at the step's end, frozen at the touchdown
            assert!(!early);
            assert_eq!(last, 2.0);
        }
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
    let plant = Plant::co_simulation();
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
        "fmi3SetFloat64: variable m0 (vr 113): value -5 is outside (0, inf)",
        "fmi3SetFloat64: variable m0 (vr 113): value NaN is not finite",
        "a fixed parameter can only be set before the end of initialization",
        "variable mass (vr 23) cannot be set: an output is computed by the FMU",
    ] {
        assert!(log.contains(expected), "missing {expected:?} in\n{log}");
    }
}

#[test]
fn missing_features_and_the_other_interface_answer_error_with_a_reason() {
    let plant = Plant::co_simulation();
    plant.init();
    let mut active = [false];
    let vr = 1u32;
    let x = [0.0; 18];
    // SAFETY: a live instance and valid arrays.
    unsafe {
        assert_eq!(
            fmu::fmi3GetClock(plant.c, &vr, 1, active.as_mut_ptr()),
            fmi3Error
        );
        assert_eq!(
            fmu::fmi3SetContinuousStates(plant.c, x.as_ptr(), 18),
            fmi3Error
        );
        assert_eq!(fmu::fmi3EnterConfigurationMode(plant.c), fmi3Error);
    }
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
    let plant = Plant::co_simulation();
    plant.set("omega0_body", &[0.3, -0.2, 0.1]);
    plant.init();
    for k in 0..5 {
        plant.step(k as f64 * 0.1, 0.1);
    }
    let mut state: fmi3FMUState = std::ptr::null_mut();
    let mut size = 0usize;
    // SAFETY: a live instance; buffers of the announced size.
    let bytes = unsafe {
        assert_eq!(fmu::fmi3GetFMUState(plant.c, &mut state), fmi3OK);
        assert_eq!(
            fmu::fmi3SerializedFMUStateSize(plant.c, state, &mut size),
            fmi3OK
        );
        let mut bytes = vec![0u8; size];
        assert_eq!(
            fmu::fmi3SerializeFMUState(plant.c, state, bytes.as_mut_ptr(), size),
            fmi3OK
        );
        assert_eq!(fmu::fmi3FreeFMUState(plant.c, &mut state), fmi3OK);
        bytes
    };
    assert_eq!(&bytes[..8], b"FMI3SNAP");
    for k in 5..10 {
        plant.step(k as f64 * 0.1, 0.1);
    }
    let reference = plant.get("q_body_to_nue", 4);
    // SAFETY: as above.
    unsafe {
        let mut restored: fmi3FMUState = std::ptr::null_mut();
        assert_eq!(
            fmu::fmi3DeserializeFMUState(plant.c, bytes.as_ptr(), bytes.len(), &mut restored),
            fmi3OK
        );
        assert_eq!(fmu::fmi3SetFMUState(plant.c, restored), fmi3OK);
        fmu::fmi3FreeFMUState(plant.c, &mut restored);
        let mut corrupt = bytes.clone();
        let last = corrupt.len() - 1;
        corrupt[last] ^= 0xff;
        let mut refused: fmi3FMUState = std::ptr::null_mut();
        assert_eq!(
            fmu::fmi3DeserializeFMUState(plant.c, corrupt.as_ptr(), corrupt.len(), &mut refused),
            fmi3Error
        );
    }
    for k in 5..10 {
        plant.step(k as f64 * 0.1, 0.1);
    }
    assert_eq!(plant.get("q_body_to_nue", 4), reference, "bit for bit");
    assert!(plant.log().contains("checksum"), "{}", plant.log());
}

#[test]
fn a_wrong_instantiation_token_gives_null_and_says_why() {
    let sink = Box::<Sink>::default();
    // SAFETY: valid strings; the sink outlives the call.
    let c = unsafe {
        fmu::fmi3InstantiateModelExchange(
            c"plant".as_ptr(),
            c"{not-the-token}".as_ptr(),
            std::ptr::null(),
            false,
            false,
            &*sink as *const Sink as *mut c_void,
            Some(record),
        )
    };
    assert!(c.is_null());
    let log = sink.0.lock().unwrap();
    assert!(
        log[0].1.contains(
            "fmi3InstantiateModelExchange: instantiationToken \"{not-the-token}\" does not match"
        ),
        "{log:?}"
    );
}

#[test]
fn integers_and_booleans_cross_with_their_checks() {
    let plant = Plant::co_simulation();
    let (count, model) = (Plant::vr("engine_count"), Plant::vr("translation_model"));
    let touchdown = Plant::vr("touchdown");
    // SAFETY: a live instance; one value per variable.
    unsafe {
        // engine_count >= 1: 0 is refused, and nothing is written by the refused pair;
        // translation_model (a selector exchanged as Int32) accepts only its items
        assert_eq!(
            fmu::fmi3SetInt32(plant.c, [model, count].as_ptr(), 2, [2, 0].as_ptr(), 2),
            fmi3Error
        );
        assert_eq!(fmu::fmi3SetInt32(plant.c, &model, 1, &3, 1), fmi3Error);
        let mut got = [0i32; 2];
        assert_eq!(
            fmu::fmi3GetInt32(plant.c, [model, count].as_ptr(), 2, got.as_mut_ptr(), 2),
            fmi3Error,
            "no get before initialization mode"
        );
        plant.init();
        assert_eq!(
            fmu::fmi3GetInt32(plant.c, [model, count].as_ptr(), 2, got.as_mut_ptr(), 2),
            fmi3OK
        );
        assert_eq!(got, [1, 2], "flat model, two engines: the start values");
        let mut down = [true];
        assert_eq!(
            fmu::fmi3GetBoolean(plant.c, &touchdown, 1, down.as_mut_ptr(), 1),
            fmi3OK
        );
        assert_eq!(down, [false]);
        assert_eq!(
            fmu::fmi3SetBoolean(plant.c, &touchdown, 1, [true].as_ptr(), 1),
            fmi3Error
        );
        // a Float64 value reference asked for as Int32
        assert_eq!(
            fmu::fmi3GetInt32(plant.c, &Plant::vr("mass"), 1, got.as_mut_ptr(), 1),
            fmi3Error
        );
    }
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
    let plant = Plant::co_simulation();
    // SAFETY: a live instance.
    unsafe {
        assert_eq!(
            fmu::fmi3EnterInitializationMode(plant.c, false, 0.0, 0.0, false, 0.0),
            fmi3OK
        );
    }
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
    let vrs: Vec<u32> = names.iter().map(|(n, _)| Plant::vr(n)).collect();
    let total: usize = names.iter().map(|(_, n)| n).sum();
    // Every value nudged from what the one-variable gets show.
    let mut values: Vec<f64> = names
        .iter()
        .flat_map(|&(n, len)| plant.get(n, len))
        .map(|v| if v == 0.0 { 0.25 } else { v * 1.01 })
        .collect();
    // SAFETY: arrays of the lengths passed.
    let status =
        unsafe { fmu::fmi3SetFloat64(plant.c, vrs.as_ptr(), vrs.len(), values.as_ptr(), total) };
    assert_eq!(status, fmi3OK, "{}", plant.log());
    let one_by_one: Vec<f64> = names
        .iter()
        .flat_map(|&(n, len)| plant.get(n, len))
        .collect();
    assert_eq!(one_by_one, values);
    // AND a get of them all, with `time` in the middle, reads the same
    let mut with_time = vrs.clone();
    with_time.insert(5, fmi3_export::variables::TIME_VR);
    let mut read = vec![f64::NAN; total + 1];
    // SAFETY: as above.
    let status = unsafe {
        fmu::fmi3GetFloat64(
            plant.c,
            with_time.as_ptr(),
            with_time.len(),
            read.as_mut_ptr(),
            total + 1,
        )
    };
    assert_eq!(status, fmi3OK, "{}", plant.log());
    let time_at = names[..5].iter().map(|(_, n)| n).sum::<usize>();
    assert_eq!(read.remove(time_at), 0.0, "time");
    assert_eq!(read, values);
    // AND a get or set with one value too few or too many, or an unknown reference among
    // them, is refused naming the fault
    for (n, expect) in [(total - 1, "nValues"), (total + 1, "nValues")] {
        let mut buffer = vec![0.0; total + 1];
        // SAFETY: buffers at least as long as the counts passed.
        let (get, set) = unsafe {
            (
                fmu::fmi3GetFloat64(plant.c, vrs.as_ptr(), vrs.len(), buffer.as_mut_ptr(), n),
                fmu::fmi3SetFloat64(plant.c, vrs.as_ptr(), vrs.len(), buffer.as_ptr(), n),
            )
        };
        assert_eq!((get, set), (fmi3Error, fmi3Error), "{n}");
        assert!(plant.log().contains(expect), "{}", plant.log());
    }
    let mut unknown = vrs.clone();
    unknown[7] = 77_777;
    let mut buffer = vec![0.0; total];
    // SAFETY: as above.
    let get = unsafe {
        fmu::fmi3GetFloat64(
            plant.c,
            unknown.as_ptr(),
            unknown.len(),
            buffer.as_mut_ptr(),
            total,
        )
    };
    assert_eq!(get, fmi3Error);
    assert!(plant.log().contains("77777"), "{}", plant.log());
    // AND a NaN in the last variable refuses the whole call
    let before = values.clone();
    *values.last_mut().unwrap() = f64::NAN;
    // SAFETY: as above.
    let status =
        unsafe { fmu::fmi3SetFloat64(plant.c, vrs.as_ptr(), vrs.len(), values.as_ptr(), total) };
    assert_eq!(status, fmi3Error);
    let after: Vec<f64> = names
        .iter()
        .flat_map(|&(n, len)| plant.get(n, len))
        .collect();
    assert_eq!(after, before);
}
