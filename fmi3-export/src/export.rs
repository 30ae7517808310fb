//! `export_fmi3!`: the 75 C symbols of an FMI 3.0 FMU.

/// Exports every FMI 3.0 function for `$model` from the invoking crate, each a one-line call
/// into [`crate::abi`] or [`crate::me`]. `export_fmi3!(crate::M)` is Co-Simulation only (the
/// Model Exchange functions refuse, from [`crate::no_me`]); `export_fmi3!(crate::M,
/// model_exchange)` adds Model Exchange for a model that implements
/// `fmi_model::ContinuousModel`. The functions of features none of our FMUs has (clocks,
/// configuration mode, Scheduled Execution) answer `fmi3Error` with a log line.
/// The symbols are named `fmi3*`, so they live beside the FMI 2.0 layer's `fmi2*` ones in
/// one library.
#[macro_export]
macro_rules! export_fmi3 {
    ($model:ty) => {
        $crate::export_fmi3! { @all $model, no_me }
        // A Co-Simulation-only model: the Model Exchange functions refuse.
        $crate::fmi_export::export_symbols! {
            fmi3EnterContinuousTimeMode(
                instance: $crate::ffi::fmi3Instance
            ) -> $crate::ffi::fmi3Status
                => $crate::no_me::enter_continuous_time_mode::<$model>(instance);
            fmi3SetTime(
                instance: $crate::ffi::fmi3Instance,
                time: $crate::ffi::fmi3Float64
            ) -> $crate::ffi::fmi3Status
                => $crate::no_me::set_time::<$model>(instance, time);
            fmi3SetContinuousStates(
                instance: $crate::ffi::fmi3Instance,
                continuousStates: *const $crate::ffi::fmi3Float64,
                nContinuousStates: usize
            ) -> $crate::ffi::fmi3Status
                => $crate::no_me::set_continuous_states::<$model>(instance, continuousStates, nContinuousStates);
            fmi3GetContinuousStateDerivatives(
                instance: $crate::ffi::fmi3Instance,
                derivatives: *mut $crate::ffi::fmi3Float64,
                nContinuousStates: usize
            ) -> $crate::ffi::fmi3Status
                => $crate::no_me::get_continuous_state_derivatives::<$model>(instance, derivatives, nContinuousStates);
            fmi3GetEventIndicators(
                instance: $crate::ffi::fmi3Instance,
                eventIndicators: *mut $crate::ffi::fmi3Float64,
                nEventIndicators: usize
            ) -> $crate::ffi::fmi3Status
                => $crate::no_me::get_event_indicators::<$model>(instance, eventIndicators, nEventIndicators);
            fmi3GetContinuousStates(
                instance: $crate::ffi::fmi3Instance,
                continuousStates: *mut $crate::ffi::fmi3Float64,
                nContinuousStates: usize
            ) -> $crate::ffi::fmi3Status
                => $crate::no_me::get_continuous_states::<$model>(instance, continuousStates, nContinuousStates);
            fmi3GetNominalsOfContinuousStates(
                instance: $crate::ffi::fmi3Instance,
                nominals: *mut $crate::ffi::fmi3Float64,
                nContinuousStates: usize
            ) -> $crate::ffi::fmi3Status
                => $crate::no_me::get_nominals_of_continuous_states::<$model>(instance, nominals, nContinuousStates);
        }
    };
    ($model:ty, model_exchange) => {
        $crate::export_fmi3! { @all $model, me }
        $crate::fmi_export::export_shared! { $model, $crate::Fmi3,
            status = $crate::ffi::fmi3Status, model_exchange = [
            fmi3SetTime, fmi3SetContinuousStates, fmi3GetContinuousStateDerivatives,
            fmi3GetEventIndicators, fmi3GetContinuousStates, fmi3GetNominalsOfContinuousStates,
            fmi3EnterContinuousTimeMode
        ] }
    };
    (@all $model:ty, $me:ident) => {
        $crate::fmi_export::export_shared! { $model, $crate::Fmi3,
            status = $crate::ffi::fmi3Status, byte = $crate::ffi::fmi3Byte,
            fmu_state = [fmi3GetFMUState, fmi3SetFMUState, fmi3FreeFMUState,
                fmi3SerializedFMUStateSize, fmi3SerializeFMUState, fmi3DeserializeFMUState],
            lifecycle = [fmi3ExitInitializationMode, fmi3Terminate, fmi3Reset]
        }
        $crate::fmi_export::export_symbols! {
            fmi3GetVersion(

            ) -> *const ::std::os::raw::c_char
                => $crate::abi::get_version();
            fmi3SetDebugLogging(
                instance: $crate::ffi::fmi3Instance,
                loggingOn: $crate::ffi::fmi3Boolean,
                nCategories: usize,
                categories: *const $crate::ffi::fmi3String
            ) -> $crate::ffi::fmi3Status
                => $crate::abi::set_debug_logging::<$model>(instance, loggingOn, nCategories, categories);
            fmi3InstantiateModelExchange(
                instanceName: $crate::ffi::fmi3String,
                instantiationToken: $crate::ffi::fmi3String,
                resourcePath: $crate::ffi::fmi3String,
                visible: $crate::ffi::fmi3Boolean,
                loggingOn: $crate::ffi::fmi3Boolean,
                instanceEnvironment: $crate::ffi::fmi3InstanceEnvironment,
                logMessage: $crate::ffi::fmi3LogMessageCallback
            ) -> $crate::ffi::fmi3Instance
                => $crate::$me::instantiate_model_exchange::<$model>(instanceName, instantiationToken, resourcePath, visible, loggingOn, instanceEnvironment, logMessage);
            fmi3InstantiateCoSimulation(
                instanceName: $crate::ffi::fmi3String,
                instantiationToken: $crate::ffi::fmi3String,
                resourcePath: $crate::ffi::fmi3String,
                visible: $crate::ffi::fmi3Boolean,
                loggingOn: $crate::ffi::fmi3Boolean,
                eventModeUsed: $crate::ffi::fmi3Boolean,
                earlyReturnAllowed: $crate::ffi::fmi3Boolean,
                requiredIntermediateVariables: *const $crate::ffi::fmi3ValueReference,
                nRequiredIntermediateVariables: usize,
                instanceEnvironment: $crate::ffi::fmi3InstanceEnvironment,
                logMessage: $crate::ffi::fmi3LogMessageCallback,
                intermediateUpdate: $crate::ffi::fmi3IntermediateUpdateCallback
            ) -> $crate::ffi::fmi3Instance
                => $crate::abi::instantiate_co_simulation::<$model>(instanceName, instantiationToken, resourcePath, visible, loggingOn, eventModeUsed, earlyReturnAllowed, requiredIntermediateVariables, nRequiredIntermediateVariables, instanceEnvironment, logMessage, intermediateUpdate);
            fmi3InstantiateScheduledExecution(
                instanceName: $crate::ffi::fmi3String,
                instantiationToken: $crate::ffi::fmi3String,
                resourcePath: $crate::ffi::fmi3String,
                visible: $crate::ffi::fmi3Boolean,
                loggingOn: $crate::ffi::fmi3Boolean,
                instanceEnvironment: $crate::ffi::fmi3InstanceEnvironment,
                logMessage: $crate::ffi::fmi3LogMessageCallback,
                clockUpdate: $crate::ffi::fmi3ClockUpdateCallback,
                lockPreemption: $crate::ffi::fmi3LockPreemptionCallback,
                unlockPreemption: $crate::ffi::fmi3UnlockPreemptionCallback
            ) -> $crate::ffi::fmi3Instance
                => $crate::abi::instantiate_scheduled_execution::<$model>(instanceName, instantiationToken, resourcePath, visible, loggingOn, instanceEnvironment, logMessage, clockUpdate, lockPreemption, unlockPreemption);
            fmi3FreeInstance(
                instance: $crate::ffi::fmi3Instance
            ) -> ()
                => $crate::abi::free_instance::<$model>(instance);
            fmi3EnterInitializationMode(
                instance: $crate::ffi::fmi3Instance,
                toleranceDefined: $crate::ffi::fmi3Boolean,
                tolerance: $crate::ffi::fmi3Float64,
                startTime: $crate::ffi::fmi3Float64,
                stopTimeDefined: $crate::ffi::fmi3Boolean,
                stopTime: $crate::ffi::fmi3Float64
            ) -> $crate::ffi::fmi3Status
                => $crate::abi::enter_initialization_mode::<$model>(instance, toleranceDefined, tolerance, startTime, stopTimeDefined, stopTime);
            fmi3EnterEventMode(
                instance: $crate::ffi::fmi3Instance
            ) -> $crate::ffi::fmi3Status
                => $crate::$me::enter_event_mode::<$model>(instance);
            fmi3GetFloat32(
                instance: $crate::ffi::fmi3Instance,
                valueReferences: *const $crate::ffi::fmi3ValueReference,
                nValueReferences: usize,
                values: *mut $crate::ffi::fmi3Float32,
                nValues: usize
            ) -> $crate::ffi::fmi3Status
                => $crate::abi::no_variables::<$model>(instance, $crate::state::Function::GetFloat32, valueReferences, nValueReferences);
            fmi3GetFloat64(
                instance: $crate::ffi::fmi3Instance,
                valueReferences: *const $crate::ffi::fmi3ValueReference,
                nValueReferences: usize,
                values: *mut $crate::ffi::fmi3Float64,
                nValues: usize
            ) -> $crate::ffi::fmi3Status
                => $crate::abi::get_float64::<$model>(instance, valueReferences, nValueReferences, values, nValues);
            fmi3GetInt8(
                instance: $crate::ffi::fmi3Instance,
                valueReferences: *const $crate::ffi::fmi3ValueReference,
                nValueReferences: usize,
                values: *mut $crate::ffi::fmi3Int8,
                nValues: usize
            ) -> $crate::ffi::fmi3Status
                => $crate::abi::no_variables::<$model>(instance, $crate::state::Function::GetInt8, valueReferences, nValueReferences);
            fmi3GetUInt8(
                instance: $crate::ffi::fmi3Instance,
                valueReferences: *const $crate::ffi::fmi3ValueReference,
                nValueReferences: usize,
                values: *mut $crate::ffi::fmi3UInt8,
                nValues: usize
            ) -> $crate::ffi::fmi3Status
                => $crate::abi::no_variables::<$model>(instance, $crate::state::Function::GetUInt8, valueReferences, nValueReferences);
            fmi3GetInt16(
                instance: $crate::ffi::fmi3Instance,
                valueReferences: *const $crate::ffi::fmi3ValueReference,
                nValueReferences: usize,
                values: *mut $crate::ffi::fmi3Int16,
                nValues: usize
            ) -> $crate::ffi::fmi3Status
                => $crate::abi::no_variables::<$model>(instance, $crate::state::Function::GetInt16, valueReferences, nValueReferences);
            fmi3GetUInt16(
                instance: $crate::ffi::fmi3Instance,
                valueReferences: *const $crate::ffi::fmi3ValueReference,
                nValueReferences: usize,
                values: *mut $crate::ffi::fmi3UInt16,
                nValues: usize
            ) -> $crate::ffi::fmi3Status
                => $crate::abi::no_variables::<$model>(instance, $crate::state::Function::GetUInt16, valueReferences, nValueReferences);
            fmi3GetInt32(
                instance: $crate::ffi::fmi3Instance,
                valueReferences: *const $crate::ffi::fmi3ValueReference,
                nValueReferences: usize,
                values: *mut $crate::ffi::fmi3Int32,
                nValues: usize
            ) -> $crate::ffi::fmi3Status
                => $crate::abi::get_int32::<$model>(instance, valueReferences, nValueReferences, values, nValues);
            fmi3GetUInt32(
                instance: $crate::ffi::fmi3Instance,
                valueReferences: *const $crate::ffi::fmi3ValueReference,
                nValueReferences: usize,
                values: *mut $crate::ffi::fmi3UInt32,
                nValues: usize
            ) -> $crate::ffi::fmi3Status
                => $crate::abi::no_variables::<$model>(instance, $crate::state::Function::GetUInt32, valueReferences, nValueReferences);
            fmi3GetInt64(
                instance: $crate::ffi::fmi3Instance,
                valueReferences: *const $crate::ffi::fmi3ValueReference,
                nValueReferences: usize,
                values: *mut $crate::ffi::fmi3Int64,
                nValues: usize
            ) -> $crate::ffi::fmi3Status
                => $crate::abi::get_int64::<$model>(instance, valueReferences, nValueReferences, values, nValues);
            fmi3GetUInt64(
                instance: $crate::ffi::fmi3Instance,
                valueReferences: *const $crate::ffi::fmi3ValueReference,
                nValueReferences: usize,
                values: *mut $crate::ffi::fmi3UInt64,
                nValues: usize
            ) -> $crate::ffi::fmi3Status
                => $crate::abi::no_variables::<$model>(instance, $crate::state::Function::GetUInt64, valueReferences, nValueReferences);
            fmi3GetBoolean(
                instance: $crate::ffi::fmi3Instance,
                valueReferences: *const $crate::ffi::fmi3ValueReference,
                nValueReferences: usize,
                values: *mut $crate::ffi::fmi3Boolean,
                nValues: usize
            ) -> $crate::ffi::fmi3Status
                => $crate::abi::get_boolean::<$model>(instance, valueReferences, nValueReferences, values, nValues);
            fmi3GetString(
                instance: $crate::ffi::fmi3Instance,
                valueReferences: *const $crate::ffi::fmi3ValueReference,
                nValueReferences: usize,
                values: *mut $crate::ffi::fmi3String,
                nValues: usize
            ) -> $crate::ffi::fmi3Status
                => $crate::abi::get_string::<$model>(instance, valueReferences, nValueReferences, values, nValues);
            fmi3GetBinary(
                instance: $crate::ffi::fmi3Instance,
                valueReferences: *const $crate::ffi::fmi3ValueReference,
                nValueReferences: usize,
                valueSizes: *mut usize,
                values: *mut $crate::ffi::fmi3Binary,
                nValues: usize
            ) -> $crate::ffi::fmi3Status
                => $crate::abi::no_variables::<$model>(instance, $crate::state::Function::GetBinary, valueReferences, nValueReferences);
            fmi3GetClock(
                instance: $crate::ffi::fmi3Instance,
                valueReferences: *const $crate::ffi::fmi3ValueReference,
                nValueReferences: usize,
                values: *mut $crate::ffi::fmi3Clock
            ) -> $crate::ffi::fmi3Status
                => $crate::abi::unsupported::<$model>(instance, $crate::state::Function::GetClock);
            fmi3SetFloat32(
                instance: $crate::ffi::fmi3Instance,
                valueReferences: *const $crate::ffi::fmi3ValueReference,
                nValueReferences: usize,
                values: *const $crate::ffi::fmi3Float32,
                nValues: usize
            ) -> $crate::ffi::fmi3Status
                => $crate::abi::no_variables::<$model>(instance, $crate::state::Function::SetFloat32, valueReferences, nValueReferences);
            fmi3SetFloat64(
                instance: $crate::ffi::fmi3Instance,
                valueReferences: *const $crate::ffi::fmi3ValueReference,
                nValueReferences: usize,
                values: *const $crate::ffi::fmi3Float64,
                nValues: usize
            ) -> $crate::ffi::fmi3Status
                => $crate::abi::set_float64::<$model>(instance, valueReferences, nValueReferences, values, nValues);
            fmi3SetInt8(
                instance: $crate::ffi::fmi3Instance,
                valueReferences: *const $crate::ffi::fmi3ValueReference,
                nValueReferences: usize,
                values: *const $crate::ffi::fmi3Int8,
                nValues: usize
            ) -> $crate::ffi::fmi3Status
                => $crate::abi::no_variables::<$model>(instance, $crate::state::Function::SetInt8, valueReferences, nValueReferences);
            fmi3SetUInt8(
                instance: $crate::ffi::fmi3Instance,
                valueReferences: *const $crate::ffi::fmi3ValueReference,
                nValueReferences: usize,
                values: *const $crate::ffi::fmi3UInt8,
                nValues: usize
            ) -> $crate::ffi::fmi3Status
                => $crate::abi::no_variables::<$model>(instance, $crate::state::Function::SetUInt8, valueReferences, nValueReferences);
            fmi3SetInt16(
                instance: $crate::ffi::fmi3Instance,
                valueReferences: *const $crate::ffi::fmi3ValueReference,
                nValueReferences: usize,
                values: *const $crate::ffi::fmi3Int16,
                nValues: usize
            ) -> $crate::ffi::fmi3Status
                => $crate::abi::no_variables::<$model>(instance, $crate::state::Function::SetInt16, valueReferences, nValueReferences);
            fmi3SetUInt16(
                instance: $crate::ffi::fmi3Instance,
                valueReferences: *const $crate::ffi::fmi3ValueReference,
                nValueReferences: usize,
                values: *const $crate::ffi::fmi3UInt16,
                nValues: usize
            ) -> $crate::ffi::fmi3Status
                => $crate::abi::no_variables::<$model>(instance, $crate::state::Function::SetUInt16, valueReferences, nValueReferences);
            fmi3SetInt32(
                instance: $crate::ffi::fmi3Instance,
                valueReferences: *const $crate::ffi::fmi3ValueReference,
                nValueReferences: usize,
                values: *const $crate::ffi::fmi3Int32,
                nValues: usize
            ) -> $crate::ffi::fmi3Status
                => $crate::abi::set_int32::<$model>(instance, valueReferences, nValueReferences, values, nValues);
            fmi3SetUInt32(
                instance: $crate::ffi::fmi3Instance,
                valueReferences: *const $crate::ffi::fmi3ValueReference,
                nValueReferences: usize,
                values: *const $crate::ffi::fmi3UInt32,
                nValues: usize
            ) -> $crate::ffi::fmi3Status
                => $crate::abi::no_variables::<$model>(instance, $crate::state::Function::SetUInt32, valueReferences, nValueReferences);
            fmi3SetInt64(
                instance: $crate::ffi::fmi3Instance,
                valueReferences: *const $crate::ffi::fmi3ValueReference,
                nValueReferences: usize,
                values: *const $crate::ffi::fmi3Int64,
                nValues: usize
            ) -> $crate::ffi::fmi3Status
                => $crate::abi::set_int64::<$model>(instance, valueReferences, nValueReferences, values, nValues);
            fmi3SetUInt64(
                instance: $crate::ffi::fmi3Instance,
                valueReferences: *const $crate::ffi::fmi3ValueReference,
                nValueReferences: usize,
                values: *const $crate::ffi::fmi3UInt64,
                nValues: usize
            ) -> $crate::ffi::fmi3Status
                => $crate::abi::no_variables::<$model>(instance, $crate::state::Function::SetUInt64, valueReferences, nValueReferences);
            fmi3SetBoolean(
                instance: $crate::ffi::fmi3Instance,
                valueReferences: *const $crate::ffi::fmi3ValueReference,
                nValueReferences: usize,
                values: *const $crate::ffi::fmi3Boolean,
                nValues: usize
            ) -> $crate::ffi::fmi3Status
                => $crate::abi::set_boolean::<$model>(instance, valueReferences, nValueReferences, values, nValues);
            fmi3SetString(
                instance: $crate::ffi::fmi3Instance,
                valueReferences: *const $crate::ffi::fmi3ValueReference,
                nValueReferences: usize,
                values: *const $crate::ffi::fmi3String,
                nValues: usize
            ) -> $crate::ffi::fmi3Status
                => $crate::abi::set_string::<$model>(instance, valueReferences, nValueReferences, values, nValues);
            fmi3SetBinary(
                instance: $crate::ffi::fmi3Instance,
                valueReferences: *const $crate::ffi::fmi3ValueReference,
                nValueReferences: usize,
                valueSizes: *const usize,
                values: *const $crate::ffi::fmi3Binary,
                nValues: usize
            ) -> $crate::ffi::fmi3Status
                => $crate::abi::no_variables::<$model>(instance, $crate::state::Function::SetBinary, valueReferences, nValueReferences);
            fmi3SetClock(
                instance: $crate::ffi::fmi3Instance,
                valueReferences: *const $crate::ffi::fmi3ValueReference,
                nValueReferences: usize,
                values: *const $crate::ffi::fmi3Clock
            ) -> $crate::ffi::fmi3Status
                => $crate::abi::unsupported::<$model>(instance, $crate::state::Function::SetClock);
            fmi3GetNumberOfVariableDependencies(
                instance: $crate::ffi::fmi3Instance,
                valueReference: $crate::ffi::fmi3ValueReference,
                nDependencies: *mut usize
            ) -> $crate::ffi::fmi3Status
                => $crate::abi::unsupported::<$model>(instance, $crate::state::Function::GetNumberOfVariableDependencies);
            fmi3GetVariableDependencies(
                instance: $crate::ffi::fmi3Instance,
                dependent: $crate::ffi::fmi3ValueReference,
                elementIndicesOfDependent: *mut usize,
                independents: *mut $crate::ffi::fmi3ValueReference,
                elementIndicesOfIndependents: *mut usize,
                dependencyKinds: *mut $crate::ffi::fmi3DependencyKind,
                nDependencies: usize
            ) -> $crate::ffi::fmi3Status
                => $crate::abi::unsupported::<$model>(instance, $crate::state::Function::GetVariableDependencies);
            fmi3GetDirectionalDerivative(
                instance: $crate::ffi::fmi3Instance,
                unknowns: *const $crate::ffi::fmi3ValueReference,
                nUnknowns: usize,
                knowns: *const $crate::ffi::fmi3ValueReference,
                nKnowns: usize,
                seed: *const $crate::ffi::fmi3Float64,
                nSeed: usize,
                sensitivity: *mut $crate::ffi::fmi3Float64,
                nSensitivity: usize
            ) -> $crate::ffi::fmi3Status
                => $crate::$me::derivative::<$model>(instance, $crate::state::Function::GetDirectionalDerivative, unknowns, nUnknowns, knowns, nKnowns, seed, nSeed, sensitivity, nSensitivity);
            fmi3GetAdjointDerivative(
                instance: $crate::ffi::fmi3Instance,
                unknowns: *const $crate::ffi::fmi3ValueReference,
                nUnknowns: usize,
                knowns: *const $crate::ffi::fmi3ValueReference,
                nKnowns: usize,
                seed: *const $crate::ffi::fmi3Float64,
                nSeed: usize,
                sensitivity: *mut $crate::ffi::fmi3Float64,
                nSensitivity: usize
            ) -> $crate::ffi::fmi3Status
                => $crate::$me::derivative::<$model>(instance, $crate::state::Function::GetAdjointDerivative, unknowns, nUnknowns, knowns, nKnowns, seed, nSeed, sensitivity, nSensitivity);
            fmi3EnterConfigurationMode(
                instance: $crate::ffi::fmi3Instance
            ) -> $crate::ffi::fmi3Status
                => $crate::abi::unsupported::<$model>(instance, $crate::state::Function::EnterConfigurationMode);
            fmi3ExitConfigurationMode(
                instance: $crate::ffi::fmi3Instance
            ) -> $crate::ffi::fmi3Status
                => $crate::abi::unsupported::<$model>(instance, $crate::state::Function::ExitConfigurationMode);
            fmi3GetIntervalDecimal(
                instance: $crate::ffi::fmi3Instance,
                valueReferences: *const $crate::ffi::fmi3ValueReference,
                nValueReferences: usize,
                intervals: *mut $crate::ffi::fmi3Float64,
                qualifiers: *mut $crate::ffi::fmi3IntervalQualifier
            ) -> $crate::ffi::fmi3Status
                => $crate::abi::unsupported::<$model>(instance, $crate::state::Function::GetIntervalDecimal);
            fmi3GetIntervalFraction(
                instance: $crate::ffi::fmi3Instance,
                valueReferences: *const $crate::ffi::fmi3ValueReference,
                nValueReferences: usize,
                counters: *mut $crate::ffi::fmi3UInt64,
                resolutions: *mut $crate::ffi::fmi3UInt64,
                qualifiers: *mut $crate::ffi::fmi3IntervalQualifier
            ) -> $crate::ffi::fmi3Status
                => $crate::abi::unsupported::<$model>(instance, $crate::state::Function::GetIntervalFraction);
            fmi3GetShiftDecimal(
                instance: $crate::ffi::fmi3Instance,
                valueReferences: *const $crate::ffi::fmi3ValueReference,
                nValueReferences: usize,
                shifts: *mut $crate::ffi::fmi3Float64
            ) -> $crate::ffi::fmi3Status
                => $crate::abi::unsupported::<$model>(instance, $crate::state::Function::GetShiftDecimal);
            fmi3GetShiftFraction(
                instance: $crate::ffi::fmi3Instance,
                valueReferences: *const $crate::ffi::fmi3ValueReference,
                nValueReferences: usize,
                counters: *mut $crate::ffi::fmi3UInt64,
                resolutions: *mut $crate::ffi::fmi3UInt64
            ) -> $crate::ffi::fmi3Status
                => $crate::abi::unsupported::<$model>(instance, $crate::state::Function::GetShiftFraction);
            fmi3SetIntervalDecimal(
                instance: $crate::ffi::fmi3Instance,
                valueReferences: *const $crate::ffi::fmi3ValueReference,
                nValueReferences: usize,
                intervals: *const $crate::ffi::fmi3Float64
            ) -> $crate::ffi::fmi3Status
                => $crate::abi::unsupported::<$model>(instance, $crate::state::Function::SetIntervalDecimal);
            fmi3SetIntervalFraction(
                instance: $crate::ffi::fmi3Instance,
                valueReferences: *const $crate::ffi::fmi3ValueReference,
                nValueReferences: usize,
                counters: *const $crate::ffi::fmi3UInt64,
                resolutions: *const $crate::ffi::fmi3UInt64
            ) -> $crate::ffi::fmi3Status
                => $crate::abi::unsupported::<$model>(instance, $crate::state::Function::SetIntervalFraction);
            fmi3SetShiftDecimal(
                instance: $crate::ffi::fmi3Instance,
                valueReferences: *const $crate::ffi::fmi3ValueReference,
                nValueReferences: usize,
                shifts: *const $crate::ffi::fmi3Float64
            ) -> $crate::ffi::fmi3Status
                => $crate::abi::unsupported::<$model>(instance, $crate::state::Function::SetShiftDecimal);
            fmi3SetShiftFraction(
                instance: $crate::ffi::fmi3Instance,
                valueReferences: *const $crate::ffi::fmi3ValueReference,
                nValueReferences: usize,
                counters: *const $crate::ffi::fmi3UInt64,
                resolutions: *const $crate::ffi::fmi3UInt64
            ) -> $crate::ffi::fmi3Status
                => $crate::abi::unsupported::<$model>(instance, $crate::state::Function::SetShiftFraction);
            fmi3EvaluateDiscreteStates(
                instance: $crate::ffi::fmi3Instance
            ) -> $crate::ffi::fmi3Status
                => $crate::abi::evaluate_discrete_states::<$model>(instance);
            fmi3UpdateDiscreteStates(
                instance: $crate::ffi::fmi3Instance,
                discreteStatesNeedUpdate: *mut $crate::ffi::fmi3Boolean,
                terminateSimulation: *mut $crate::ffi::fmi3Boolean,
                nominalsOfContinuousStatesChanged: *mut $crate::ffi::fmi3Boolean,
                valuesOfContinuousStatesChanged: *mut $crate::ffi::fmi3Boolean,
                nextEventTimeDefined: *mut $crate::ffi::fmi3Boolean,
                nextEventTime: *mut $crate::ffi::fmi3Float64
            ) -> $crate::ffi::fmi3Status
                => $crate::$me::update_discrete_states::<$model>(instance, discreteStatesNeedUpdate, terminateSimulation, nominalsOfContinuousStatesChanged, valuesOfContinuousStatesChanged, nextEventTimeDefined, nextEventTime);
            fmi3CompletedIntegratorStep(
                instance: $crate::ffi::fmi3Instance,
                noSetFMUStatePriorToCurrentPoint: $crate::ffi::fmi3Boolean,
                enterEventMode: *mut $crate::ffi::fmi3Boolean,
                terminateSimulation: *mut $crate::ffi::fmi3Boolean
            ) -> $crate::ffi::fmi3Status
                => $crate::$me::completed_integrator_step::<$model>(instance, noSetFMUStatePriorToCurrentPoint, enterEventMode, terminateSimulation);
            fmi3GetNumberOfEventIndicators(
                instance: $crate::ffi::fmi3Instance,
                nEventIndicators: *mut usize
            ) -> $crate::ffi::fmi3Status
                => $crate::$me::get_number_of_event_indicators::<$model>(instance, nEventIndicators);
            fmi3GetNumberOfContinuousStates(
                instance: $crate::ffi::fmi3Instance,
                nContinuousStates: *mut usize
            ) -> $crate::ffi::fmi3Status
                => $crate::$me::get_number_of_continuous_states::<$model>(instance, nContinuousStates);
            fmi3EnterStepMode(
                instance: $crate::ffi::fmi3Instance
            ) -> $crate::ffi::fmi3Status
                => $crate::abi::enter_step_mode::<$model>(instance);
            fmi3GetOutputDerivatives(
                instance: $crate::ffi::fmi3Instance,
                valueReferences: *const $crate::ffi::fmi3ValueReference,
                nValueReferences: usize,
                orders: *const $crate::ffi::fmi3Int32,
                values: *mut $crate::ffi::fmi3Float64,
                nValues: usize
            ) -> $crate::ffi::fmi3Status
                => $crate::abi::unsupported::<$model>(instance, $crate::state::Function::GetOutputDerivatives);
            fmi3DoStep(
                instance: $crate::ffi::fmi3Instance,
                currentCommunicationPoint: $crate::ffi::fmi3Float64,
                communicationStepSize: $crate::ffi::fmi3Float64,
                noSetFMUStatePriorToCurrentPoint: $crate::ffi::fmi3Boolean,
                eventHandlingNeeded: *mut $crate::ffi::fmi3Boolean,
                terminateSimulation: *mut $crate::ffi::fmi3Boolean,
                earlyReturn: *mut $crate::ffi::fmi3Boolean,
                lastSuccessfulTime: *mut $crate::ffi::fmi3Float64
            ) -> $crate::ffi::fmi3Status
                => $crate::abi::do_step::<$model>(instance, currentCommunicationPoint, communicationStepSize, noSetFMUStatePriorToCurrentPoint, eventHandlingNeeded, terminateSimulation, earlyReturn, lastSuccessfulTime);
            fmi3ActivateModelPartition(
                instance: $crate::ffi::fmi3Instance,
                clockReference: $crate::ffi::fmi3ValueReference,
                activationTime: $crate::ffi::fmi3Float64
            ) -> $crate::ffi::fmi3Status
                => $crate::abi::unsupported::<$model>(instance, $crate::state::Function::ActivateModelPartition);
        }
    };
}
