//! FMI 2.0: the common functions, those of Co-Simulation and those of Model Exchange, typed
//! as the standard's `fmi2XxxTYPE` (`fmi2FunctionTypes.h`).
use super::function_table;
use fmi_abi::fmi2::*;

function_table! {
    $
    /// The 25 functions both interfaces export (FMI 2.0, 2.1.2).
    Fmi2Common, linked as fmi2_common {
        get_types_platform: fmi2GetTypesPlatformTYPE = fmi2GetTypesPlatform,
        get_version: fmi2GetVersionTYPE = fmi2GetVersion,
        set_debug_logging: fmi2SetDebugLoggingTYPE = fmi2SetDebugLogging,
        instantiate: fmi2InstantiateTYPE = fmi2Instantiate,
        free_instance: fmi2FreeInstanceTYPE = fmi2FreeInstance,
        setup_experiment: fmi2SetupExperimentTYPE = fmi2SetupExperiment,
        enter_initialization_mode: fmi2ComponentOnlyTYPE = fmi2EnterInitializationMode,
        exit_initialization_mode: fmi2ComponentOnlyTYPE = fmi2ExitInitializationMode,
        terminate: fmi2ComponentOnlyTYPE = fmi2Terminate,
        reset: fmi2ComponentOnlyTYPE = fmi2Reset,
        get_real: fmi2GetRealTYPE = fmi2GetReal,
        get_integer: fmi2GetIntegerTYPE = fmi2GetInteger,
        get_boolean: fmi2GetBooleanTYPE = fmi2GetBoolean,
        get_string: fmi2GetStringTYPE = fmi2GetString,
        set_real: fmi2SetRealTYPE = fmi2SetReal,
        set_integer: fmi2SetIntegerTYPE = fmi2SetInteger,
        set_boolean: fmi2SetBooleanTYPE = fmi2SetBoolean,
        set_string: fmi2SetStringTYPE = fmi2SetString,
        get_fmu_state: fmi2GetFMUstateTYPE = fmi2GetFMUstate,
        set_fmu_state: fmi2SetFMUstateTYPE = fmi2SetFMUstate,
        free_fmu_state: fmi2FreeFMUstateTYPE = fmi2FreeFMUstate,
        serialized_fmu_state_size: fmi2SerializedFMUstateSizeTYPE = fmi2SerializedFMUstateSize,
        serialize_fmu_state: fmi2SerializeFMUstateTYPE = fmi2SerializeFMUstate,
        de_serialize_fmu_state: fmi2DeSerializeFMUstateTYPE = fmi2DeSerializeFMUstate,
        get_directional_derivative: fmi2GetDirectionalDerivativeTYPE = fmi2GetDirectionalDerivative,
    }
}

function_table! {
    $
    /// The 9 functions of Co-Simulation (FMI 2.0, 4.2).
    Fmi2CoSimulation, linked as fmi2_co_simulation {
        set_real_input_derivatives: fmi2SetRealInputDerivativesTYPE = fmi2SetRealInputDerivatives,
        get_real_output_derivatives: fmi2GetRealOutputDerivativesTYPE = fmi2GetRealOutputDerivatives,
        do_step: fmi2DoStepTYPE = fmi2DoStep,
        cancel_step: fmi2ComponentOnlyTYPE = fmi2CancelStep,
        get_status: fmi2GetStatusTYPE = fmi2GetStatus,
        get_real_status: fmi2GetRealStatusTYPE = fmi2GetRealStatus,
        get_integer_status: fmi2GetIntegerStatusTYPE = fmi2GetIntegerStatus,
        get_boolean_status: fmi2GetBooleanStatusTYPE = fmi2GetBooleanStatus,
        get_string_status: fmi2GetStringStatusTYPE = fmi2GetStringStatus,
    }
}

function_table! {
    $
    /// The 10 functions of Model Exchange (FMI 2.0, 3.2).
    Fmi2ModelExchange, linked as fmi2_model_exchange {
        enter_event_mode: fmi2ComponentOnlyTYPE = fmi2EnterEventMode,
        new_discrete_states: fmi2NewDiscreteStatesTYPE = fmi2NewDiscreteStates,
        enter_continuous_time_mode: fmi2ComponentOnlyTYPE = fmi2EnterContinuousTimeMode,
        completed_integrator_step: fmi2CompletedIntegratorStepTYPE = fmi2CompletedIntegratorStep,
        set_time: fmi2SetTimeTYPE = fmi2SetTime,
        set_continuous_states: fmi2SetContinuousStatesTYPE = fmi2SetContinuousStates,
        get_derivatives: fmi2GetRealVectorTYPE = fmi2GetDerivatives,
        get_event_indicators: fmi2GetRealVectorTYPE = fmi2GetEventIndicators,
        get_continuous_states: fmi2GetRealVectorTYPE = fmi2GetContinuousStates,
        get_nominals_of_continuous_states: fmi2GetRealVectorTYPE = fmi2GetNominalsOfContinuousStates,
    }
}

#[cfg(test)]
mod tests {
    use super::super::assert_listed_once;
    use super::*;

    #[test]
    fn the_fmi2_tables_list_the_standards_25_common_9_co_simulation_and_10_model_exchange_functions(
    ) {
        assert_listed_once(Fmi2Common::SYMBOLS, "fmi2", 25);
        assert_listed_once(Fmi2CoSimulation::SYMBOLS, "fmi2", 9);
        assert_listed_once(Fmi2ModelExchange::SYMBOLS, "fmi2", 10);
        let all = [
            Fmi2Common::SYMBOLS,
            Fmi2CoSimulation::SYMBOLS,
            Fmi2ModelExchange::SYMBOLS,
        ]
        .concat();
        assert_listed_once(&all, "fmi2", 44);
    }
}
