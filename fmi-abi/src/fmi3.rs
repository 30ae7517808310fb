//! The FMI 3.0 C types, written by hand after `fmi3PlatformTypes.h` and `fmi3FunctionTypes.h`
//! (checked against those headers by the system tests' C ABI check).
//!
//! As for FMI 2.0, every C enumeration is a C `int` with the header's constants: the other
//! side may pass any value, and a Rust enum holding an undeclared one would be undefined
//! behaviour. `fmi3Boolean` is C's `bool` (one byte, 0 or 1); the layer reads arrays of it
//! that a master fills as bytes.
#![allow(non_camel_case_types, non_upper_case_globals, non_snake_case)]

use std::os::raw::{c_char, c_int, c_void};

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

/// `fmi3Status`: a C `int` (an enumeration the other side may fill with any value); the
/// values are the constants below.
#[repr(transparent)]
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct fmi3Status(pub c_int);

impl From<c_int> for fmi3Status {
    fn from(code: c_int) -> Self {
        fmi3Status(code)
    }
}

pub const fmi3OK: fmi3Status = fmi3Status(0);
pub const fmi3Warning: fmi3Status = fmi3Status(1);
pub const fmi3Discard: fmi3Status = fmi3Status(2);
pub const fmi3Error: fmi3Status = fmi3Status(3);
pub const fmi3Fatal: fmi3Status = fmi3Status(4);

impl fmi3Status {
    /// `fmi3OK` or `fmi3Warning`: the call's results are valid.
    pub const fn is_success(self) -> bool {
        self.0 == fmi3OK.0 || self.0 == fmi3Warning.0
    }

    /// The header's name of the status, `None` for a value outside the enumeration.
    pub const fn name(self) -> Option<&'static str> {
        match self.0 {
            0 => Some("fmi3OK"),
            1 => Some("fmi3Warning"),
            2 => Some("fmi3Discard"),
            3 => Some("fmi3Error"),
            4 => Some("fmi3Fatal"),
            _ => None,
        }
    }
}

impl std::fmt::Debug for fmi3Status {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.name() {
            Some(name) => f.write_str(name),
            None => write!(f, "fmi3Status({})", self.0),
        }
    }
}

/// `fmi3DependencyKind`: a C `int`.
pub type fmi3DependencyKind = c_int;
pub const fmi3Independent: fmi3DependencyKind = 0;
pub const fmi3Constant: fmi3DependencyKind = 1;
pub const fmi3Fixed: fmi3DependencyKind = 2;
pub const fmi3Tunable: fmi3DependencyKind = 3;
pub const fmi3Discrete: fmi3DependencyKind = 4;
pub const fmi3Dependent: fmi3DependencyKind = 5;

/// `fmi3IntervalQualifier`: a C `int`.
pub type fmi3IntervalQualifier = c_int;
pub const fmi3IntervalNotYetKnown: fmi3IntervalQualifier = 0;
pub const fmi3IntervalUnchanged: fmi3IntervalQualifier = 1;
pub const fmi3IntervalChanged: fmi3IntervalQualifier = 2;

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
        assert_eq!(size_of::<fmi3Status>(), size_of::<c_int>());
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
    fn status_values_follow_the_header_order_and_any_int_is_representable() {
        for (i, s) in [fmi3OK, fmi3Warning, fmi3Discard, fmi3Error, fmi3Fatal]
            .iter()
            .enumerate()
        {
            assert_eq!(s.0, i as c_int);
            assert!(s.name().is_some());
        }
        assert!(fmi3Warning.is_success() && !fmi3Discard.is_success());
        assert_eq!(format!("{:?}", fmi3Status(42)), "fmi3Status(42)");
        assert_eq!(fmi3Dependent, 5);
        assert_eq!(fmi3IntervalChanged, 2);
    }
}
