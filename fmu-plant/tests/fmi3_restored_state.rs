//! Restored FMU states through the FMI 3.0 C functions: a buffer resealed with a valid
//! header and checksum is accepted only if the plant could have reached the state it holds
//! (the checks the FMI 2.0 layer makes); a refusal names the field and leaves the instance
//! as it was. Also: communication points a corrupt or crafted time cannot sneak past.
#![allow(unsafe_code)]

use fmi3_export::ffi::*;
use fmi_model::snapshot::{reseal, HEADER_LEN};
use fmi_model::Model;
use fmu_plant as fmu;
use std::ffi::{c_void, CStr, CString};
use std::ptr;
use std::sync::Mutex;

#[derive(Default)]
struct Sink(Mutex<Vec<String>>);

unsafe extern "C" fn record(
    environment: fmi3InstanceEnvironment,
    _status: fmi3Status,
    _category: fmi3String,
    message: fmi3String,
) {
    // SAFETY: the environment is our Sink, the message a NUL-terminated string.
    let sink = unsafe { &*(environment as *const Sink) };
    let text = unsafe { CStr::from_ptr(message) }.to_string_lossy();
    sink.0.lock().unwrap().push(text.into_owned());
}

fn vr(name: &str) -> u32 {
    fmu::LanderPlant::declarations()
        .iter()
        .find(|d| d.name == name)
        .unwrap_or_else(|| panic!("no declaration {name}"))
        .value_reference
}

struct Plant {
    c: fmi3Instance,
    sink: Box<Sink>,
}

impl Plant {
    fn new() -> Plant {
        let sink = Box::<Sink>::default();
        let token = CString::new(fmi3_export::instantiation_token::<fmu::LanderPlant>()).unwrap();
        // SAFETY: valid strings; the sink outlives the instance.
        let c = unsafe {
            fmu::fmi3InstantiateCoSimulation(
                c"plant".as_ptr(),
                token.as_ptr(),
                ptr::null(),
                false,
                false,
                false,
                false,
                ptr::null(),
                0,
                &*sink as *const Sink as *mut c_void,
                Some(record),
                None,
            )
        };
        assert!(!c.is_null());
        Plant { c, sink }
    }

    fn last_message(&self) -> String {
        self.sink
            .0
            .lock()
            .unwrap()
            .last()
            .cloned()
            .unwrap_or_default()
    }

    fn set(&self, name: &str, values: &[f64]) {
        let vr = vr(name);
        // SAFETY: a live instance; as many values as the variable has elements.
        let s = unsafe { fmu::fmi3SetFloat64(self.c, &vr, 1, values.as_ptr(), values.len()) };
        assert_eq!(s, fmi3OK, "{}", self.last_message());
    }

    fn set_int(&self, name: &str, value: i32) {
        let vr = vr(name);
        // SAFETY: a live instance, one value.
        let s = unsafe { fmu::fmi3SetInt32(self.c, &vr, 1, &value, 1) };
        assert_eq!(s, fmi3OK, "{}", self.last_message());
    }

    fn get(&self, name: &str, n: usize) -> Vec<f64> {
        let vr = vr(name);
        let mut values = vec![f64::NAN; n];
        // SAFETY: a live instance, n values for an n-element variable.
        let s = unsafe { fmu::fmi3GetFloat64(self.c, &vr, 1, values.as_mut_ptr(), n) };
        assert_eq!(s, fmi3OK, "{}", self.last_message());
        values
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

    fn step(&self, t: f64, h: f64) -> fmi3Status {
        let (mut event, mut terminate, mut early, mut last) = (false, false, false, 0.0);
        // SAFETY: a live instance and valid out-parameters.
        unsafe {
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
        }
    }

    /// The instance's current state, serialized.
    fn genuine(&self) -> Vec<u8> {
        let mut state: fmi3FMUState = ptr::null_mut();
        let mut size = 0;
        // SAFETY: a live instance, out-pointers, a buffer of the size the FMU gave.
        unsafe {
            assert_eq!(fmu::fmi3GetFMUState(self.c, &mut state), fmi3OK);
            assert_eq!(
                fmu::fmi3SerializedFMUStateSize(self.c, state, &mut size),
                fmi3OK
            );
            let mut bytes = vec![0u8; size];
            assert_eq!(
                fmu::fmi3SerializeFMUState(self.c, state, bytes.as_mut_ptr(), size),
                fmi3OK
            );
            assert_eq!(fmu::fmi3FreeFMUState(self.c, &mut state), fmi3OK);
            bytes
        }
    }

    /// fmi3DeserializeFMUState then, if accepted, fmi3SetFMUState and fmi3FreeFMUState.
    fn restore(&self, bytes: &[u8]) -> fmi3Status {
        let mut state: fmi3FMUState = ptr::null_mut();
        // SAFETY: a live instance, a buffer of `len` bytes, an out-pointer.
        unsafe {
            let s = fmu::fmi3DeserializeFMUState(self.c, bytes.as_ptr(), bytes.len(), &mut state);
            if s != fmi3OK {
                assert!(state.is_null());
                return s;
            }
            assert_eq!(fmu::fmi3SetFMUState(self.c, state), fmi3OK);
            assert_eq!(fmu::fmi3FreeFMUState(self.c, &mut state), fmi3OK);
            s
        }
    }
}

impl Drop for Plant {
    fn drop(&mut self) {
        // SAFETY: created by instantiate, freed once.
        unsafe { fmu::fmi3FreeInstance(self.c) };
    }
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
    let plant = Plant::new();
    plant.set("omega0_body", &[0.011, 0.0, 0.02]);
    plant.set("isp", &[301.25]);
    plant.init();
    plant.set("thrust_cmd", &[1200.0]);
    for k in 0..5 {
        assert_eq!(plant.step(f64::from(k) * 0.1, 0.1), fmi3OK);
    }
    plant
}

#[test]
fn a_genuine_state_round_trips() {
    let plant = flying();
    let bytes = plant.genuine();
    let mass = plant.get("mass", 1);
    assert_eq!(plant.step(0.5, 0.1), fmi3OK);
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
        assert_eq!(plant.step(0.5, 0.1), fmi3OK);
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
    let plant = Plant::new();
    let flat = plant.genuine();
    plant.set_int("translation_model", 2);
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
    assert_eq!(plant.step(1.5e308, 1.5e308), fmi3Error);
    assert!(
        plant
            .last_message()
            .contains("does not advance a finite time"),
        "{}",
        plant.last_message()
    );
    // AND so are points that do not match, or are not numbers
    for t in [f64::NAN, f64::INFINITY, 0.5] {
        assert_eq!(plant.step(t, 0.1), fmi3Error, "{t}");
    }
}

#[test]
fn model_exchange_set_time_refuses_a_time_that_is_not_finite_or_before_the_start() {
    let sink = Box::<Sink>::default();
    let token = CString::new(fmi3_export::instantiation_token::<fmu::LanderPlant>()).unwrap();
    // SAFETY: valid strings; the sink outlives the instance.
    let c = unsafe {
        fmu::fmi3InstantiateModelExchange(
            c"plant".as_ptr(),
            token.as_ptr(),
            ptr::null(),
            false,
            false,
            &*sink as *const Sink as *mut c_void,
            Some(record),
        )
    };
    assert!(!c.is_null());
    let plant = Plant { c, sink };
    // SAFETY: a live instance.
    unsafe {
        assert_eq!(
            fmu::fmi3EnterInitializationMode(c, false, 0.0, 10.0, false, 0.0),
            fmi3OK
        );
        assert_eq!(fmu::fmi3ExitInitializationMode(c), fmi3OK);
        assert_eq!(fmu::fmi3EnterContinuousTimeMode(c), fmi3OK);
        for t in [f64::NAN, f64::NEG_INFINITY, 9.0, -1e300] {
            assert_eq!(fmu::fmi3SetTime(c, t), fmi3Error, "{t}");
        }
        assert!(
            plant.last_message().contains("before the start time 10"),
            "{}",
            plant.last_message()
        );
        assert_eq!(fmu::fmi3SetTime(c, 10.5), fmi3OK);
    }
}
