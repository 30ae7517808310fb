//! The 34 FMI 2.0 Co-Simulation functions of one shared library, resolved by name with
//! `libloading` and held as raw C function pointers.
#![allow(unsafe_code)]

use crate::ffi::*;
use std::ffi::{c_char, c_int};
use std::path::Path;

macro_rules! api {
    ($($field:ident = $symbol:literal : fn($($arg:ty),*) -> $ret:ty;)*) => {
        /// Raw function pointers of one FMU library; the library stays loaded while this lives.
        pub struct Api {
            $(pub $field: unsafe extern "C" fn($($arg),*) -> $ret,)*
            _library: libloading::Library,
        }

        /// The exported symbol names, in the order of the standard's function list.
        pub const SYMBOLS: &[&str] = &[$($symbol,)*];

        impl Api {
            /// Loads `path` and resolves all 34 functions.
            pub fn load(path: &Path) -> Result<Api, libloading::Error> {
                // SAFETY: loading runs the library's initialisers; an FMU library has none
                // beyond what the Rust runtime sets up.
                let library = unsafe { libloading::Library::new(path) }?;
                // SAFETY: each symbol is declared with the C signature of the FMI 2.0
                // standard; the pointers are used only while `library` is held.
                unsafe {
                    Ok(Api {
                        $($field: *library.get::<unsafe extern "C" fn($($arg),*) -> $ret>(
                            concat!($symbol, "\0").as_bytes())?,)*
                        _library: library,
                    })
                }
            }
        }
    };
}

type C = fmi2Component;
type Vr = *const fmi2ValueReference;

api! {
    get_types_platform = "fmi2GetTypesPlatform": fn() -> *const c_char;
    get_version = "fmi2GetVersion": fn() -> *const c_char;
    set_debug_logging = "fmi2SetDebugLogging": fn(C, fmi2Boolean, usize, *const fmi2String) -> fmi2Status;
    instantiate = "fmi2Instantiate": fn(fmi2String, fmi2Type, fmi2String, fmi2String, *const fmi2CallbackFunctions, fmi2Boolean, fmi2Boolean) -> C;
    free_instance = "fmi2FreeInstance": fn(C) -> ();
    setup_experiment = "fmi2SetupExperiment": fn(C, fmi2Boolean, fmi2Real, fmi2Real, fmi2Boolean, fmi2Real) -> fmi2Status;
    enter_initialization_mode = "fmi2EnterInitializationMode": fn(C) -> fmi2Status;
    exit_initialization_mode = "fmi2ExitInitializationMode": fn(C) -> fmi2Status;
    terminate = "fmi2Terminate": fn(C) -> fmi2Status;
    reset = "fmi2Reset": fn(C) -> fmi2Status;
    get_real = "fmi2GetReal": fn(C, Vr, usize, *mut fmi2Real) -> fmi2Status;
    get_integer = "fmi2GetInteger": fn(C, Vr, usize, *mut fmi2Integer) -> fmi2Status;
    get_boolean = "fmi2GetBoolean": fn(C, Vr, usize, *mut fmi2Boolean) -> fmi2Status;
    get_string = "fmi2GetString": fn(C, Vr, usize, *mut fmi2String) -> fmi2Status;
    set_real = "fmi2SetReal": fn(C, Vr, usize, *const fmi2Real) -> fmi2Status;
    set_integer = "fmi2SetInteger": fn(C, Vr, usize, *const fmi2Integer) -> fmi2Status;
    set_boolean = "fmi2SetBoolean": fn(C, Vr, usize, *const fmi2Boolean) -> fmi2Status;
    set_string = "fmi2SetString": fn(C, Vr, usize, *const fmi2String) -> fmi2Status;
    get_fmu_state = "fmi2GetFMUstate": fn(C, *mut fmi2FMUstate) -> fmi2Status;
    set_fmu_state = "fmi2SetFMUstate": fn(C, fmi2FMUstate) -> fmi2Status;
    free_fmu_state = "fmi2FreeFMUstate": fn(C, *mut fmi2FMUstate) -> fmi2Status;
    serialized_fmu_state_size = "fmi2SerializedFMUstateSize": fn(C, fmi2FMUstate, *mut usize) -> fmi2Status;
    serialize_fmu_state = "fmi2SerializeFMUstate": fn(C, fmi2FMUstate, *mut fmi2Byte, usize) -> fmi2Status;
    de_serialize_fmu_state = "fmi2DeSerializeFMUstate": fn(C, *const fmi2Byte, usize, *mut fmi2FMUstate) -> fmi2Status;
    get_directional_derivative = "fmi2GetDirectionalDerivative": fn(C, Vr, usize, Vr, usize, *const fmi2Real, *mut fmi2Real) -> fmi2Status;
    set_real_input_derivatives = "fmi2SetRealInputDerivatives": fn(C, Vr, usize, *const fmi2Integer, *const fmi2Real) -> fmi2Status;
    get_real_output_derivatives = "fmi2GetRealOutputDerivatives": fn(C, Vr, usize, *const fmi2Integer, *mut fmi2Real) -> fmi2Status;
    do_step = "fmi2DoStep": fn(C, fmi2Real, fmi2Real, fmi2Boolean) -> fmi2Status;
    cancel_step = "fmi2CancelStep": fn(C) -> fmi2Status;
    get_status = "fmi2GetStatus": fn(C, fmi2StatusKind, *mut fmi2Status) -> fmi2Status;
    get_real_status = "fmi2GetRealStatus": fn(C, fmi2StatusKind, *mut fmi2Real) -> fmi2Status;
    get_integer_status = "fmi2GetIntegerStatus": fn(C, fmi2StatusKind, *mut fmi2Integer) -> fmi2Status;
    get_boolean_status = "fmi2GetBooleanStatus": fn(C, fmi2StatusKind, *mut fmi2Boolean) -> fmi2Status;
    get_string_status = "fmi2GetStringStatus": fn(C, fmi2StatusKind, *mut fmi2String) -> fmi2Status;
}

// The fuzzer's statuses are c_int; keep the alias honest.
const _: () = assert!(std::mem::size_of::<fmi2Status>() == std::mem::size_of::<c_int>());

#[cfg(test)]
mod tests {
    use super::SYMBOLS;

    #[test]
    fn all_thirty_four_functions_are_declared_once() {
        assert_eq!(SYMBOLS.len(), 34);
        let mut unique = SYMBOLS.to_vec();
        unique.sort_unstable();
        unique.dedup();
        assert_eq!(unique.len(), 34);
    }
}
