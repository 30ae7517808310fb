//! The FMI 2.0 entry points of one FMU as a table of function pointers.
use fmi_abi::fmi2::*;

/// Every FMI 2.0 Co-Simulation function, typed as the standard's `fmi2XxxTYPE`.
#[derive(Debug, Clone, Copy)]
pub struct Fmi2Functions {
    pub get_types_platform: fmi2GetTypesPlatformTYPE,
    pub get_version: fmi2GetVersionTYPE,
    pub set_debug_logging: fmi2SetDebugLoggingTYPE,
    pub instantiate: fmi2InstantiateTYPE,
    pub free_instance: fmi2FreeInstanceTYPE,
    pub setup_experiment: fmi2SetupExperimentTYPE,
    pub enter_initialization_mode: fmi2ComponentOnlyTYPE,
    pub exit_initialization_mode: fmi2ComponentOnlyTYPE,
    pub terminate: fmi2ComponentOnlyTYPE,
    pub reset: fmi2ComponentOnlyTYPE,
    pub get_real: fmi2GetRealTYPE,
    pub get_integer: fmi2GetIntegerTYPE,
    pub get_boolean: fmi2GetBooleanTYPE,
    pub get_string: fmi2GetStringTYPE,
    pub set_real: fmi2SetRealTYPE,
    pub set_integer: fmi2SetIntegerTYPE,
    pub set_boolean: fmi2SetBooleanTYPE,
    pub set_string: fmi2SetStringTYPE,
    pub get_fmu_state: fmi2GetFMUstateTYPE,
    pub set_fmu_state: fmi2SetFMUstateTYPE,
    pub free_fmu_state: fmi2FreeFMUstateTYPE,
    pub serialized_fmu_state_size: fmi2SerializedFMUstateSizeTYPE,
    pub serialize_fmu_state: fmi2SerializeFMUstateTYPE,
    pub de_serialize_fmu_state: fmi2DeSerializeFMUstateTYPE,
    pub get_directional_derivative: fmi2GetDirectionalDerivativeTYPE,
    pub set_real_input_derivatives: fmi2SetRealInputDerivativesTYPE,
    pub get_real_output_derivatives: fmi2GetRealOutputDerivativesTYPE,
    pub do_step: fmi2DoStepTYPE,
    pub cancel_step: fmi2ComponentOnlyTYPE,
    pub get_status: fmi2GetStatusTYPE,
    pub get_real_status: fmi2GetRealStatusTYPE,
    pub get_integer_status: fmi2GetIntegerStatusTYPE,
    pub get_boolean_status: fmi2GetBooleanStatusTYPE,
    pub get_string_status: fmi2GetStringStatusTYPE,
}

/// The [`Fmi2Functions`] of an FMU crate linked into the test (its `export_fmi2!` symbols),
/// e.g. `static FMU: Fmi2Functions = fmi2_functions!(fmu_gnc);`.
#[macro_export]
macro_rules! fmi2_functions {
    ($fmu:path) => {{
        use $fmu as fmu;
        $crate::Fmi2Functions {
            get_types_platform: fmu::fmi2GetTypesPlatform,
            get_version: fmu::fmi2GetVersion,
            set_debug_logging: fmu::fmi2SetDebugLogging,
            instantiate: fmu::fmi2Instantiate,
            free_instance: fmu::fmi2FreeInstance,
            setup_experiment: fmu::fmi2SetupExperiment,
            enter_initialization_mode: fmu::fmi2EnterInitializationMode,
            exit_initialization_mode: fmu::fmi2ExitInitializationMode,
            terminate: fmu::fmi2Terminate,
            reset: fmu::fmi2Reset,
            get_real: fmu::fmi2GetReal,
            get_integer: fmu::fmi2GetInteger,
            get_boolean: fmu::fmi2GetBoolean,
            get_string: fmu::fmi2GetString,
            set_real: fmu::fmi2SetReal,
            set_integer: fmu::fmi2SetInteger,
            set_boolean: fmu::fmi2SetBoolean,
            set_string: fmu::fmi2SetString,
            get_fmu_state: fmu::fmi2GetFMUstate,
            set_fmu_state: fmu::fmi2SetFMUstate,
            free_fmu_state: fmu::fmi2FreeFMUstate,
            serialized_fmu_state_size: fmu::fmi2SerializedFMUstateSize,
            serialize_fmu_state: fmu::fmi2SerializeFMUstate,
            de_serialize_fmu_state: fmu::fmi2DeSerializeFMUstate,
            get_directional_derivative: fmu::fmi2GetDirectionalDerivative,
            set_real_input_derivatives: fmu::fmi2SetRealInputDerivatives,
            get_real_output_derivatives: fmu::fmi2GetRealOutputDerivatives,
            do_step: fmu::fmi2DoStep,
            cancel_step: fmu::fmi2CancelStep,
            get_status: fmu::fmi2GetStatus,
            get_real_status: fmu::fmi2GetRealStatus,
            get_integer_status: fmu::fmi2GetIntegerStatus,
            get_boolean_status: fmu::fmi2GetBooleanStatus,
            get_string_status: fmu::fmi2GetStringStatus,
        }
    }};
}

impl Fmi2Functions {
    /// The entry points of a loaded shared library (an FMU's binary). The library must stay
    /// loaded while the table is used.
    ///
    /// # Safety
    /// The library's `fmi2*` symbols must have the standard's signatures.
    pub unsafe fn load(library: &libloading::Library) -> Result<Fmi2Functions, libloading::Error> {
        macro_rules! symbol {
            ($name:literal) => {
                // SAFETY: the caller promises the standard's signature.
                *unsafe { library.get(concat!($name, "\0").as_bytes()) }?
            };
        }
        Ok(Fmi2Functions {
            get_types_platform: symbol!("fmi2GetTypesPlatform"),
            get_version: symbol!("fmi2GetVersion"),
            set_debug_logging: symbol!("fmi2SetDebugLogging"),
            instantiate: symbol!("fmi2Instantiate"),
            free_instance: symbol!("fmi2FreeInstance"),
            setup_experiment: symbol!("fmi2SetupExperiment"),
            enter_initialization_mode: symbol!("fmi2EnterInitializationMode"),
            exit_initialization_mode: symbol!("fmi2ExitInitializationMode"),
            terminate: symbol!("fmi2Terminate"),
            reset: symbol!("fmi2Reset"),
            get_real: symbol!("fmi2GetReal"),
            get_integer: symbol!("fmi2GetInteger"),
            get_boolean: symbol!("fmi2GetBoolean"),
            get_string: symbol!("fmi2GetString"),
            set_real: symbol!("fmi2SetReal"),
            set_integer: symbol!("fmi2SetInteger"),
            set_boolean: symbol!("fmi2SetBoolean"),
            set_string: symbol!("fmi2SetString"),
            get_fmu_state: symbol!("fmi2GetFMUstate"),
            set_fmu_state: symbol!("fmi2SetFMUstate"),
            free_fmu_state: symbol!("fmi2FreeFMUstate"),
            serialized_fmu_state_size: symbol!("fmi2SerializedFMUstateSize"),
            serialize_fmu_state: symbol!("fmi2SerializeFMUstate"),
            de_serialize_fmu_state: symbol!("fmi2DeSerializeFMUstate"),
            get_directional_derivative: symbol!("fmi2GetDirectionalDerivative"),
            set_real_input_derivatives: symbol!("fmi2SetRealInputDerivatives"),
            get_real_output_derivatives: symbol!("fmi2GetRealOutputDerivatives"),
            do_step: symbol!("fmi2DoStep"),
            cancel_step: symbol!("fmi2CancelStep"),
            get_status: symbol!("fmi2GetStatus"),
            get_real_status: symbol!("fmi2GetRealStatus"),
            get_integer_status: symbol!("fmi2GetIntegerStatus"),
            get_boolean_status: symbol!("fmi2GetBooleanStatus"),
            get_string_status: symbol!("fmi2GetStringStatus"),
        })
    }
}
