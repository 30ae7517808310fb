//! The FMI 3.0 C types, written by hand after `fmi3PlatformTypes.h` and `fmi3FunctionTypes.h`
//! (checked against those headers by the system tests' C ABI check).
//!
//! As for FMI 2.0, enumerations only ever produced by us (`fmi3Status`) are `#[repr(C)]`
//! enums; a value a master passes in is a plain integer. `fmi3Boolean` is C's `bool`: one
//! byte, 0 or 1, which Rust's `bool` matches.
#![allow(non_camel_case_types, non_upper_case_globals, non_snake_case)]

use std::os::raw::{c_char, c_void};

pub type fmi3Instance = *mut c_void;
pub type fmi3InstanceEnvironment = *mut c_void;
pub type fmi3FMUState = *mut c_void;
pub type fmi3ValueReference = u32;
pub type fmi3Float32 = f32;
pub type fmi3Float64 = f64;
pub type fmi3Int8 = i8;
pub type fmi3UInt8 = u8;
pub type fmi3Int16 = i16;
pub type fmi3UInt16 = u16;
pub type fmi3Int32 = i32;
pub type fmi3UInt32 = u32;
pub type fmi3Int64 = i64;
pub type fmi3UInt64 = u64;
pub type fmi3Boolean = bool;
pub type fmi3Char = c_char;
pub type fmi3String = *const fmi3Char;
pub type fmi3Byte = u8;
pub type fmi3Binary = *const fmi3Byte;
pub type fmi3Clock = bool;

pub const fmi3True: fmi3Boolean = true;
pub const fmi3False: fmi3Boolean = false;

/// `fmi3Version`, NUL-terminated for the C API.
pub const VERSION: &std::ffi::CStr = c"3.0";

#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum fmi3Status {
    fmi3OK = 0,
    fmi3Warning = 1,
    fmi3Discard = 2,
    fmi3Error = 3,
    fmi3Fatal = 4,
}

#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum fmi3DependencyKind {
    fmi3Independent = 0,
    fmi3Constant = 1,
    fmi3Fixed = 2,
    fmi3Tunable = 3,
    fmi3Discrete = 4,
    fmi3Dependent = 5,
}

#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum fmi3IntervalQualifier {
    fmi3IntervalNotYetKnown = 0,
    fmi3IntervalUnchanged = 1,
    fmi3IntervalChanged = 2,
}

/// `fmi3LogMessageCallback`: not variadic in FMI 3.0, the message is formatted by the FMU.
pub type fmi3LogMessageCallback = Option<
    unsafe extern "C" fn(
        instanceEnvironment: fmi3InstanceEnvironment,
        status: fmi3Status,
        category: fmi3String,
        message: fmi3String,
    ),
>;
pub type fmi3ClockUpdateCallback =
    Option<unsafe extern "C" fn(instanceEnvironment: fmi3InstanceEnvironment)>;
pub type fmi3IntermediateUpdateCallback = Option<
    unsafe extern "C" fn(
        instanceEnvironment: fmi3InstanceEnvironment,
        intermediateUpdateTime: fmi3Float64,
        intermediateVariableSetRequested: fmi3Boolean,
        intermediateVariableGetAllowed: fmi3Boolean,
        intermediateStepFinished: fmi3Boolean,
        canReturnEarly: fmi3Boolean,
        earlyReturnRequested: *mut fmi3Boolean,
        earlyReturnTime: *mut fmi3Float64,
    ),
>;
pub type fmi3LockPreemptionCallback = Option<unsafe extern "C" fn()>;
pub type fmi3UnlockPreemptionCallback = Option<unsafe extern "C" fn()>;

#[cfg(test)]
mod tests {
    use super::*;
    use std::mem::size_of;

    /// The sizes the official headers imply on an LP64 platform.
    #[test]
    fn type_sizes_match_the_c_types() {
        assert_eq!(size_of::<fmi3Status>(), size_of::<std::os::raw::c_int>());
        assert_eq!(size_of::<fmi3Boolean>(), 1);
        assert_eq!(size_of::<fmi3ValueReference>(), 4);
        assert_eq!(
            size_of::<fmi3LogMessageCallback>(),
            size_of::<*const c_void>()
        );
        assert_eq!(
            size_of::<fmi3IntermediateUpdateCallback>(),
            size_of::<*const c_void>()
        );
    }

    #[test]
    fn enumeration_values_follow_the_header_order() {
        let status = [
            fmi3Status::fmi3OK,
            fmi3Status::fmi3Warning,
            fmi3Status::fmi3Discard,
            fmi3Status::fmi3Error,
            fmi3Status::fmi3Fatal,
        ];
        for (i, s) in status.iter().enumerate() {
            assert_eq!(*s as i32, i as i32);
        }
        assert_eq!(fmi3DependencyKind::fmi3Dependent as i32, 5);
        assert_eq!(fmi3IntervalQualifier::fmi3IntervalChanged as i32, 2);
    }
}
