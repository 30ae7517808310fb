//! Driver for LanderGnc's exported C functions (the same calls a master makes).
//!
//! The logger: a C-variadic callback cannot be defined in stable Rust, so the recorder is
//! declared with the fixed arguments the layer passes (`"%s"` and one `const char*`) and
//! transmuted into the variadic pointer type, as in the export layer's own tests.
#![allow(dead_code, unsafe_code)]

use fmi2_export::ffi::*;
use fmu_gnc as fmu;
use std::ffi::{c_char, c_void, CStr, CString};
use std::sync::Mutex;

pub mod vr {
    pub const R_NUE: [u32; 3] = [1, 2, 3];
    pub const V_NUE: [u32; 3] = [4, 5, 6];
    pub const Q_BODY_TO_NUE: [u32; 4] = [7, 8, 9, 10];
    pub const OMEGA_BODY: [u32; 3] = [11, 12, 13];
    pub const MASS: u32 = 14;
    pub const THRUST_CMD: u32 = 100;
    pub const TORQUE_CMD_BODY: [u32; 3] = [101, 102, 103];
    pub const GUIDANCE_PHASE: u32 = 122;
    pub const TIME_TO_GO: u32 = 123;
    pub const CONTROL_LAW: u32 = 200;
    pub const PHI_CMD: u32 = 201;
    pub const CONTROL_BANDWIDTH: u32 = 203;
    /// thrust_cmd, torque_cmd_body[1..3], a_cmd_nue[1..3], q_ref[1..4], phi_b, err_*, tilt, tgo
    pub const ALL_REAL_OUTPUTS: [u32; 17] = [
        100, 101, 102, 103, 110, 111, 112, 113, 114, 115, 116, 117, 118, 119, 120, 121, 123,
    ];
}

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
    let text = unsafe { CStr::from_ptr(message as *const c_char) }
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
pub struct Gnc {
    pub c: fmi2Component,
    pub sink: Box<Sink>,
}

impl Gnc {
    pub fn new() -> Gnc {
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
        let guid = CString::new(fmi2_export::guid::<fmu::LanderGnc>()).unwrap();
        let c = unsafe {
            fmu::fmi2Instantiate(
                c"gnc".as_ptr(),
                fmi2CoSimulation,
                guid.as_ptr(),
                c"file:///nowhere".as_ptr(),
                &functions,
                fmi2False,
                fmi2False,
            )
        };
        assert!(!c.is_null(), "instantiate failed: {:?}", sink.messages);
        Gnc { c, sink }
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

    /// Set up at t = 0 and enter and leave initialization mode.
    pub fn initialize(&self) -> fmi2Status {
        unsafe {
            assert_eq!(
                fmu::fmi2SetupExperiment(self.c, fmi2False, 0.0, 0.0, fmi2False, 0.0),
                fmi2OK
            );
            assert_eq!(fmu::fmi2EnterInitializationMode(self.c), fmi2OK);
            fmu::fmi2ExitInitializationMode(self.c)
        }
    }

    pub fn set_reals(&self, vrs: &[u32], values: &[f64]) -> fmi2Status {
        assert_eq!(vrs.len(), values.len());
        unsafe { fmu::fmi2SetReal(self.c, vrs.as_ptr(), vrs.len(), values.as_ptr()) }
    }

    pub fn get_reals(&self, vrs: &[u32]) -> (fmi2Status, Vec<f64>) {
        let mut values = vec![0.0; vrs.len()];
        let status =
            unsafe { fmu::fmi2GetReal(self.c, vrs.as_ptr(), vrs.len(), values.as_mut_ptr()) };
        (status, values)
    }

    pub fn get_integer(&self, vr: u32) -> i32 {
        let mut value = 0;
        let status = unsafe { fmu::fmi2GetInteger(self.c, &vr, 1, &mut value) };
        assert_eq!(status, fmi2OK);
        value
    }

    pub fn set_integer(&self, vr: u32, value: i32) -> fmi2Status {
        unsafe { fmu::fmi2SetInteger(self.c, &vr, 1, &value) }
    }

    /// Set the navigation inputs: r, v, q (scalar first), omega, mass.
    pub fn set_navigation(
        &self,
        r: [f64; 3],
        v: [f64; 3],
        q: [f64; 4],
        w: [f64; 3],
        m: f64,
    ) -> fmi2Status {
        let vrs: Vec<u32> = vr::R_NUE
            .iter()
            .chain(&vr::V_NUE)
            .chain(&vr::Q_BODY_TO_NUE)
            .chain(&vr::OMEGA_BODY)
            .chain(&[vr::MASS])
            .copied()
            .collect();
        let values: Vec<f64> = r
            .iter()
            .chain(&v)
            .chain(&q)
            .chain(&w)
            .chain(&[m])
            .copied()
            .collect();
        self.set_reals(&vrs, &values)
    }

    pub fn do_step(&self, t: f64, h: f64) -> fmi2Status {
        unsafe { fmu::fmi2DoStep(self.c, t, h, fmi2True) }
    }
}

impl Drop for Gnc {
    fn drop(&mut self) {
        unsafe { fmu::fmi2FreeInstance(self.c) };
    }
}
