//! A small driver of LanderPlant's exported C functions, as a master would call them.
//!
//! The logger: a C-variadic callback cannot be defined in stable Rust, so the recorder is
//! declared with the fixed arguments the layer passes (`"%s"` and one `const char*`) and
//! transmuted into the variadic pointer type. On x86-64 System V and AArch64 Linux a
//! variadic call with those arguments places them exactly where a non-variadic callee reads
//! them.
#![allow(dead_code, unsafe_code)]

use fmi2_export::ffi::*;
use fmu_plant as fmu;
use std::ffi::{c_void, CStr, CString};
use std::sync::Mutex;

/// Looks a value reference up by name in the variable table (the single declaration).
pub fn vr(name: &str) -> u32 {
    fmi2_export::variables::<fmu::LanderPlant>()
        .iter()
        .find(|v| v.name == name)
        .unwrap_or_else(|| panic!("no variable {name}"))
        .value_reference
}

/// What `componentEnvironment` points to.
#[derive(Debug, Default)]
pub struct Sink {
    pub messages: Mutex<Vec<(fmi2Status, String)>>,
}

extern "C" fn record(
    environment: fmi2ComponentEnvironment,
    _instance: fmi2String,
    status: fmi2Status,
    _category: fmi2String,
    _format: fmi2String,
    message: fmi2String,
) {
    let text = unsafe { CStr::from_ptr(message) }
        .to_string_lossy()
        .into_owned();
    let sink = unsafe { &*(environment as *const Sink) };
    sink.messages.lock().unwrap().push((status, text));
}

type FixedLogger = extern "C" fn(
    fmi2ComponentEnvironment,
    fmi2String,
    fmi2Status,
    fmi2String,
    fmi2String,
    fmi2String,
);

/// One instance, freed on drop.
pub struct Plant {
    pub c: fmi2Component,
    sink: Box<Sink>,
}

impl Plant {
    pub fn new() -> Plant {
        Plant::instantiate(fmi2CoSimulation)
    }

    /// An instance for Model Exchange.
    pub fn model_exchange() -> Plant {
        Plant::instantiate(fmi2ModelExchange)
    }

    fn instantiate(fmu_type: fmi2Type) -> Plant {
        let sink = Box::<Sink>::default();
        // SAFETY: see the module documentation.
        let logger = unsafe { std::mem::transmute::<FixedLogger, fmi2CallbackLogger>(record) };
        let functions = fmi2CallbackFunctions {
            logger,
            allocateMemory: None,
            freeMemory: None,
            stepFinished: None,
            componentEnvironment: &*sink as *const Sink as *mut c_void,
        };
        let guid = CString::new(fmi2_export::guid::<fmu::LanderPlant>()).unwrap();
        let c = unsafe {
            fmu::fmi2Instantiate(
                c"plant".as_ptr(),
                fmu_type,
                guid.as_ptr(),
                c"file:///nowhere".as_ptr(),
                &functions,
                fmi2False,
                fmi2False,
            )
        };
        assert!(!c.is_null(), "instantiate failed: {:?}", sink.messages);
        Plant { c, sink }
    }

    pub fn messages(&self) -> Vec<String> {
        self.sink
            .messages
            .lock()
            .unwrap()
            .iter()
            .map(|(_, m)| m.clone())
            .collect()
    }

    /// Setup at t = 0, enter initialization mode (parameters can be set afterwards).
    pub fn enter_init(&self) {
        assert_eq!(
            unsafe { fmu::fmi2SetupExperiment(self.c, fmi2False, 0.0, 0.0, fmi2False, 0.0) },
            fmi2Status::fmi2OK
        );
        assert_eq!(
            unsafe { fmu::fmi2EnterInitializationMode(self.c) },
            fmi2Status::fmi2OK
        );
    }

    pub fn exit_init(&self) -> fmi2Status {
        unsafe { fmu::fmi2ExitInitializationMode(self.c) }
    }

    pub fn init(&self) {
        self.enter_init();
        assert_eq!(
            self.exit_init(),
            fmi2Status::fmi2OK,
            "{:?}",
            self.messages()
        );
    }

    pub fn step(&self, t: f64, h: f64) -> fmi2Status {
        unsafe { fmu::fmi2DoStep(self.c, t, h, fmi2True) }
    }

    pub fn set(&self, name: &str, value: f64) {
        let r = vr(name);
        let status = unsafe { fmu::fmi2SetReal(self.c, &r, 1, &value) };
        assert_eq!(
            status,
            fmi2Status::fmi2OK,
            "set {name}: {:?}",
            self.messages()
        );
    }

    pub fn set_integer(&self, name: &str, value: i32) {
        let r = vr(name);
        let status = unsafe { fmu::fmi2SetInteger(self.c, &r, 1, &value) };
        assert_eq!(
            status,
            fmi2Status::fmi2OK,
            "set {name}: {:?}",
            self.messages()
        );
    }

    pub fn get(&self, name: &str) -> f64 {
        let r = vr(name);
        let mut value = f64::NAN;
        let status = unsafe { fmu::fmi2GetReal(self.c, &r, 1, &mut value) };
        assert!(
            status <= fmi2Status::fmi2Warning,
            "get {name}: {status:?} {:?}",
            self.messages()
        );
        value
    }

    pub fn get_many(&self, vrs: &[u32]) -> Vec<f64> {
        let mut values = vec![f64::NAN; vrs.len()];
        let status =
            unsafe { fmu::fmi2GetReal(self.c, vrs.as_ptr(), vrs.len(), values.as_mut_ptr()) };
        assert!(
            status <= fmi2Status::fmi2Warning,
            "{status:?} {:?}",
            self.messages()
        );
        values
    }

    pub fn get_boolean(&self, name: &str) -> bool {
        let r = vr(name);
        let mut value = -1;
        let status = unsafe { fmu::fmi2GetBoolean(self.c, &r, 1, &mut value) };
        assert!(status <= fmi2Status::fmi2Warning, "get {name}: {status:?}");
        value == fmi2True
    }

    pub fn last_successful_time(&self) -> f64 {
        let mut t = f64::NAN;
        let status = unsafe { fmu::fmi2GetRealStatus(self.c, fmi2LastSuccessfulTime, &mut t) };
        assert_eq!(status, fmi2Status::fmi2OK);
        t
    }

    pub fn terminated(&self) -> bool {
        let mut b = -1;
        let status = unsafe { fmu::fmi2GetBooleanStatus(self.c, fmi2Terminated, &mut b) };
        assert_eq!(status, fmi2Status::fmi2OK);
        b == fmi2True
    }

    pub fn get_state(&self) -> fmi2FMUstate {
        let mut state: fmi2FMUstate = std::ptr::null_mut();
        assert_eq!(
            unsafe { fmu::fmi2GetFMUstate(self.c, &mut state) },
            fmi2Status::fmi2OK
        );
        state
    }

    pub fn set_state(&self, state: fmi2FMUstate) {
        assert_eq!(
            unsafe { fmu::fmi2SetFMUstate(self.c, state) },
            fmi2Status::fmi2OK
        );
    }

    pub fn free_state(&self, mut state: fmi2FMUstate) {
        assert_eq!(
            unsafe { fmu::fmi2FreeFMUstate(self.c, &mut state) },
            fmi2Status::fmi2OK
        );
    }

    pub fn serialize(&self, state: fmi2FMUstate) -> Vec<u8> {
        let mut size = 0usize;
        assert_eq!(
            unsafe { fmu::fmi2SerializedFMUstateSize(self.c, state, &mut size) },
            fmi2Status::fmi2OK
        );
        let mut bytes = vec![0u8; size];
        let status = unsafe {
            fmu::fmi2SerializeFMUstate(self.c, state, bytes.as_mut_ptr() as *mut fmi2Byte, size)
        };
        assert_eq!(status, fmi2Status::fmi2OK);
        bytes
    }

    pub fn deserialize(&self, bytes: &[u8]) -> fmi2FMUstate {
        let mut state: fmi2FMUstate = std::ptr::null_mut();
        let status = unsafe {
            fmu::fmi2DeSerializeFMUstate(
                self.c,
                bytes.as_ptr() as *const fmi2Byte,
                bytes.len(),
                &mut state,
            )
        };
        assert_eq!(status, fmi2Status::fmi2OK);
        state
    }
}

impl Default for Plant {
    fn default() -> Self {
        Self::new()
    }
}

impl Drop for Plant {
    fn drop(&mut self) {
        unsafe { fmu::fmi2FreeInstance(self.c) };
    }
}

/// The LanderPlant outputs of the INTERFACE contract, in order.
pub const NAVIGATION_OUTPUTS: [&str; 14] = [
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

pub fn navigation_vrs() -> Vec<u32> {
    NAVIGATION_OUTPUTS.iter().map(|n| vr(n)).collect()
}
