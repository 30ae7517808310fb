//! The FMI 2.0 backend of [`super::Instance`]: one Co-Simulation slave or Model Exchange
//! model driven through its C ABI. Every FMI status comes back as a `Result`, and a failure carries what the FMU logged
//! during the failing call.
#![allow(unsafe_code)]

use super::error::{CallError, FmiError};
use super::ffi::{self, fmi2Component, fmi2FMUstate, fmi2Status};
use super::loaded::FmuShared;
use super::logger::{LogEnv, LogMark};
use super::state::FmuState;
use super::status::{Failure, Status, StepStatus, Success};
use crate::binary::Fmi2Functions;
use crate::model_exchange::{EventUpdate, Interface, MeVector, StepEnd};
use crate::tables::fmi2::{Fmi2CoSimulation, Fmi2ModelExchange};
use crate::version::FmiVersion;
use std::ffi::{c_void, CStr, CString};
use std::ptr::{self, NonNull};
use std::sync::Arc;

/// A Co-Simulation slave. `fmi2FreeInstance` is called on drop.
pub(crate) struct Fmi2Instance {
    component: NonNull<c_void>,
    name: String,
    /// The number its calls are noted by in the black box.
    pub(crate) black_box: u32,
    fmu: Arc<FmuShared>,
    functions: Fmi2Functions,
    interface: Interface,
    /// Also the instance's identity for [`FmuState`] tokens.
    log: Arc<LogEnv>,
    /// FMUs written against FMI 2.0 may keep this pointer instead of copying the struct,
    /// and likewise the strings; all live until after `fmi2FreeInstance`.
    _callbacks: Box<ffi::fmi2CallbackFunctions>,
    _instantiate_strings: [CString; 3],
    /// Live FMU states by slot; a freed slot is null and reused.
    states: Vec<fmi2FMUstate>,
    /// Reused by every Boolean and String call, so a master's exchange does not allocate
    /// per call once these have grown to its widest exchange.
    booleans: Vec<ffi::fmi2Boolean>,
    strings: Vec<ffi::fmi2String>,
}

// SAFETY: the component and FMU-state pointers are used only through `&mut self` (or in
// `drop`), so calls into one instance are serialised. FMI 2.0 does not bind an instance to the
// thread that created it, and the callbacks we pass are thread-safe (`LogEnv` locks).
unsafe impl Send for Fmi2Instance {}

impl std::fmt::Debug for Fmi2Instance {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Fmi2Instance")
            .field("name", &self.name)
            .field("model_name", &self.fmu.description.model_name)
            .finish_non_exhaustive()
    }
}

impl Fmi2Instance {
    pub(crate) fn new(
        fmu: Arc<FmuShared>,
        functions: Fmi2Functions,
        name: &str,
        logging_on: bool,
        interface: Interface,
    ) -> Result<Self, CallError> {
        let c_string = |what: &str, text: &str| {
            CString::new(text).map_err(|_| CallError::InvalidArgument {
                function: "fmi2Instantiate",
                instance: name.to_owned(),
                reason: format!("{what} contains a NUL byte"),
            })
        };
        let instance_name = c_string("instance name", name)?;
        let guid = c_string("GUID", &fmu.description.guid)?;
        let resource_uri = c_string("resource location", &fmu.files.resource_uri)?;

        let log = Arc::new(LogEnv::new());
        let callbacks = Box::new(log.callbacks());
        let mark = log.mark();
        let black_box = crate::blackbox::register(name);
        let call = crate::blackbox::enter(
            black_box,
            const { crate::blackbox::function("fmi2Instantiate") },
        );
        // SAFETY: every pointer is valid for the call, and `log`, `callbacks` and the strings
        // are moved into the instance, which outlives the component.
        let component = unsafe {
            (functions.instantiate)(
                instance_name.as_ptr(),
                match interface {
                    Interface::CoSimulation => ffi::fmi2CoSimulation,
                    Interface::ModelExchange => ffi::fmi2ModelExchange,
                },
                guid.as_ptr(),
                resource_uri.as_ptr(),
                &*callbacks,
                ffi::fmi2False,
                fmi2_bool(logging_on),
            )
        };
        drop(call);
        let Some(component) = NonNull::new(component) else {
            return Err(CallError::InstantiationFailed {
                function: "fmi2Instantiate",
                instance: name.to_owned(),
                log: log.since(mark),
            });
        };
        Ok(Self {
            component,
            name: name.to_owned(),
            black_box,
            fmu,
            functions,
            interface,
            log,
            _callbacks: callbacks,
            _instantiate_strings: [instance_name, guid, resource_uri],
            states: Vec::new(),
            booleans: Vec::new(),
            strings: Vec::new(),
        })
    }

    pub(crate) fn name(&self) -> &str {
        &self.name
    }

    pub(crate) fn log(&self) -> &Arc<LogEnv> {
        &self.log
    }

    fn c(&self) -> fmi2Component {
        self.component.as_ptr()
    }

    fn functions(&self) -> &Fmi2Functions {
        &self.functions
    }

    /// The table of the interface this instance was made for; a call of the other interface's
    /// functions is refused here rather than passed to an FMU that may not export them.
    fn co_simulation(&self, function: &'static str) -> Result<Fmi2CoSimulation, FmiError> {
        match (self.interface, self.functions.co_simulation) {
            (Interface::CoSimulation, Some(table)) => Ok(table),
            _ => Err(self.wrong_interface(function, "Co-Simulation")),
        }
    }

    fn model_exchange(&self, function: &'static str) -> Result<Fmi2ModelExchange, FmiError> {
        match (self.interface, self.functions.model_exchange) {
            (Interface::ModelExchange, Some(table)) => Ok(table),
            _ => Err(self.wrong_interface(function, "Model Exchange")),
        }
    }

    fn wrong_interface(&self, function: &'static str, wanted: &str) -> FmiError {
        FmiError::from_importer(
            function,
            &self.name,
            FmiVersion::Fmi2,
            format!(
                "{function} is a {wanted} function and this instance was made for {:?}",
                self.interface
            ),
        )
    }

    /// Turns a returned status into a `Result`, attaching the messages logged since `mark`.
    fn check(
        &self,
        function: &'static str,
        mark: LogMark,
        raw: fmi2Status,
    ) -> Result<Success, FmiError> {
        Status::from_raw(raw)
            .into_result()
            .map_err(|status| FmiError {
                function,
                instance: self.name.clone(),
                status,
                log: self.log.since(mark),
            })
    }

    fn invalid(&self, function: &'static str, reason: String) -> CallError {
        CallError::InvalidArgument {
            function,
            instance: self.name.clone(),
            reason,
        }
    }

    fn check_lengths(
        &self,
        function: &'static str,
        vrs: usize,
        values: usize,
    ) -> Result<(), CallError> {
        if vrs == values {
            Ok(())
        } else {
            Err(self.invalid(
                function,
                format!("{vrs} value references but {values} values"),
            ))
        }
    }

    /// `fmi2SetDebugLogging`; an empty `categories` means all categories.
    pub(crate) fn set_debug_logging(
        &mut self,
        logging_on: bool,
        categories: &[&str],
    ) -> Result<Success, CallError> {
        const F: &str = "fmi2SetDebugLogging";
        let owned = categories
            .iter()
            .map(|category| {
                CString::new(*category).map_err(|_| {
                    self.invalid(F, format!("category {category:?} contains a NUL byte"))
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        let pointers: Vec<ffi::fmi2String> = owned.iter().map(|c| c.as_ptr()).collect();
        let mark = self.log.mark();
        // SAFETY: `pointers` holds `len` valid C strings for the duration of the call.
        let raw = unsafe {
            (self.functions().set_debug_logging)(
                self.c(),
                fmi2_bool(logging_on),
                pointers.len(),
                array_or_null(&pointers),
            )
        };
        Ok(self.check(F, mark, raw)?)
    }

    /// `fmi2SetupExperiment`. `None` leaves the tolerance or stop time undefined.
    pub(crate) fn setup_experiment(
        &mut self,
        tolerance: Option<f64>,
        start_time: f64,
        stop_time: Option<f64>,
    ) -> Result<Success, FmiError> {
        let mark = self.log.mark();
        // SAFETY: plain values only.
        let raw = unsafe {
            (self.functions().setup_experiment)(
                self.c(),
                fmi2_bool(tolerance.is_some()),
                tolerance.unwrap_or(0.0),
                start_time,
                fmi2_bool(stop_time.is_some()),
                stop_time.unwrap_or(0.0),
            )
        };
        self.check("fmi2SetupExperiment", mark, raw)
    }

    fn component_only(
        &mut self,
        function: &'static str,
        call: ffi::fmi2ComponentOnlyTYPE,
    ) -> Result<Success, FmiError> {
        let mark = self.log.mark();
        // SAFETY: the component is live; the function takes nothing else.
        let raw = unsafe { call(self.c()) };
        self.check(function, mark, raw)
    }

    pub(crate) fn enter_initialization_mode(&mut self) -> Result<Success, FmiError> {
        let call = self.functions().enter_initialization_mode;
        self.component_only("fmi2EnterInitializationMode", call)
    }

    pub(crate) fn exit_initialization_mode(&mut self) -> Result<Success, FmiError> {
        let call = self.functions().exit_initialization_mode;
        self.component_only("fmi2ExitInitializationMode", call)
    }

    pub(crate) fn terminate(&mut self) -> Result<Success, FmiError> {
        let call = self.functions().terminate;
        self.component_only("fmi2Terminate", call)
    }

    /// `fmi2Reset`: back to the freshly instantiated state. Saved FMU states stay valid.
    pub(crate) fn reset(&mut self) -> Result<Success, FmiError> {
        let call = self.functions().reset;
        self.component_only("fmi2Reset", call)
    }

    /// `fmi2DoStep` from `current_time` over `step_size`.
    ///
    /// `noSetFMUStatePriorToCurrentPoint` is passed as false because this API lets the caller
    /// restore any saved state at any time.
    pub(crate) fn do_step(
        &mut self,
        current_time: f64,
        step_size: f64,
    ) -> Result<StepStatus, FmiError> {
        const F: &str = "fmi2DoStep";
        let do_step = self.co_simulation(F)?.do_step;
        let mark = self.log.mark();
        // SAFETY: plain values only.
        let raw = unsafe { (do_step)(self.c(), current_time, step_size, ffi::fmi2False) };
        match Status::from_raw(raw).into_result() {
            Ok(success) => Ok(StepStatus::Complete(success)),
            Err(Failure::Discard) => Ok(StepStatus::Discarded {
                last_successful_time: self.last_successful_time()?,
                terminated: self.terminated()?,
            }),
            Err(status) => Err(FmiError {
                function: F,
                instance: self.name.clone(),
                status,
                log: self.log.since(mark),
            }),
        }
    }

    /// `fmi2GetRealStatus(fmi2LastSuccessfulTime)`.
    pub(crate) fn last_successful_time(&mut self) -> Result<f64, FmiError> {
        let mut time = f64::NAN;
        let get_real_status = self.co_simulation("fmi2GetRealStatus")?.get_real_status;
        let mark = self.log.mark();
        // SAFETY: `time` is a valid out-pointer.
        let raw = unsafe { (get_real_status)(self.c(), ffi::fmi2LastSuccessfulTime, &mut time) };
        self.check("fmi2GetRealStatus(fmi2LastSuccessfulTime)", mark, raw)?;
        Ok(time)
    }

    /// `fmi2GetBooleanStatus(fmi2Terminated)`: the FMU wants the simulation to end.
    pub(crate) fn terminated(&mut self) -> Result<bool, FmiError> {
        let mut terminated = ffi::fmi2False;
        let get_boolean_status = self
            .co_simulation("fmi2GetBooleanStatus")?
            .get_boolean_status;
        let mark = self.log.mark();
        // SAFETY: `terminated` is a valid out-pointer.
        let raw = unsafe { (get_boolean_status)(self.c(), ffi::fmi2Terminated, &mut terminated) };
        self.check("fmi2GetBooleanStatus(fmi2Terminated)", mark, raw)?;
        Ok(terminated != ffi::fmi2False)
    }

    // ---- Model Exchange (FMI 2.0, 3.2) ----

    pub(crate) fn set_time(&mut self, time: f64) -> Result<Success, FmiError> {
        const F: &str = "fmi2SetTime";
        let set_time = self.model_exchange(F)?.set_time;
        let mark = self.log.mark();
        // SAFETY: plain values only.
        let raw = unsafe { set_time(self.c(), time) };
        self.check(F, mark, raw)
    }

    pub(crate) fn set_continuous_states(&mut self, x: &[f64]) -> Result<Success, FmiError> {
        const F: &str = "fmi2SetContinuousStates";
        let set = self.model_exchange(F)?.set_continuous_states;
        let mark = self.log.mark();
        // SAFETY: `x` is valid for `x.len()` reads.
        let raw = unsafe { set(self.c(), x.as_ptr(), x.len()) };
        self.check(F, mark, raw)
    }

    /// One of the vector reads: states, derivatives, event indicators, nominals.
    pub(crate) fn get_vector(
        &mut self,
        which: MeVector,
        values: &mut [f64],
    ) -> Result<Success, FmiError> {
        let (function, table) = match which {
            MeVector::States => (
                "fmi2GetContinuousStates",
                self.model_exchange("fmi2GetContinuousStates")?
                    .get_continuous_states,
            ),
            MeVector::Derivatives => (
                "fmi2GetDerivatives",
                self.model_exchange("fmi2GetDerivatives")?.get_derivatives,
            ),
            MeVector::EventIndicators => (
                "fmi2GetEventIndicators",
                self.model_exchange("fmi2GetEventIndicators")?
                    .get_event_indicators,
            ),
            MeVector::Nominals => (
                "fmi2GetNominalsOfContinuousStates",
                self.model_exchange("fmi2GetNominalsOfContinuousStates")?
                    .get_nominals_of_continuous_states,
            ),
        };
        let mark = self.log.mark();
        // SAFETY: `values` is valid for `values.len()` writes.
        let raw = unsafe { table(self.c(), values.as_mut_ptr(), values.len()) };
        self.check(function, mark, raw)
    }

    pub(crate) fn enter_event_mode_me(&mut self) -> Result<Success, FmiError> {
        const F: &str = "fmi2EnterEventMode";
        let call = self.model_exchange(F)?.enter_event_mode;
        self.component_only(F, call)
    }

    pub(crate) fn enter_continuous_time_mode(&mut self) -> Result<Success, FmiError> {
        const F: &str = "fmi2EnterContinuousTimeMode";
        let call = self.model_exchange(F)?.enter_continuous_time_mode;
        self.component_only(F, call)
    }

    /// One `fmi2NewDiscreteStates` of the event iteration.
    pub(crate) fn update_discrete_states(&mut self) -> Result<EventUpdate, FmiError> {
        const F: &str = "fmi2NewDiscreteStates";
        let call = self.model_exchange(F)?.new_discrete_states;
        let mut info = ffi::fmi2EventInfo {
            newDiscreteStatesNeeded: ffi::fmi2False,
            terminateSimulation: ffi::fmi2False,
            nominalsOfContinuousStatesChanged: ffi::fmi2False,
            valuesOfContinuousStatesChanged: ffi::fmi2False,
            nextEventTimeDefined: ffi::fmi2False,
            nextEventTime: 0.0,
        };
        let mark = self.log.mark();
        // SAFETY: `info` is a valid out-pointer.
        let raw = unsafe { call(self.c(), &mut info) };
        self.check(F, mark, raw)?;
        Ok(EventUpdate {
            discrete_states_need_update: info.newDiscreteStatesNeeded != ffi::fmi2False,
            terminate_simulation: info.terminateSimulation != ffi::fmi2False,
            nominals_changed: info.nominalsOfContinuousStatesChanged != ffi::fmi2False,
            states_changed: info.valuesOfContinuousStatesChanged != ffi::fmi2False,
            next_event_time: (info.nextEventTimeDefined != ffi::fmi2False)
                .then_some(info.nextEventTime),
        })
    }

    /// `fmi2CompletedIntegratorStep` with `noSetFMUStatePriorToCurrentPoint = false`.
    pub(crate) fn completed_integrator_step(&mut self) -> Result<StepEnd, FmiError> {
        const F: &str = "fmi2CompletedIntegratorStep";
        let call = self.model_exchange(F)?.completed_integrator_step;
        let (mut enter_event_mode, mut terminate) = (ffi::fmi2False, ffi::fmi2False);
        let mark = self.log.mark();
        // SAFETY: both are valid out-pointers.
        let raw = unsafe {
            call(
                self.c(),
                ffi::fmi2False,
                &mut enter_event_mode,
                &mut terminate,
            )
        };
        self.check(F, mark, raw)?;
        Ok(StepEnd {
            enter_event_mode: enter_event_mode != ffi::fmi2False,
            terminate_simulation: terminate != ffi::fmi2False,
        })
    }

    // ---- values by value reference ----

    /// One `fmi2Set*` call, the values passed as they are.
    fn set_values<T>(
        &mut self,
        function: &'static str,
        set: unsafe extern "C" fn(fmi2Component, *const u32, usize, *const T) -> fmi2Status,
        vrs: &[u32],
        values: &[T],
    ) -> Result<Success, CallError> {
        self.check_lengths(function, vrs.len(), values.len())?;
        let mark = self.log.mark();
        // SAFETY: both arrays hold `vrs.len()` elements.
        let raw = unsafe {
            set(
                self.c(),
                array_or_null(vrs),
                vrs.len(),
                array_or_null(values),
            )
        };
        Ok(self.check(function, mark, raw)?)
    }

    /// One `fmi2Get*` call into `values` as they are.
    fn get_values<T>(
        &mut self,
        function: &'static str,
        get: unsafe extern "C" fn(fmi2Component, *const u32, usize, *mut T) -> fmi2Status,
        vrs: &[u32],
        values: &mut [T],
    ) -> Result<Success, CallError> {
        self.check_lengths(function, vrs.len(), values.len())?;
        let mark = self.log.mark();
        // SAFETY: both arrays hold `vrs.len()` elements; `values` is writable.
        let raw = unsafe {
            get(
                self.c(),
                array_or_null(vrs),
                vrs.len(),
                mut_array_or_null(values),
            )
        };
        Ok(self.check(function, mark, raw)?)
    }

    /// `fmi2GetDirectionalDerivative`: `sensitivity = J seed`, `J` the partials of
    /// `unknowns` with respect to `knowns`.
    pub(crate) fn directional_derivative(
        &mut self,
        unknowns: &[u32],
        knowns: &[u32],
        seed: &[f64],
        sensitivity: &mut [f64],
    ) -> Result<Success, CallError> {
        const F: &str = "fmi2GetDirectionalDerivative";
        self.check_lengths(F, knowns.len(), seed.len())?;
        self.check_lengths(F, unknowns.len(), sensitivity.len())?;
        let get = self.functions().get_directional_derivative;
        let mark = self.log.mark();
        // SAFETY: `unknowns` and `sensitivity`, `knowns` and `seed` hold as many elements as
        // passed; `sensitivity` is writable.
        let raw = unsafe {
            get(
                self.c(),
                array_or_null(unknowns),
                unknowns.len(),
                array_or_null(knowns),
                knowns.len(),
                array_or_null(seed),
                mut_array_or_null(sensitivity),
            )
        };
        Ok(self.check(F, mark, raw)?)
    }

    pub(crate) fn set_real(&mut self, vrs: &[u32], values: &[f64]) -> Result<Success, CallError> {
        let set = self.functions().set_real;
        self.set_values("fmi2SetReal", set, vrs, values)
    }

    pub(crate) fn get_real(
        &mut self,
        vrs: &[u32],
        values: &mut [f64],
    ) -> Result<Success, CallError> {
        let get = self.functions().get_real;
        self.get_values("fmi2GetReal", get, vrs, values)
    }

    /// Also sets Enumeration variables.
    pub(crate) fn set_integer(
        &mut self,
        vrs: &[u32],
        values: &[i32],
    ) -> Result<Success, CallError> {
        let set = self.functions().set_integer;
        self.set_values("fmi2SetInteger", set, vrs, values)
    }

    /// Also gets Enumeration variables.
    pub(crate) fn get_integer(
        &mut self,
        vrs: &[u32],
        values: &mut [i32],
    ) -> Result<Success, CallError> {
        let get = self.functions().get_integer;
        self.get_values("fmi2GetInteger", get, vrs, values)
    }

    pub(crate) fn set_boolean(
        &mut self,
        vrs: &[u32],
        values: &[bool],
    ) -> Result<Success, CallError> {
        const F: &str = "fmi2SetBoolean";
        self.check_lengths(F, vrs.len(), values.len())?;
        let mut raw_values = std::mem::take(&mut self.booleans);
        raw_values.clear();
        raw_values.extend(values.iter().map(|&value| fmi2_bool(value)));
        let mark = self.log.mark();
        // SAFETY: both arrays hold `vrs.len()` elements.
        let raw = unsafe {
            (self.functions().set_boolean)(
                self.c(),
                array_or_null(vrs),
                vrs.len(),
                array_or_null(&raw_values),
            )
        };
        self.booleans = raw_values;
        Ok(self.check(F, mark, raw)?)
    }

    pub(crate) fn get_boolean(
        &mut self,
        vrs: &[u32],
        values: &mut [bool],
    ) -> Result<Success, CallError> {
        const F: &str = "fmi2GetBoolean";
        self.check_lengths(F, vrs.len(), values.len())?;
        let mut raw_values = std::mem::take(&mut self.booleans);
        raw_values.clear();
        raw_values.resize(vrs.len(), ffi::fmi2False);
        let mark = self.log.mark();
        // SAFETY: both arrays hold `vrs.len()` elements; `raw_values` is writable.
        let raw = unsafe {
            (self.functions().get_boolean)(
                self.c(),
                array_or_null(vrs),
                vrs.len(),
                mut_array_or_null(&mut raw_values),
            )
        };
        for (value, &raw_value) in values.iter_mut().zip(&raw_values) {
            *value = raw_value != ffi::fmi2False;
        }
        self.booleans = raw_values;
        let success = self.check(F, mark, raw)?;
        Ok(success)
    }

    /// `fmi2SetBoolean` with the values as `fmi2Boolean` (C `int`, 0 is false), as a master
    /// that keeps its exchange in the FMI representation passes them: no conversion, no copy.
    pub(crate) fn set_boolean_raw(
        &mut self,
        vrs: &[u32],
        values: &[i32],
    ) -> Result<Success, CallError> {
        let set = self.functions().set_boolean;
        self.set_values("fmi2SetBoolean", set, vrs, values)
    }

    /// `fmi2GetBoolean` into `fmi2Boolean` values, each normalised to 0 or 1 (an FMU may
    /// return any non-zero value for true), so they pass on and record as [`Self::get_boolean`]'s.
    pub(crate) fn get_boolean_raw(
        &mut self,
        vrs: &[u32],
        values: &mut [i32],
    ) -> Result<Success, CallError> {
        let get = self.functions().get_boolean;
        let success = self.get_values("fmi2GetBoolean", get, vrs, values);
        for value in values.iter_mut() {
            *value = i32::from(*value != ffi::fmi2False);
        }
        success
    }

    pub(crate) fn set_string(
        &mut self,
        vrs: &[u32],
        values: &[&str],
    ) -> Result<Success, CallError> {
        const F: &str = "fmi2SetString";
        self.check_lengths(F, vrs.len(), values.len())?;
        let owned = values
            .iter()
            .map(|value| {
                CString::new(*value)
                    .map_err(|_| self.invalid(F, format!("value {value:?} contains a NUL byte")))
            })
            .collect::<Result<Vec<_>, _>>()?;
        let pointers: Vec<ffi::fmi2String> = owned.iter().map(|c| c.as_ptr()).collect();
        let mark = self.log.mark();
        // SAFETY: both arrays hold `vrs.len()` elements, the strings outlive the call.
        let raw = unsafe {
            (self.functions().set_string)(
                self.c(),
                array_or_null(vrs),
                vrs.len(),
                array_or_null(&pointers),
            )
        };
        Ok(self.check(F, mark, raw)?)
    }

    /// `fmi2GetString` into existing strings, which keep their capacity: a master
    /// that reads the same strings every step allocates only when one grows.
    pub(crate) fn get_string_into(
        &mut self,
        vrs: &[u32],
        values: &mut [String],
    ) -> Result<Success, CallError> {
        const F: &str = "fmi2GetString";
        self.check_lengths(F, vrs.len(), values.len())?;
        let mut pointers = std::mem::take(&mut self.strings);
        pointers.clear();
        pointers.resize(vrs.len(), ptr::null());
        let mark = self.log.mark();
        // SAFETY: both arrays hold `vrs.len()` elements; `pointers` is writable.
        let raw = unsafe {
            (self.functions().get_string)(
                self.c(),
                array_or_null(vrs),
                vrs.len(),
                mut_array_or_null(&mut pointers),
            )
        };
        let copied = self
            .check(F, mark, raw)
            .map_err(CallError::from)
            .and_then(|success| {
                for ((value, &pointer), vr) in values.iter_mut().zip(&pointers).zip(vrs) {
                    if pointer.is_null() {
                        return Err(self.invalid(
                            F,
                            format!("the FMU returned NULL for value reference {vr}"),
                        ));
                    }
                    // SAFETY: a non-null fmi2String returned by the FMU is NUL-terminated and
                    // valid until the next call into the instance.
                    let text = unsafe { CStr::from_ptr(pointer) }.to_string_lossy();
                    value.clear();
                    value.push_str(&text);
                }
                Ok(success)
            });
        // The FMU's pointers die with its next call: none is kept.
        pointers.iter_mut().for_each(|p| *p = ptr::null());
        self.strings = pointers;
        copied
    }

    // ---- FMU state ----

    fn owned_state(
        &self,
        function: &'static str,
        state: &FmuState,
    ) -> Result<fmi2FMUstate, CallError> {
        let pointer = if ptr::eq(state.owner.as_ptr(), Arc::as_ptr(&self.log)) {
            self.states
                .get(state.slot)
                .copied()
                .unwrap_or(ptr::null_mut())
        } else {
            ptr::null_mut()
        };
        if pointer.is_null() {
            return Err(self.invalid(
                function,
                "the FMU state belongs to another instance".to_owned(),
            ));
        }
        Ok(pointer)
    }

    fn store_state(&mut self, pointer: fmi2FMUstate) -> FmuState {
        let slot = match self.states.iter().position(|state| state.is_null()) {
            Some(free) => {
                self.states[free] = pointer;
                free
            }
            None => {
                self.states.push(pointer);
                self.states.len() - 1
            }
        };
        FmuState {
            slot,
            owner: Arc::downgrade(&self.log),
        }
    }

    /// `fmi2GetFMUstate` into a new state.
    pub(crate) fn get_fmu_state(&mut self) -> Result<FmuState, FmiError> {
        let mut pointer: fmi2FMUstate = ptr::null_mut();
        let mark = self.log.mark();
        // SAFETY: a null state asks the FMU to allocate a new one.
        let raw = unsafe { (self.functions().get_fmu_state)(self.c(), &mut pointer) };
        self.check("fmi2GetFMUstate", mark, raw)?;
        Ok(self.store_state(pointer))
    }

    /// `fmi2GetFMUstate` overwriting an existing state, without a new allocation.
    pub(crate) fn update_fmu_state(&mut self, state: &FmuState) -> Result<Success, CallError> {
        const F: &str = "fmi2GetFMUstate";
        let mut pointer = self.owned_state(F, state)?;
        let mark = self.log.mark();
        // SAFETY: `pointer` is a live state of this instance.
        let raw = unsafe { (self.functions().get_fmu_state)(self.c(), &mut pointer) };
        // The FMU may hand back a different pointer even on failure; keep whatever it returned.
        self.states[state.slot] = pointer;
        Ok(self.check(F, mark, raw)?)
    }

    /// `fmi2SetFMUstate`: continue from a saved state.
    pub(crate) fn set_fmu_state(&mut self, state: &FmuState) -> Result<Success, CallError> {
        const F: &str = "fmi2SetFMUstate";
        let pointer = self.owned_state(F, state)?;
        let mark = self.log.mark();
        // SAFETY: `pointer` is a live state of this instance.
        let raw = unsafe { (self.functions().set_fmu_state)(self.c(), pointer) };
        Ok(self.check(F, mark, raw)?)
    }

    /// `fmi2FreeFMUstate`.
    pub(crate) fn free_fmu_state(&mut self, state: FmuState) -> Result<Success, CallError> {
        const F: &str = "fmi2FreeFMUstate";
        let mut pointer = self.owned_state(F, &state)?;
        self.states[state.slot] = ptr::null_mut();
        let mark = self.log.mark();
        // SAFETY: `pointer` is a live state of this instance, freed exactly once (its slot is cleared).
        let raw = unsafe { (self.functions().free_fmu_state)(self.c(), &mut pointer) };
        Ok(self.check(F, mark, raw)?)
    }

    /// `fmi2SerializedFMUstateSize` + `fmi2SerializeFMUstate`.
    pub(crate) fn serialize_fmu_state(&mut self, state: &FmuState) -> Result<Vec<u8>, CallError> {
        let pointer = self.owned_state("fmi2SerializeFMUstate", state)?;
        let mut size = 0usize;
        let mark = self.log.mark();
        // SAFETY: `pointer` is a live state of this instance; `size` is a valid out-pointer.
        let raw =
            unsafe { (self.functions().serialized_fmu_state_size)(self.c(), pointer, &mut size) };
        self.check("fmi2SerializedFMUstateSize", mark, raw)?;
        let mut bytes = vec![0u8; size];
        let mark = self.log.mark();
        // SAFETY: `bytes` holds exactly the `size` bytes the FMU asked for.
        let raw = unsafe {
            (self.functions().serialize_fmu_state)(
                self.c(),
                pointer,
                bytes.as_mut_ptr().cast(),
                bytes.len(),
            )
        };
        self.check("fmi2SerializeFMUstate", mark, raw)?;
        Ok(bytes)
    }

    /// `fmi2DeSerializeFMUstate` into a new state.
    pub(crate) fn deserialize_fmu_state(&mut self, bytes: &[u8]) -> Result<FmuState, FmiError> {
        let mut pointer: fmi2FMUstate = ptr::null_mut();
        let mark = self.log.mark();
        // SAFETY: `bytes` is readable for its length; a null state asks for a new one.
        let raw = unsafe {
            (self.functions().de_serialize_fmu_state)(
                self.c(),
                bytes.as_ptr().cast(),
                bytes.len(),
                &mut pointer,
            )
        };
        self.check("fmi2DeSerializeFMUstate", mark, raw)?;
        Ok(self.store_state(pointer))
    }
}

impl Drop for Fmi2Instance {
    fn drop(&mut self) {
        let functions = self.functions;
        for pointer in self.states.iter_mut().filter(|state| !state.is_null()) {
            // SAFETY: each non-null slot is a live state of this instance, freed once here. A
            // failure cannot be reported from drop; the FMU has logged it.
            unsafe { (functions.free_fmu_state)(self.component.as_ptr(), pointer) };
        }
        let _call = crate::blackbox::enter(
            self.black_box,
            const { crate::blackbox::function("fmi2FreeInstance") },
        );
        // SAFETY: the component is live and never used again; the callbacks and log sink
        // are dropped only after this returns.
        unsafe { (functions.free_instance)(self.component.as_ptr()) };
    }
}

fn fmi2_bool(value: bool) -> ffi::fmi2Boolean {
    if value {
        ffi::fmi2True
    } else {
        ffi::fmi2False
    }
}

/// The standard allows null arrays only with a zero count; pass null then rather than a
/// dangling (if well-aligned) pointer from an empty slice.
fn array_or_null<T>(slice: &[T]) -> *const T {
    if slice.is_empty() {
        ptr::null()
    } else {
        slice.as_ptr()
    }
}

fn mut_array_or_null<T>(slice: &mut [T]) -> *mut T {
    if slice.is_empty() {
        ptr::null_mut()
    } else {
        slice.as_mut_ptr()
    }
}
