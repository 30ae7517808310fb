//! The FMI 2.0 C types, written by hand after `fmi2TypesPlatform.h` and
//! `fmi2FunctionTypes.h` (platform "default").
//!
//! Enumerations the master *passes in* (`fmi2Type`, `fmi2StatusKind`) are plain `c_int`s
//! with constants, because a C caller can hand us any integer and a Rust enum holding an
//! undeclared value is undefined behaviour. `fmi2Status` is only ever produced by us (and
//! written through `fmi2GetStatus`), so it is a `#[repr(C)]` enum.
#![allow(non_camel_case_types, non_upper_case_globals, non_snake_case)]

use std::os::raw::{c_char, c_int, c_void};

pub type fmi2Component = *mut c_void;
pub type fmi2ComponentEnvironment = *mut c_void;
pub type fmi2FMUstate = *mut c_void;
pub type fmi2ValueReference = u32;
pub type fmi2Real = f64;
pub type fmi2Integer = i32;
pub type fmi2Boolean = i32;
pub type fmi2Char = c_char;
pub type fmi2String = *const fmi2Char;
pub type fmi2Byte = c_char;

pub const fmi2True: fmi2Boolean = 1;
pub const fmi2False: fmi2Boolean = 0;

/// `fmi2TypesPlatform` and `fmi2Version`, NUL-terminated for the C API.
pub const TYPES_PLATFORM: &std::ffi::CStr = c"default";
pub const VERSION: &std::ffi::CStr = c"2.0";

#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum fmi2Status {
    fmi2OK = 0,
    fmi2Warning = 1,
    fmi2Discard = 2,
    fmi2Error = 3,
    fmi2Fatal = 4,
    fmi2Pending = 5,
}

pub type fmi2Type = c_int;
pub const fmi2ModelExchange: fmi2Type = 0;
pub const fmi2CoSimulation: fmi2Type = 1;

pub type fmi2StatusKind = c_int;
pub const fmi2DoStepStatus: fmi2StatusKind = 0;
pub const fmi2PendingStatus: fmi2StatusKind = 1;
pub const fmi2LastSuccessfulTime: fmi2StatusKind = 2;
pub const fmi2Terminated: fmi2StatusKind = 3;

/// `fmi2CallbackLogger`: variadic; we always call it with the format `"%s"` and the
/// message as the single variadic argument.
pub type fmi2CallbackLogger = Option<
    unsafe extern "C" fn(
        componentEnvironment: fmi2ComponentEnvironment,
        instanceName: fmi2String,
        status: fmi2Status,
        category: fmi2String,
        message: fmi2String,
        ...
    ),
>;
pub type fmi2CallbackAllocateMemory =
    Option<unsafe extern "C" fn(nobj: usize, size: usize) -> *mut c_void>;
pub type fmi2CallbackFreeMemory = Option<unsafe extern "C" fn(obj: *mut c_void)>;
pub type fmi2StepFinished = Option<
    unsafe extern "C" fn(componentEnvironment: fmi2ComponentEnvironment, status: fmi2Status),
>;

#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct fmi2CallbackFunctions {
    pub logger: fmi2CallbackLogger,
    pub allocateMemory: fmi2CallbackAllocateMemory,
    pub freeMemory: fmi2CallbackFreeMemory,
    pub stepFinished: fmi2StepFinished,
    pub componentEnvironment: fmi2ComponentEnvironment,
}

/// What `fmi2NewDiscreteStates` reports (Model Exchange).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct fmi2EventInfo {
    pub newDiscreteStatesNeeded: fmi2Boolean,
    pub terminateSimulation: fmi2Boolean,
    pub nominalsOfContinuousStatesChanged: fmi2Boolean,
    pub valuesOfContinuousStatesChanged: fmi2Boolean,
    pub nextEventTimeDefined: fmi2Boolean,
    pub nextEventTime: fmi2Real,
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::mem::{align_of, size_of};

    /// The sizes the official headers imply on an LP64 platform (the C ABI check in the
    /// system tests compares against the headers themselves).
    #[test]
    fn type_sizes_match_the_lp64_c_types() {
        assert_eq!(size_of::<fmi2Status>(), size_of::<c_int>());
        assert_eq!(size_of::<fmi2Boolean>(), 4);
        assert_eq!(size_of::<fmi2ValueReference>(), 4);
        assert_eq!(size_of::<fmi2CallbackLogger>(), size_of::<*const c_void>());
        assert_eq!(
            size_of::<fmi2CallbackFunctions>(),
            5 * size_of::<*const c_void>()
        );
        assert_eq!(
            align_of::<fmi2CallbackFunctions>(),
            align_of::<*const c_void>()
        );
    }

    #[test]
    fn status_values_follow_the_header_order() {
        let all = [
            fmi2Status::fmi2OK,
            fmi2Status::fmi2Warning,
            fmi2Status::fmi2Discard,
            fmi2Status::fmi2Error,
            fmi2Status::fmi2Fatal,
            fmi2Status::fmi2Pending,
        ];
        for (i, s) in all.iter().enumerate() {
            assert_eq!(*s as c_int, i as c_int);
        }
    }
}
