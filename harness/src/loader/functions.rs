//! Every FMI 2.0 Co-Simulation entry point of a loaded binary, resolved once at load time.
#![allow(unsafe_code)]

use super::error::LoadError;
use super::ffi::*;
use libloading::Library;
use std::path::Path;

/// Declares the table once: the struct fields and the symbol each is resolved from.
macro_rules! fmi2_functions {
    ($($field:ident: $ty:ty = $symbol:literal,)+) => {
        /// Typed pointers to the 34 `fmi2*` functions. Valid only while the `Library` they came
        /// from stays loaded, which is why they live next to it in the shared `Fmu` state.
        // Every function is required by the standard and so resolved, even the ones
        // (directional derivatives, input interpolation, asynchronous status) no call uses yet.
        #[allow(dead_code)]
        #[derive(Clone, Copy)]
        pub(crate) struct Fmi2Functions {
            $(pub(crate) $field: $ty,)+
        }

        impl Fmi2Functions {
            /// The symbols resolved, in table order.
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

fmi2_functions! {
    get_types_platform: fmi2GetTypesPlatformTYPE = "fmi2GetTypesPlatform",
    get_version: fmi2GetVersionTYPE = "fmi2GetVersion",
    set_debug_logging: fmi2SetDebugLoggingTYPE = "fmi2SetDebugLogging",
    instantiate: fmi2InstantiateTYPE = "fmi2Instantiate",
    free_instance: fmi2FreeInstanceTYPE = "fmi2FreeInstance",
    setup_experiment: fmi2SetupExperimentTYPE = "fmi2SetupExperiment",
    enter_initialization_mode: fmi2ComponentOnlyTYPE = "fmi2EnterInitializationMode",
    exit_initialization_mode: fmi2ComponentOnlyTYPE = "fmi2ExitInitializationMode",
    terminate: fmi2ComponentOnlyTYPE = "fmi2Terminate",
    reset: fmi2ComponentOnlyTYPE = "fmi2Reset",
    get_real: fmi2GetRealTYPE = "fmi2GetReal",
    get_integer: fmi2GetIntegerTYPE = "fmi2GetInteger",
    get_boolean: fmi2GetBooleanTYPE = "fmi2GetBoolean",
    get_string: fmi2GetStringTYPE = "fmi2GetString",
    set_real: fmi2SetRealTYPE = "fmi2SetReal",
    set_integer: fmi2SetIntegerTYPE = "fmi2SetInteger",
    set_boolean: fmi2SetBooleanTYPE = "fmi2SetBoolean",
    set_string: fmi2SetStringTYPE = "fmi2SetString",
    get_fmu_state: fmi2GetFMUstateTYPE = "fmi2GetFMUstate",
    set_fmu_state: fmi2SetFMUstateTYPE = "fmi2SetFMUstate",
    free_fmu_state: fmi2FreeFMUstateTYPE = "fmi2FreeFMUstate",
    serialized_fmu_state_size: fmi2SerializedFMUstateSizeTYPE = "fmi2SerializedFMUstateSize",
    serialize_fmu_state: fmi2SerializeFMUstateTYPE = "fmi2SerializeFMUstate",
    deserialize_fmu_state: fmi2DeSerializeFMUstateTYPE = "fmi2DeSerializeFMUstate",
    get_directional_derivative: fmi2GetDirectionalDerivativeTYPE = "fmi2GetDirectionalDerivative",
    set_real_input_derivatives: fmi2SetRealInputDerivativesTYPE = "fmi2SetRealInputDerivatives",
    get_real_output_derivatives: fmi2GetRealOutputDerivativesTYPE = "fmi2GetRealOutputDerivatives",
    do_step: fmi2DoStepTYPE = "fmi2DoStep",
    cancel_step: fmi2ComponentOnlyTYPE = "fmi2CancelStep",
    get_status: fmi2GetStatusTYPE = "fmi2GetStatus",
    get_real_status: fmi2GetRealStatusTYPE = "fmi2GetRealStatus",
    get_integer_status: fmi2GetIntegerStatusTYPE = "fmi2GetIntegerStatus",
    get_boolean_status: fmi2GetBooleanStatusTYPE = "fmi2GetBooleanStatus",
    get_string_status: fmi2GetStringStatusTYPE = "fmi2GetStringStatus",
}

pub(crate) fn resolve<T: Copy>(
    library: &Library,
    path: &Path,
    symbol: &'static str,
) -> Result<T, LoadError> {
    // SAFETY: `T` is the type the FMI standard (2.0 or 3.0) gives this symbol; a binary that
    // exports it with another signature violates the standard and cannot be detected here.
    // The copied pointer is only used while `library` is kept loaded (see `FmuShared`).
    let loaded = unsafe { library.get::<T>(symbol.as_bytes()) };
    loaded
        .map(|function| *function)
        .map_err(|source| LoadError::MissingSymbol {
            symbol,
            binary: path.to_path_buf(),
            source,
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_table_lists_the_25_common_and_9_co_simulation_functions_once_each() {
        let symbols = Fmi2Functions::SYMBOLS;
        assert_eq!(symbols.len(), 34);
        let unique: std::collections::BTreeSet<_> = symbols.iter().collect();
        assert_eq!(unique.len(), 34);
        assert!(symbols.iter().all(|symbol| symbol.starts_with("fmi2")));
    }
}
