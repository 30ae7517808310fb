//! Test driver for the Oscillator's exported C functions.
//!
//! The logger: a C-variadic callback cannot be defined in stable Rust, so the recorder is
//! declared with the fixed arguments the layer passes (`"%s"` and one `const char*`) and
//! transmuted into the variadic pointer type. On x86-64 System V and AArch64 Linux a
//! variadic call with those arguments places them exactly where a non-variadic callee
//! reads them; the recorder also asserts that the format really is "%s".
#![allow(dead_code, unsafe_code)]

use fmi2_export::ffi::*;
use fmu_testmodel as fmu;
use std::ffi::{c_char, c_void, CStr, CString};
use std::sync::Mutex;

pub mod vr {
    pub const X0: u32 = 0;
    pub const K: u32 = 1;
    pub const C: u32 = 2;
    pub const THRESHOLD: u32 = 3;
    pub const U: u32 = 4;
    pub const X: u32 = 5;
    pub const V: u32 = 6;
    pub const OMEGA_N: u32 = 7;
    pub const MASS: u32 = 8;
    pub const STEP_COUNT: u32 = 0;
    pub const SUBSTEPS: u32 = 1;
    pub const CROSSING: u32 = 2;
    pub const STOP_AT_THRESHOLD: u32 = 0;
    pub const LABEL: u32 = 0;
}

#[derive(Debug, Clone)]
pub struct Record {
    pub environment: usize,
    pub instance: String,
    pub status: fmi2Status,
    pub category: String,
    pub message: String,
}

/// What `componentEnvironment` points to.
#[derive(Debug, Default)]
pub struct Sink {
    pub records: Mutex<Vec<Record>>,
}

extern "C" fn record(
    environment: fmi2ComponentEnvironment,
    instance: fmi2String,
    status: fmi2Status,
    category: fmi2String,
    format: fmi2String,
    message: fmi2String,
) {
    let text = |p: *const c_char| unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned();
    assert_eq!(
        text(format),
        "%s",
        "the logger must always get the fixed format"
    );
    let sink = unsafe { &*(environment as *const Sink) };
    sink.records.lock().unwrap().push(Record {
        environment: environment as usize,
        instance: text(instance),
        status,
        category: text(category),
        message: text(message),
    });
}

type FixedLogger = extern "C" fn(
    fmi2ComponentEnvironment,
    fmi2String,
    fmi2Status,
    fmi2String,
    fmi2String,
    fmi2String,
);

pub fn callbacks(sink: &Sink) -> fmi2CallbackFunctions {
    // SAFETY: see the module documentation.
    let logger = unsafe { std::mem::transmute::<FixedLogger, fmi2CallbackLogger>(record) };
    fmi2CallbackFunctions {
        logger,
        allocateMemory: None,
        freeMemory: None,
        stepFinished: None,
        componentEnvironment: sink as *const Sink as *mut c_void,
    }
}

pub fn guid() -> CString {
    CString::new(fmi2_export::guid::<fmu::Oscillator>()).unwrap()
}

/// One instance, freed on drop.
pub struct Fmu {
    pub c: fmi2Component,
    pub sink: Box<Sink>,
    pub name: String,
}

impl Fmu {
    pub fn new(logging_on: bool) -> Fmu {
        Self::named("osc", logging_on)
    }

    pub fn named(name: &str, logging_on: bool) -> Fmu {
        let sink = Box::<Sink>::default();
        let functions = callbacks(&sink);
        let cname = CString::new(name).unwrap();
        let c = unsafe {
            fmu::fmi2Instantiate(
                cname.as_ptr(),
                fmi2CoSimulation,
                guid().as_ptr(),
                c"file:///nowhere".as_ptr(),
                &functions,
                fmi2False,
                logging_on as fmi2Boolean,
            )
        };
        assert!(!c.is_null(), "instantiate failed: {:?}", sink.records);
        Fmu {
            c,
            sink,
            name: name.into(),
        }
    }

    pub fn records(&self) -> Vec<Record> {
        self.sink.records.lock().unwrap().clone()
    }

    pub fn clear(&self) {
        self.sink.records.lock().unwrap().clear();
    }

    /// Messages of non-trace categories.
    pub fn messages(&self) -> Vec<String> {
        self.records()
            .into_iter()
            .filter(|r| r.category != "logCalls")
            .map(|r| r.message)
            .collect()
    }

    pub fn last_message(&self) -> String {
        self.messages().last().cloned().unwrap_or_default()
    }

    pub fn setup(&self, start: f64, stop: Option<f64>) -> fmi2Status {
        unsafe {
            fmu::fmi2SetupExperiment(
                self.c,
                fmi2False,
                0.0,
                start,
                stop.is_some() as fmi2Boolean,
                stop.unwrap_or(0.0),
            )
        }
    }

    pub fn enter_init(&self) -> fmi2Status {
        unsafe { fmu::fmi2EnterInitializationMode(self.c) }
    }

    pub fn exit_init(&self) -> fmi2Status {
        unsafe { fmu::fmi2ExitInitializationMode(self.c) }
    }

    /// Setup at t = 0 without stop time, enter and exit initialization mode.
    pub fn init(&self) {
        assert_eq!(self.setup(0.0, None), fmi2OK);
        assert_eq!(self.enter_init(), fmi2OK);
        assert_eq!(self.exit_init(), fmi2OK, "{:?}", self.messages());
    }

    pub fn step(&self, t: f64, h: f64) -> fmi2Status {
        unsafe { fmu::fmi2DoStep(self.c, t, h, fmi2True) }
    }

    pub fn set_real(&self, vr: u32, value: f64) -> fmi2Status {
        unsafe { fmu::fmi2SetReal(self.c, &vr, 1, &value) }
    }

    pub fn set_integer(&self, vr: u32, value: i32) -> fmi2Status {
        unsafe { fmu::fmi2SetInteger(self.c, &vr, 1, &value) }
    }

    pub fn set_boolean(&self, vr: u32, value: bool) -> fmi2Status {
        let value = value as fmi2Boolean;
        unsafe { fmu::fmi2SetBoolean(self.c, &vr, 1, &value) }
    }

    pub fn set_string(&self, vr: u32, value: &str) -> fmi2Status {
        let value = CString::new(value).unwrap();
        let p = value.as_ptr();
        unsafe { fmu::fmi2SetString(self.c, &vr, 1, &p) }
    }

    pub fn get_real(&self, vr: u32) -> f64 {
        let mut value = f64::NAN;
        let status = unsafe { fmu::fmi2GetReal(self.c, &vr, 1, &mut value) };
        assert!(status <= fmi2Warning, "{status:?}: {:?}", self.messages());
        value
    }

    pub fn get_integer(&self, vr: u32) -> i32 {
        let mut value = -1;
        let status = unsafe { fmu::fmi2GetInteger(self.c, &vr, 1, &mut value) };
        assert!(status <= fmi2Warning, "{status:?}: {:?}", self.messages());
        value
    }

    pub fn get_string(&self, vr: u32) -> String {
        let mut value: fmi2String = std::ptr::null();
        let status = unsafe { fmu::fmi2GetString(self.c, &vr, 1, &mut value) };
        assert_eq!(status, fmi2OK, "{:?}", self.messages());
        unsafe { CStr::from_ptr(value) }
            .to_str()
            .unwrap()
            .to_owned()
    }

    pub fn last_successful_time(&self) -> f64 {
        let mut t = f64::NAN;
        let status = unsafe { fmu::fmi2GetRealStatus(self.c, fmi2LastSuccessfulTime, &mut t) };
        assert_eq!(status, fmi2OK, "{:?}", self.messages());
        t
    }

    pub fn terminated(&self) -> bool {
        let mut b = -1;
        let status = unsafe { fmu::fmi2GetBooleanStatus(self.c, fmi2Terminated, &mut b) };
        assert_eq!(status, fmi2OK, "{:?}", self.messages());
        b == fmi2True
    }

    pub fn get_state(&self) -> fmi2FMUstate {
        let mut state: fmi2FMUstate = std::ptr::null_mut();
        let status = unsafe { fmu::fmi2GetFMUstate(self.c, &mut state) };
        assert_eq!(status, fmi2OK, "{:?}", self.messages());
        state
    }

    pub fn serialize(&self, state: fmi2FMUstate) -> Vec<u8> {
        let mut size = 0usize;
        let status = unsafe { fmu::fmi2SerializedFMUstateSize(self.c, state, &mut size) };
        assert_eq!(status, fmi2OK, "{:?}", self.messages());
        let mut bytes = vec![0u8; size];
        let status = unsafe {
            fmu::fmi2SerializeFMUstate(self.c, state, bytes.as_mut_ptr() as *mut fmi2Byte, size)
        };
        assert_eq!(status, fmi2OK, "{:?}", self.messages());
        bytes
    }

    /// Deserializes into a new FMU state; the status and the state (NULL on failure).
    pub fn deserialize(&self, bytes: &[u8]) -> (fmi2Status, fmi2FMUstate) {
        let mut state: fmi2FMUstate = std::ptr::null_mut();
        let status = unsafe {
            fmu::fmi2DeSerializeFMUstate(
                self.c,
                bytes.as_ptr() as *const fmi2Byte,
                bytes.len(),
                &mut state,
            )
        };
        (status, state)
    }
}

impl Drop for Fmu {
    fn drop(&mut self) {
        unsafe { fmu::fmi2FreeInstance(self.c) };
    }
}

/// Position of m x'' + c x' + k x = u (m = 1) from x(0) = x0, x'(0) = 0, underdamped.
pub fn analytic_x(t: f64, x0: f64, k: f64, c: f64, u: f64) -> f64 {
    let x_eq = u / k;
    let zeta_omega = c / 2.0;
    let omega_d = (k - zeta_omega * zeta_omega).sqrt();
    let a = x0 - x_eq;
    let b = zeta_omega * a / omega_d;
    x_eq + (-zeta_omega * t).exp() * (a * (omega_d * t).cos() + b * (omega_d * t).sin())
}
