//! The FMI 3.0 Co-Simulation entry points the harness calls, resolved once at load time and
//! typed after `fmi3FunctionTypes.h` (the C types are `fmi-abi`'s).
#![allow(unsafe_code)]

use super::super::error::LoadError;
use super::super::functions::resolve;
use fmi_abi::fmi3::*;
use libloading::Library;
use std::ffi::c_char;
use std::path::Path;

type Vr = fmi3ValueReference;
type Inst = fmi3Instance;
pub(crate) type Get<T> = unsafe extern "C" fn(Inst, *const Vr, usize, *mut T, usize) -> fmi3Status;
pub(crate) type Set<T> =
    unsafe extern "C" fn(Inst, *const Vr, usize, *const T, usize) -> fmi3Status;
pub(crate) type Only = unsafe extern "C" fn(Inst) -> fmi3Status;
pub(crate) type InstantiateCoSimulation = unsafe extern "C" fn(
    fmi3String,
    fmi3String,
    fmi3String,
    fmi3Boolean,
    fmi3Boolean,
    fmi3Boolean,
    fmi3Boolean,
    *const Vr,
    usize,
    fmi3InstanceEnvironment,
    fmi3LogMessageCallback,
    fmi3IntermediateUpdateCallback,
) -> Inst;
pub(crate) type DoStep = unsafe extern "C" fn(
    Inst,
    f64,
    f64,
    fmi3Boolean,
    *mut fmi3Boolean,
    *mut fmi3Boolean,
    *mut fmi3Boolean,
    *mut f64,
) -> fmi3Status;
pub(crate) type UpdateDiscreteStates = unsafe extern "C" fn(
    Inst,
    *mut fmi3Boolean,
    *mut fmi3Boolean,
    *mut fmi3Boolean,
    *mut fmi3Boolean,
    *mut fmi3Boolean,
    *mut f64,
) -> fmi3Status;

macro_rules! fmi3_functions {
    ($($field:ident: $ty:ty = $symbol:literal,)+) => {
        /// Typed pointers into the loaded binary; valid while its `Library` stays loaded (it
        /// lives next to them in the shared `Fmu` state).
        #[derive(Clone, Copy)]
        pub(crate) struct Fmi3Functions {
            $(pub(crate) $field: $ty,)+
        }

        impl Fmi3Functions {
            #[cfg(test)]
            pub(crate) const SYMBOLS: &'static [&'static str] = &[$($symbol),+];

            /// Resolves every function, failing on the first symbol the library lacks.
            pub(crate) fn resolve(library: &Library, path: &Path) -> Result<Self, LoadError> {
                Ok(Self {
                    $($field: resolve::<$ty>(library, path, $symbol)?,)+
                })
            }
        }
    };
}

fmi3_functions! {
    get_version: unsafe extern "C" fn() -> *const c_char = "fmi3GetVersion",
    set_debug_logging: unsafe extern "C" fn(Inst, fmi3Boolean, usize, *const fmi3String) -> fmi3Status = "fmi3SetDebugLogging",
    instantiate_co_simulation: InstantiateCoSimulation = "fmi3InstantiateCoSimulation",
    free_instance: unsafe extern "C" fn(Inst) = "fmi3FreeInstance",
    enter_initialization_mode: unsafe extern "C" fn(Inst, fmi3Boolean, f64, f64, fmi3Boolean, f64) -> fmi3Status = "fmi3EnterInitializationMode",
    exit_initialization_mode: Only = "fmi3ExitInitializationMode",
    enter_event_mode: Only = "fmi3EnterEventMode",
    terminate: Only = "fmi3Terminate",
    reset: Only = "fmi3Reset",
    get_float64: Get<f64> = "fmi3GetFloat64",
    get_int32: Get<i32> = "fmi3GetInt32",
    get_int64: Get<i64> = "fmi3GetInt64",
    get_boolean: Get<fmi3Boolean> = "fmi3GetBoolean",
    get_string: Get<fmi3String> = "fmi3GetString",
    set_float64: Set<f64> = "fmi3SetFloat64",
    set_int32: Set<i32> = "fmi3SetInt32",
    set_int64: Set<i64> = "fmi3SetInt64",
    set_boolean: Set<fmi3Boolean> = "fmi3SetBoolean",
    set_string: Set<fmi3String> = "fmi3SetString",
    enter_step_mode: Only = "fmi3EnterStepMode",
    do_step: DoStep = "fmi3DoStep",
    update_discrete_states: UpdateDiscreteStates = "fmi3UpdateDiscreteStates",
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_symbol_is_an_fmi3_function_listed_once() {
        let symbols = Fmi3Functions::SYMBOLS;
        let unique: std::collections::BTreeSet<_> = symbols.iter().collect();
        assert_eq!(unique.len(), symbols.len());
        assert!(symbols.iter().all(|symbol| symbol.starts_with("fmi3")));
    }
}
