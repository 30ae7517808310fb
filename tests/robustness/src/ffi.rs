//! The FMI 2.0 C types as a master sees them, declared here by hand from
//! `fmi2TypesPlatform.h` and `fmi2FunctionTypes.h` so that the fuzzer calls the FMUs exactly
//! as a C master would, with no Rust type of the export layer in between.
//!
//! The status an FMU returns is read as a plain `c_int`: the tests must be able to see any
//! value a broken FMU could return, and a Rust enum holding an undeclared value would be
//! undefined behaviour.
#![allow(non_camel_case_types)]

use std::ffi::{c_char, c_int, c_void};

pub type fmi2Component = *mut c_void;
pub type fmi2ComponentEnvironment = *mut c_void;
pub type fmi2FMUstate = *mut c_void;
pub type fmi2ValueReference = u32;
pub type fmi2Real = f64;
pub type fmi2Integer = i32;
pub type fmi2Boolean = i32;
pub type fmi2String = *const c_char;
pub type fmi2Byte = c_char;
pub type fmi2Status = c_int;
pub type fmi2Type = c_int;
pub type fmi2StatusKind = c_int;

pub const OK: fmi2Status = 0;
pub const WARNING: fmi2Status = 1;
pub const DISCARD: fmi2Status = 2;
pub const ERROR: fmi2Status = 3;
pub const FATAL: fmi2Status = 4;
pub const PENDING: fmi2Status = 5;

pub const MODEL_EXCHANGE: fmi2Type = 0;
pub const CO_SIMULATION: fmi2Type = 1;

pub const DO_STEP_STATUS: fmi2StatusKind = 0;
pub const PENDING_STATUS: fmi2StatusKind = 1;
pub const LAST_SUCCESSFUL_TIME: fmi2StatusKind = 2;
pub const TERMINATED: fmi2StatusKind = 3;

/// The variadic `fmi2CallbackLogger`.
pub type Logger = unsafe extern "C" fn(
    fmi2ComponentEnvironment,
    fmi2String,
    fmi2Status,
    fmi2String,
    fmi2String,
    ...
);

#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct fmi2CallbackFunctions {
    pub logger: Option<Logger>,
    pub allocate_memory: Option<unsafe extern "C" fn(usize, usize) -> *mut c_void>,
    pub free_memory: Option<unsafe extern "C" fn(*mut c_void)>,
    pub step_finished: Option<unsafe extern "C" fn(fmi2ComponentEnvironment, fmi2Status)>,
    pub component_environment: fmi2ComponentEnvironment,
}

/// The name of a status for messages.
pub fn status_name(status: fmi2Status) -> &'static str {
    match status {
        OK => "fmi2OK",
        WARNING => "fmi2Warning",
        DISCARD => "fmi2Discard",
        ERROR => "fmi2Error",
        FATAL => "fmi2Fatal",
        PENDING => "fmi2Pending",
        _ => "not an fmi2Status",
    }
}
