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
    (@export $(
        $name:ident ( $($arg:ident : $ty:ty),* $(,)? ) -> $ret:ty => $body:expr;
    )*) => {
        $(
            #[allow(unsafe_code, non_snake_case, clippy::missing_safety_doc, clippy::unused_unit)]
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn $name($($arg: $ty),*) -> $ret {
                #[allow(unused_unsafe)]
                unsafe {
                    $body
                }
            }
        )*
    };
    ($model:ty) => {
        $crate::export_fmi2! { @co_simulation $model, false }
    };
    // A model that implements `fmi_model::ContinuousModel`: Co-Simulation and Model Exchange.
    ($model:ty, model_exchange) => {
        $crate::export_fmi2! { @co_simulation $model, true }
        $crate::export_fmi2! { @export
            fmi2EnterEventMode(c: $crate::ffi::fmi2Component) -> $crate::ffi::fmi2Status
                => $crate::model_exchange::enter_event_mode::<$model>(c);
            fmi2NewDiscreteStates(
                c: $crate::ffi::fmi2Component,
                fmi2eventInfo: *mut $crate::ffi::fmi2EventInfo
            ) -> $crate::ffi::fmi2Status
                => $crate::model_exchange::new_discrete_states::<$model>(c, fmi2eventInfo);
            fmi2EnterContinuousTimeMode(c: $crate::ffi::fmi2Component) -> $crate::ffi::fmi2Status
                => $crate::model_exchange::enter_continuous_time_mode::<$model>(c);
            fmi2CompletedIntegratorStep(
                c: $crate::ffi::fmi2Component,
                noSetFMUStatePriorToCurrentPoint: $crate::ffi::fmi2Boolean,
                enterEventMode: *mut $crate::ffi::fmi2Boolean,
                terminateSimulation: *mut $crate::ffi::fmi2Boolean
            ) -> $crate::ffi::fmi2Status
                => $crate::model_exchange::completed_integrator_step::<$model>(
                    c, noSetFMUStatePriorToCurrentPoint, enterEventMode, terminateSimulation,
                );
            fmi2SetTime(c: $crate::ffi::fmi2Component, time: $crate::ffi::fmi2Real) -> $crate::ffi::fmi2Status
                => $crate::model_exchange::set_time::<$model>(c, time);
            fmi2SetContinuousStates(
                c: $crate::ffi::fmi2Component,
                x: *const $crate::ffi::fmi2Real,
                nx: usize
            ) -> $crate::ffi::fmi2Status
                => $crate::model_exchange::set_continuous_states::<$model>(c, x, nx);
            fmi2GetDerivatives(
                c: $crate::ffi::fmi2Component,
                derivatives: *mut $crate::ffi::fmi2Real,
                nx: usize
            ) -> $crate::ffi::fmi2Status
                => $crate::model_exchange::get_derivatives::<$model>(c, derivatives, nx);
            fmi2GetEventIndicators(
                c: $crate::ffi::fmi2Component,
                eventIndicators: *mut $crate::ffi::fmi2Real,
                ni: usize
            ) -> $crate::ffi::fmi2Status
                => $crate::model_exchange::get_event_indicators::<$model>(c, eventIndicators, ni);
            fmi2GetContinuousStates(
                c: $crate::ffi::fmi2Component,
                x: *mut $crate::ffi::fmi2Real,
                nx: usize
            ) -> $crate::ffi::fmi2Status
                => $crate::model_exchange::get_continuous_states::<$model>(c, x, nx);
            fmi2GetNominalsOfContinuousStates(
                c: $crate::ffi::fmi2Component,
                x_nominal: *mut $crate::ffi::fmi2Real,
                nx: usize
            ) -> $crate::ffi::fmi2Status
                => $crate::model_exchange::get_nominals_of_continuous_states::<$model>(c, x_nominal, nx);
        }
    };
    (@co_simulation $model:ty, $model_exchange:literal) => {
        $crate::export_fmi2! { @export
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
            fmi2ExitInitializationMode(c: $crate::ffi::fmi2Component) -> $crate::ffi::fmi2Status
                => $crate::abi::exit_initialization_mode::<$model>(c);
            fmi2Terminate(c: $crate::ffi::fmi2Component) -> $crate::ffi::fmi2Status
                => $crate::abi::terminate::<$model>(c);
            fmi2Reset(c: $crate::ffi::fmi2Component) -> $crate::ffi::fmi2Status
                => $crate::abi::reset::<$model>(c);
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
            fmi2GetFMUstate(
                c: $crate::ffi::fmi2Component,
                FMUstate: *mut $crate::ffi::fmi2FMUstate
            ) -> $crate::ffi::fmi2Status
                => $crate::abi::get_fmu_state::<$model>(c, FMUstate);
            fmi2SetFMUstate(
                c: $crate::ffi::fmi2Component,
                FMUstate: $crate::ffi::fmi2FMUstate
            ) -> $crate::ffi::fmi2Status
                => $crate::abi::set_fmu_state::<$model>(c, FMUstate);
            fmi2FreeFMUstate(
                c: $crate::ffi::fmi2Component,
                FMUstate: *mut $crate::ffi::fmi2FMUstate
            ) -> $crate::ffi::fmi2Status
                => $crate::abi::free_fmu_state::<$model>(c, FMUstate);
            fmi2SerializedFMUstateSize(
                c: $crate::ffi::fmi2Component,
                FMUstate: $crate::ffi::fmi2FMUstate,
                size: *mut usize
            ) -> $crate::ffi::fmi2Status
                => $crate::abi::serialized_fmu_state_size::<$model>(c, FMUstate, size);
            fmi2SerializeFMUstate(
                c: $crate::ffi::fmi2Component,
                FMUstate: $crate::ffi::fmi2FMUstate,
                serializedState: *mut $crate::ffi::fmi2Byte,
                size: usize
            ) -> $crate::ffi::fmi2Status
                => $crate::abi::serialize_fmu_state::<$model>(c, FMUstate, serializedState, size);
            fmi2DeSerializeFMUstate(
                c: $crate::ffi::fmi2Component,
                serializedState: *const $crate::ffi::fmi2Byte,
                size: usize,
                FMUstate: *mut $crate::ffi::fmi2FMUstate
            ) -> $crate::ffi::fmi2Status
                => $crate::abi::de_serialize_fmu_state::<$model>(c, serializedState, size, FMUstate);
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
                    c, vUnknown_ref, nUnknown, vKnown_ref, nKnown, dvKnown, dvUnknown,
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
