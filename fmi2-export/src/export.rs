//! `export_fmi2!`: the 34 C symbols of a Co-Simulation FMU, 44 with Model Exchange.

/// Exports the 34 FMI 2.0 Co-Simulation functions for `$model` from the invoking crate
/// (`export_fmi2!(crate::M, model_exchange)` adds the 10 of Model Exchange for a model that
/// implements `fmi_model::ContinuousModel`),
/// each a one-line call into [`crate::abi`]. Invoke it once, at the root of a `cdylib`
/// crate whose model implements [`crate::Model`]:
///
/// ```ignore
/// fmi2_export::export_fmi2!(crate::LanderPlant);
/// ```
///
/// The functions are public `unsafe extern "C"` items of the invoking module (so Rust
/// tests can call them directly) carrying `#[allow(unsafe_code)]`: the model crate keeps
/// `#![deny(unsafe_code)]` for everything else. Two crates that invoke it cannot be
/// linked into one binary (the symbols would clash), exactly like two FMU libraries.
#[macro_export]
macro_rules! export_fmi2 {
    ($model:ty) => {
        $crate::export_fmi2! { @co_simulation $model, false, &[] }
    };
    // A model that implements `fmi_model::ContinuousModel`: Co-Simulation and Model Exchange.
    ($model:ty, model_exchange) => {
        $crate::export_fmi2! { @co_simulation $model, true,
        <$model as $crate::model::ContinuousModel>::STATE_DERIVATIVES }
        $crate::fmi_export::export_shared! { $model, $crate::Fmi2,
            status = $crate::ffi::fmi2Status, model_exchange = [
            fmi2SetTime, fmi2SetContinuousStates, fmi2GetDerivatives, fmi2GetEventIndicators,
            fmi2GetContinuousStates, fmi2GetNominalsOfContinuousStates, fmi2EnterContinuousTimeMode
        ] }
        $crate::fmi_export::export_symbols! {
            fmi2EnterEventMode(c: $crate::ffi::fmi2Component) -> $crate::ffi::fmi2Status
                => $crate::model_exchange::enter_event_mode::<$model>(c);
            fmi2NewDiscreteStates(
                c: $crate::ffi::fmi2Component,
                fmi2eventInfo: *mut $crate::ffi::fmi2EventInfo
            ) -> $crate::ffi::fmi2Status
                => $crate::model_exchange::new_discrete_states::<$model>(c, fmi2eventInfo);
            fmi2CompletedIntegratorStep(
                c: $crate::ffi::fmi2Component,
                noSetFMUStatePriorToCurrentPoint: $crate::ffi::fmi2Boolean,
                enterEventMode: *mut $crate::ffi::fmi2Boolean,
                terminateSimulation: *mut $crate::ffi::fmi2Boolean
            ) -> $crate::ffi::fmi2Status
                => $crate::model_exchange::completed_integrator_step::<$model>(
                    c, noSetFMUStatePriorToCurrentPoint, enterEventMode, terminateSimulation,
                );
        }
    };
    (@co_simulation $model:ty, $model_exchange:literal, $states:expr) => {
        $crate::fmi_export::export_shared! { $model, $crate::Fmi2,
            status = $crate::ffi::fmi2Status, byte = $crate::ffi::fmi2Byte,
            fmu_state = [fmi2GetFMUstate, fmi2SetFMUstate, fmi2FreeFMUstate,
                fmi2SerializedFMUstateSize, fmi2SerializeFMUstate, fmi2DeSerializeFMUstate],
            lifecycle = [fmi2ExitInitializationMode, fmi2Terminate, fmi2Reset]
        }
        $crate::fmi_export::export_symbols! {
            fmi2GetTypesPlatform() -> *const ::std::os::raw::c_char
                => $crate::abi::get_types_platform();
            fmi2GetVersion() -> *const ::std::os::raw::c_char
                => $crate::abi::get_version();
            fmi2SetDebugLogging(
                c: $crate::ffi::fmi2Component,
                loggingOn: $crate::ffi::fmi2Boolean,
                nCategories: usize,
                categories: *const $crate::ffi::fmi2String
            ) -> $crate::ffi::fmi2Status
                => $crate::abi::set_debug_logging::<$model>(c, loggingOn, nCategories, categories);
            fmi2Instantiate(
                instanceName: $crate::ffi::fmi2String,
                fmuType: $crate::ffi::fmi2Type,
                fmuGUID: $crate::ffi::fmi2String,
                fmuResourceLocation: $crate::ffi::fmi2String,
                functions: *const $crate::ffi::fmi2CallbackFunctions,
                visible: $crate::ffi::fmi2Boolean,
                loggingOn: $crate::ffi::fmi2Boolean
            ) -> $crate::ffi::fmi2Component
                => $crate::abi::instantiate_as::<$model>(
                    instanceName, fmuType, fmuGUID, fmuResourceLocation, functions, visible,
                    loggingOn, $model_exchange,
                );
            fmi2FreeInstance(c: $crate::ffi::fmi2Component) -> ()
                => $crate::abi::free_instance::<$model>(c);
            fmi2SetupExperiment(
                c: $crate::ffi::fmi2Component,
                toleranceDefined: $crate::ffi::fmi2Boolean,
                tolerance: $crate::ffi::fmi2Real,
                startTime: $crate::ffi::fmi2Real,
                stopTimeDefined: $crate::ffi::fmi2Boolean,
                stopTime: $crate::ffi::fmi2Real
            ) -> $crate::ffi::fmi2Status
                => $crate::abi::setup_experiment::<$model>(
                    c, toleranceDefined, tolerance, startTime, stopTimeDefined, stopTime,
                );
            fmi2EnterInitializationMode(c: $crate::ffi::fmi2Component) -> $crate::ffi::fmi2Status
                => $crate::abi::enter_initialization_mode::<$model>(c);
            fmi2GetReal(
                c: $crate::ffi::fmi2Component,
                vr: *const $crate::ffi::fmi2ValueReference,
                nvr: usize,
                value: *mut $crate::ffi::fmi2Real
            ) -> $crate::ffi::fmi2Status
                => $crate::abi::get_real::<$model>(c, vr, nvr, value);
            fmi2GetInteger(
                c: $crate::ffi::fmi2Component,
                vr: *const $crate::ffi::fmi2ValueReference,
                nvr: usize,
                value: *mut $crate::ffi::fmi2Integer
            ) -> $crate::ffi::fmi2Status
                => $crate::abi::get_integer::<$model>(c, vr, nvr, value);
            fmi2GetBoolean(
                c: $crate::ffi::fmi2Component,
                vr: *const $crate::ffi::fmi2ValueReference,
                nvr: usize,
                value: *mut $crate::ffi::fmi2Boolean
            ) -> $crate::ffi::fmi2Status
                => $crate::abi::get_boolean::<$model>(c, vr, nvr, value);
            fmi2GetString(
                c: $crate::ffi::fmi2Component,
                vr: *const $crate::ffi::fmi2ValueReference,
                nvr: usize,
                value: *mut $crate::ffi::fmi2String
            ) -> $crate::ffi::fmi2Status
                => $crate::abi::get_string::<$model>(c, vr, nvr, value);
            fmi2SetReal(
                c: $crate::ffi::fmi2Component,
                vr: *const $crate::ffi::fmi2ValueReference,
                nvr: usize,
                value: *const $crate::ffi::fmi2Real
            ) -> $crate::ffi::fmi2Status
                => $crate::abi::set_real::<$model>(c, vr, nvr, value);
            fmi2SetInteger(
                c: $crate::ffi::fmi2Component,
                vr: *const $crate::ffi::fmi2ValueReference,
                nvr: usize,
                value: *const $crate::ffi::fmi2Integer
            ) -> $crate::ffi::fmi2Status
                => $crate::abi::set_integer::<$model>(c, vr, nvr, value);
            fmi2SetBoolean(
                c: $crate::ffi::fmi2Component,
                vr: *const $crate::ffi::fmi2ValueReference,
                nvr: usize,
                value: *const $crate::ffi::fmi2Boolean
            ) -> $crate::ffi::fmi2Status
                => $crate::abi::set_boolean::<$model>(c, vr, nvr, value);
            fmi2SetString(
                c: $crate::ffi::fmi2Component,
                vr: *const $crate::ffi::fmi2ValueReference,
                nvr: usize,
                value: *const $crate::ffi::fmi2String
            ) -> $crate::ffi::fmi2Status
                => $crate::abi::set_string::<$model>(c, vr, nvr, value);
            fmi2GetDirectionalDerivative(
                c: $crate::ffi::fmi2Component,
                vUnknown_ref: *const $crate::ffi::fmi2ValueReference,
                nUnknown: usize,
                vKnown_ref: *const $crate::ffi::fmi2ValueReference,
                nKnown: usize,
                dvKnown: *const $crate::ffi::fmi2Real,
                dvUnknown: *mut $crate::ffi::fmi2Real
            ) -> $crate::ffi::fmi2Status
                => $crate::abi::get_directional_derivative::<$model>(
                    c, vUnknown_ref, nUnknown, vKnown_ref, nKnown, dvKnown, dvUnknown, $states,
                );
            fmi2SetRealInputDerivatives(
                c: $crate::ffi::fmi2Component,
                vr: *const $crate::ffi::fmi2ValueReference,
                nvr: usize,
                order: *const $crate::ffi::fmi2Integer,
                value: *const $crate::ffi::fmi2Real
            ) -> $crate::ffi::fmi2Status
                => $crate::abi::set_real_input_derivatives::<$model>(c, vr, nvr, order, value);
            fmi2GetRealOutputDerivatives(
                c: $crate::ffi::fmi2Component,
                vr: *const $crate::ffi::fmi2ValueReference,
                nvr: usize,
                order: *const $crate::ffi::fmi2Integer,
                value: *mut $crate::ffi::fmi2Real
            ) -> $crate::ffi::fmi2Status
                => $crate::abi::get_real_output_derivatives::<$model>(c, vr, nvr, order, value);
            fmi2DoStep(
                c: $crate::ffi::fmi2Component,
                currentCommunicationPoint: $crate::ffi::fmi2Real,
                communicationStepSize: $crate::ffi::fmi2Real,
                noSetFMUStatePriorToCurrentPoint: $crate::ffi::fmi2Boolean
            ) -> $crate::ffi::fmi2Status
                => $crate::abi::do_step::<$model>(
                    c, currentCommunicationPoint, communicationStepSize,
                    noSetFMUStatePriorToCurrentPoint,
                );
            fmi2CancelStep(c: $crate::ffi::fmi2Component) -> $crate::ffi::fmi2Status
                => $crate::abi::cancel_step::<$model>(c);
            fmi2GetStatus(
                c: $crate::ffi::fmi2Component,
                s: $crate::ffi::fmi2StatusKind,
                value: *mut $crate::ffi::fmi2Status
            ) -> $crate::ffi::fmi2Status
                => $crate::abi::get_status::<$model>(c, s, value);
            fmi2GetRealStatus(
                c: $crate::ffi::fmi2Component,
                s: $crate::ffi::fmi2StatusKind,
                value: *mut $crate::ffi::fmi2Real
            ) -> $crate::ffi::fmi2Status
                => $crate::abi::get_real_status::<$model>(c, s, value);
            fmi2GetIntegerStatus(
                c: $crate::ffi::fmi2Component,
                s: $crate::ffi::fmi2StatusKind,
                value: *mut $crate::ffi::fmi2Integer
            ) -> $crate::ffi::fmi2Status
                => $crate::abi::get_integer_status::<$model>(c, s, value);
            fmi2GetBooleanStatus(
                c: $crate::ffi::fmi2Component,
                s: $crate::ffi::fmi2StatusKind,
                value: *mut $crate::ffi::fmi2Boolean
            ) -> $crate::ffi::fmi2Status
                => $crate::abi::get_boolean_status::<$model>(c, s, value);
            fmi2GetStringStatus(
                c: $crate::ffi::fmi2Component,
                s: $crate::ffi::fmi2StatusKind,
                value: *mut $crate::ffi::fmi2String
            ) -> $crate::ffi::fmi2Status
                => $crate::abi::get_string_status::<$model>(c, s, value);
        }
    };
}
