//! FMI 3.0: the common functions, those of Co-Simulation and those of Model Exchange, typed
//! after `fmi3FunctionTypes.h` (the C types are `fmi-abi`'s). Every variable type but Clock
//! is listed, and Configuration Mode (structural parameters); clocks and scheduled execution
//! are not, since the importer refuses FMUs that need them.
use super::function_table;
use fmi_abi::fmi3::*;
use std::ffi::c_char;

type Vr = fmi3ValueReference;
type Inst = fmi3Instance;
pub type Get<T> = unsafe extern "C" fn(Inst, *const Vr, usize, *mut T, usize) -> fmi3Status;
pub type Set<T> = unsafe extern "C" fn(Inst, *const Vr, usize, *const T, usize) -> fmi3Status;
pub type GetBinary =
    unsafe extern "C" fn(Inst, *const Vr, usize, *mut usize, *mut fmi3Binary, usize) -> fmi3Status;
pub type SetBinary = unsafe extern "C" fn(
    Inst,
    *const Vr,
    usize,
    *const usize,
    *const fmi3Binary,
    usize,
) -> fmi3Status;
pub type Only = unsafe extern "C" fn(Inst) -> fmi3Status;
pub type Vector = unsafe extern "C" fn(Inst, *mut f64, usize) -> fmi3Status;
pub type GetVersion = unsafe extern "C" fn() -> *const c_char;
pub type SetDebugLogging =
    unsafe extern "C" fn(Inst, fmi3Boolean, usize, *const fmi3String) -> fmi3Status;
pub type FreeInstance = unsafe extern "C" fn(Inst);
pub type EnterInitializationMode =
    unsafe extern "C" fn(Inst, fmi3Boolean, f64, f64, fmi3Boolean, f64) -> fmi3Status;
pub type GetFmuState = unsafe extern "C" fn(Inst, *mut fmi3FMUState) -> fmi3Status;
pub type SetFmuState = unsafe extern "C" fn(Inst, fmi3FMUState) -> fmi3Status;
pub type SerializedFmuStateSize =
    unsafe extern "C" fn(Inst, fmi3FMUState, *mut usize) -> fmi3Status;
pub type SerializeFmuState =
    unsafe extern "C" fn(Inst, fmi3FMUState, *mut fmi3Byte, usize) -> fmi3Status;
pub type DeserializeFmuState =
    unsafe extern "C" fn(Inst, *const fmi3Byte, usize, *mut fmi3FMUState) -> fmi3Status;
pub type UpdateDiscreteStates = unsafe extern "C" fn(
    Inst,
    *mut fmi3Boolean,
    *mut fmi3Boolean,
    *mut fmi3Boolean,
    *mut fmi3Boolean,
    *mut fmi3Boolean,
    *mut f64,
) -> fmi3Status;
pub type InstantiateCoSimulation = unsafe extern "C" fn(
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
pub type DoStep = unsafe extern "C" fn(
    Inst,
    f64,
    f64,
    fmi3Boolean,
    *mut fmi3Boolean,
    *mut fmi3Boolean,
    *mut fmi3Boolean,
    *mut f64,
) -> fmi3Status;
pub type InstantiateModelExchange = unsafe extern "C" fn(
    fmi3String,
    fmi3String,
    fmi3String,
    fmi3Boolean,
    fmi3Boolean,
    fmi3InstanceEnvironment,
    fmi3LogMessageCallback,
) -> Inst;
pub type CompletedIntegratorStep =
    unsafe extern "C" fn(Inst, fmi3Boolean, *mut fmi3Boolean, *mut fmi3Boolean) -> fmi3Status;
pub type SetTime = unsafe extern "C" fn(Inst, f64) -> fmi3Status;
pub type SetContinuousStates = unsafe extern "C" fn(Inst, *const f64, usize) -> fmi3Status;
pub type GetCount = unsafe extern "C" fn(Inst, *mut usize) -> fmi3Status;
/// `fmi3GetDirectionalDerivative` and `fmi3GetAdjointDerivative` (the same signature).
pub type Derivative = unsafe extern "C" fn(
    Inst,
    *const Vr,
    usize,
    *const Vr,
    usize,
    *const f64,
    usize,
    *mut f64,
    usize,
) -> fmi3Status;

function_table! {
    $
    /// The functions both interfaces export (FMI 3.0, 2.3): version, logging, lifecycle,
    /// values, FMU states, the event update and partial derivatives.
    Fmi3Common, linked as fmi3_common {
        get_version: GetVersion = fmi3GetVersion,
        set_debug_logging: SetDebugLogging = fmi3SetDebugLogging,
        free_instance: FreeInstance = fmi3FreeInstance,
        enter_configuration_mode: Only = fmi3EnterConfigurationMode,
        exit_configuration_mode: Only = fmi3ExitConfigurationMode,
        enter_initialization_mode: EnterInitializationMode = fmi3EnterInitializationMode,
        exit_initialization_mode: Only = fmi3ExitInitializationMode,
        enter_event_mode: Only = fmi3EnterEventMode,
        terminate: Only = fmi3Terminate,
        reset: Only = fmi3Reset,
        get_float64: Get<f64> = fmi3GetFloat64,
        get_int32: Get<i32> = fmi3GetInt32,
        get_int64: Get<i64> = fmi3GetInt64,
        get_float32: Get<f32> = fmi3GetFloat32,
        get_int8: Get<i8> = fmi3GetInt8,
        get_uint8: Get<u8> = fmi3GetUInt8,
        get_int16: Get<i16> = fmi3GetInt16,
        get_uint16: Get<u16> = fmi3GetUInt16,
        get_uint32: Get<u32> = fmi3GetUInt32,
        get_uint64: Get<u64> = fmi3GetUInt64,
        get_binary: GetBinary = fmi3GetBinary,
        get_boolean: Get<fmi3Boolean> = fmi3GetBoolean,
        get_string: Get<fmi3String> = fmi3GetString,
        set_float64: Set<f64> = fmi3SetFloat64,
        set_int32: Set<i32> = fmi3SetInt32,
        set_int64: Set<i64> = fmi3SetInt64,
        set_float32: Set<f32> = fmi3SetFloat32,
        set_int8: Set<i8> = fmi3SetInt8,
        set_uint8: Set<u8> = fmi3SetUInt8,
        set_int16: Set<i16> = fmi3SetInt16,
        set_uint16: Set<u16> = fmi3SetUInt16,
        set_uint32: Set<u32> = fmi3SetUInt32,
        set_uint64: Set<u64> = fmi3SetUInt64,
        set_binary: SetBinary = fmi3SetBinary,
        set_boolean: Set<fmi3Boolean> = fmi3SetBoolean,
        set_string: Set<fmi3String> = fmi3SetString,
        get_fmu_state: GetFmuState = fmi3GetFMUState,
        set_fmu_state: SetFmuState = fmi3SetFMUState,
        free_fmu_state: GetFmuState = fmi3FreeFMUState,
        serialized_fmu_state_size: SerializedFmuStateSize = fmi3SerializedFMUStateSize,
        serialize_fmu_state: SerializeFmuState = fmi3SerializeFMUState,
        deserialize_fmu_state: DeserializeFmuState = fmi3DeserializeFMUState,
        update_discrete_states: UpdateDiscreteStates = fmi3UpdateDiscreteStates,
        get_directional_derivative: Derivative = fmi3GetDirectionalDerivative,
        get_adjoint_derivative: Derivative = fmi3GetAdjointDerivative,
    }
}

function_table! {
    $
    /// The functions of Co-Simulation (FMI 3.0, 4).
    Fmi3CoSimulation, linked as fmi3_co_simulation {
        instantiate_co_simulation: InstantiateCoSimulation = fmi3InstantiateCoSimulation,
        enter_step_mode: Only = fmi3EnterStepMode,
        do_step: DoStep = fmi3DoStep,
    }
}

function_table! {
    $
    /// The functions of Model Exchange (FMI 3.0, 3).
    Fmi3ModelExchange, linked as fmi3_model_exchange {
        instantiate_model_exchange: InstantiateModelExchange = fmi3InstantiateModelExchange,
        enter_continuous_time_mode: Only = fmi3EnterContinuousTimeMode,
        completed_integrator_step: CompletedIntegratorStep = fmi3CompletedIntegratorStep,
        set_time: SetTime = fmi3SetTime,
        set_continuous_states: SetContinuousStates = fmi3SetContinuousStates,
        get_continuous_state_derivatives: Vector = fmi3GetContinuousStateDerivatives,
        get_event_indicators: Vector = fmi3GetEventIndicators,
        get_continuous_states: Vector = fmi3GetContinuousStates,
        get_nominals_of_continuous_states: Vector = fmi3GetNominalsOfContinuousStates,
        get_number_of_event_indicators: GetCount = fmi3GetNumberOfEventIndicators,
        get_number_of_continuous_states: GetCount = fmi3GetNumberOfContinuousStates,
    }
}

#[cfg(test)]
mod tests {
    use super::super::assert_listed_once;
    use super::*;

    #[test]
    fn the_fmi3_tables_list_each_function_once_across_the_interfaces() {
        let all = [
            Fmi3Common::SYMBOLS,
            Fmi3CoSimulation::SYMBOLS,
            Fmi3ModelExchange::SYMBOLS,
        ]
        .concat();
        assert_listed_once(&all, "fmi3", all.len());
        assert!(Fmi3CoSimulation::SYMBOLS.contains(&"fmi3InstantiateCoSimulation"));
        assert!(Fmi3ModelExchange::SYMBOLS.contains(&"fmi3InstantiateModelExchange"));
    }
}
