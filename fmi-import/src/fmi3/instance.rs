//! The FMI 3.0 backend of [`crate::Instance`]: one Co-Simulation or Model Exchange instance,
//! with the state it is in, so that only call orders the standard allows reach the FMU.
//!
//! - Values travel by *element reference* (the scalar view's value reference, see
//!   `view.rs`): a get reads each array it touches whole, in one `fmi3Get{Type}` call per
//!   type, and picks the elements; a set writes each array it touches whole, the elements it
//!   does not name keeping the value last set by the harness (or the start value).
//! - Step Mode: "`fmi3Get{VariableType}` is not allowed after `fmi3Set{VariableType}`
//!   without calling `fmi3DoStep` in between" (FMI 3.0, 4.2.1). Such a get is refused here
//!   before reaching the FMU. An instance made with `same_instant_feedthrough` (and an FMU
//!   with `hasEventMode`) is instantiated with `eventModeUsed = true` and enters Event Mode
//!   (`fmi3EnterEventMode`) at the first set after a step; the next `do_step` leaves it
//!   (`fmi3UpdateDiscreteStates` until nothing needs an update, `fmi3EnterStepMode`) before
//!   `fmi3DoStep`. In Event Mode a get after a set returns the outputs of the inputs just set,
//!   as `fmi2GetReal` after `fmi2SetReal` does.
//! - `earlyReturnAllowed = true`: an FMU that returns early (`earlyReturn`, at
//!   `lastSuccessfulTime`) ends the run there if it asks to terminate, which gives the exact
//!   time of a touchdown; otherwise the importer handles the event (Event Mode, when used)
//!   and completes the communication step from where the FMU stopped, so the master's grid
//!   is kept.
#![allow(unsafe_code)]

mod derivatives;
mod fmu_state;

use super::view::{Element, Starts};
use crate::binary::Fmi3Functions;
use crate::error::{CallError, FmiError};
use crate::loaded::{Fmi3Api, FmuShared};
use crate::logger::{log_message_fmi3, LogEnv, LogMark};
use crate::model_exchange::{EventUpdate, Interface, MeVector, StepEnd};
use crate::status::{Status, StepStatus, Success};
use crate::tables::fmi3::Fmi3ModelExchange;
use fmi_abi::fmi3::{fmi3Instance, fmi3Status, fmi3String};
use model_description::fmi3::Fmi3Type;
use std::ffi::{c_void, CStr, CString};
use std::ptr::{self, NonNull};
use std::sync::Arc;

/// Where the instance is in the FMI 3.0 Co-Simulation state machine (the states the harness
/// uses).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Mode {
    Instantiated,
    Initialization,
    Event,
    Step,
    ContinuousTime,
    Terminated,
}

/// The exchange functions a value reference list goes through.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Group {
    Real,
    Integer,
    Boolean,
    String,
    /// The word types (`crate::word`), each through its own `fmi3Get{Type}`.
    Word,
    Binary,
}

impl Group {
    fn admits(self, kind: Fmi3Type) -> bool {
        match self {
            Group::Real => kind == Fmi3Type::Float64,
            Group::Integer => matches!(kind, Fmi3Type::Int32 | Fmi3Type::Enumeration),
            Group::Boolean => kind == Fmi3Type::Boolean,
            Group::String => kind == Fmi3Type::String,
            Group::Word => crate::word::is_word(kind),
            Group::Binary => kind == Fmi3Type::Binary,
        }
    }

    fn name(self) -> &'static str {
        match self {
            Group::Real => "Float64",
            Group::Integer => "Int32 or Enumeration",
            Group::Boolean => "Boolean",
            Group::String => "String",
            Group::Word => "Float32, Int8, UInt8, Int16, UInt16, UInt32, Int64 or UInt64",
            Group::Binary => "Binary",
        }
    }

    /// The group of the element type `kind`.
    fn of(kind: Fmi3Type) -> Group {
        match kind {
            Fmi3Type::Float64 => Group::Real,
            Fmi3Type::Int32 | Fmi3Type::Enumeration => Group::Integer,
            Fmi3Type::Boolean => Group::Boolean,
            Fmi3Type::Binary => Group::Binary,
            kind if crate::word::is_word(kind) => Group::Word,
            _ => Group::String,
        }
    }
}

/// One `fmi3Get{Type}`/`fmi3Set{Type}` call: whole arrays `vrs` (their elements the scalars
/// `first..first + len` of the view, `total` values in all), and where each requested
/// element sits in the call's values.
#[derive(Debug, Clone)]
struct Call {
    kind: Fmi3Type,
    vrs: Vec<u32>,
    arrays: Vec<(usize, usize)>,
    total: usize,
    /// (position in the caller's values, position in the call's values)
    picks: Vec<(usize, usize)>,
}

#[derive(Debug)]
struct Plan {
    group: Group,
    key: Vec<u32>,
    calls: Vec<Call>,
}

/// What one `fmi3DoStep` did: returned early at a time (without ending the run), or else.
enum Stepped {
    Early(f64),
    Status(StepStatus),
}

/// Plans kept per instance: a master exchanges the same lists every step.
const PLAN_CACHE: usize = 64;

pub(crate) struct Fmi3Instance {
    instance: NonNull<c_void>,
    name: String,
    /// The number its calls are noted by in the black box.
    pub(crate) black_box: u32,
    api: Arc<Fmi3Api>,
    functions: Fmi3Functions,
    log: Arc<LogEnv>,
    _fmu: Arc<FmuShared>,
    _strings: [CString; 2],
    _resource_path: Option<CString>,
    event_mode_used: bool,
    interface: Interface,
    mode: Mode,
    set_since_step: bool,
    experiment: (Option<f64>, f64, Option<f64>),
    last_successful_time: f64,
    terminated: bool,
    /// The value of every element the harness last set, or its start value.
    shadow: Starts,
    plans: Vec<Plan>,
    float64: Vec<f64>,
    int32: Vec<i32>,
    int64: Vec<i64>,
    booleans: Vec<bool>,
    strings: Vec<fmi3String>,
    /// Live FMU states by slot; a freed slot is `None` and reused.
    states: Vec<Option<fmu_state::Slot>>,
    /// One call's values of a word type, as words (`crate::word`).
    words: Vec<u64>,
    /// One call's Binary values: the FMU's pointers (valid until its next call) and sizes.
    binaries: Vec<*const u8>,
    binary_sizes: Vec<usize>,
}

// SAFETY: as for the FMI 2.0 backend: the instance pointer is used only through `&mut self`
// (or in `drop`), and the logger environment is thread-safe.
unsafe impl Send for Fmi3Instance {}

impl std::fmt::Debug for Fmi3Instance {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Fmi3Instance")
            .field("name", &self.name)
            .field("mode", &self.mode)
            .field("event_mode_used", &self.event_mode_used)
            .finish_non_exhaustive()
    }
}

impl Fmi3Instance {
    pub(crate) fn new(
        fmu: Arc<FmuShared>,
        api: Arc<Fmi3Api>,
        name: &str,
        logging_on: bool,
        event_mode_used: bool,
        interface: Interface,
    ) -> Result<Self, CallError> {
        let functions = api.functions;
        let (co_simulation, model_exchange) = (functions.co_simulation, functions.model_exchange);
        let (function, available) = match interface {
            Interface::CoSimulation => ("fmi3InstantiateCoSimulation", co_simulation.is_some()),
            Interface::ModelExchange => ("fmi3InstantiateModelExchange", model_exchange.is_some()),
        };
        if !available {
            return Err(CallError::InvalidArgument {
                function,
                instance: name.to_owned(),
                reason: format!(
                    "model '{}' does not declare {interface:?} (its model description has no \
                     <{}> element)",
                    api.description.model_name,
                    match interface {
                        Interface::CoSimulation => "CoSimulation",
                        Interface::ModelExchange => "ModelExchange",
                    }
                ),
            });
        }
        // Event Mode is what Co-Simulation may use; Model Exchange always has it.
        let event_mode_used = event_mode_used && interface == Interface::CoSimulation;
        let c_string = |what: &str, text: &str| {
            CString::new(text).map_err(|_| CallError::InvalidArgument {
                function,
                instance: name.to_owned(),
                reason: format!("{what} contains a NUL byte"),
            })
        };
        let instance_name = c_string("instance name", name)?;
        let token = c_string("instantiation token", &api.description.instantiation_token)?;
        let resources = fmu.files.resources_dir();
        let resource_path = resources
            .filter(|dir| dir.is_dir())
            .map(|dir| {
                let mut text = dir.to_string_lossy().into_owned();
                text.push(std::path::MAIN_SEPARATOR);
                c_string("resource path", &text)
            })
            .transpose()?;
        let log = Arc::new(LogEnv::named(name));
        let mark = log.mark();
        let resource = resource_path.as_ref().map_or(ptr::null(), |p| p.as_ptr());
        let environment = Arc::as_ptr(&log) as *mut c_void;
        let black_box = crate::blackbox::register(name);
        let call =
            crate::blackbox::enter(black_box, crate::blackbox::function_at_run_time(function));
        // SAFETY: every pointer is valid for the call; `log` and the strings move into the
        // instance, which outlives the FMU's instance.
        let instance = unsafe {
            match (co_simulation, model_exchange, interface) {
                (Some(cs), _, Interface::CoSimulation) => (cs.instantiate_co_simulation)(
                    instance_name.as_ptr(),
                    token.as_ptr(),
                    resource,
                    false,
                    logging_on,
                    event_mode_used,
                    true,
                    ptr::null(),
                    0,
                    environment,
                    Some(log_message_fmi3),
                    None,
                ),
                (_, Some(me), _) => (me.instantiate_model_exchange)(
                    instance_name.as_ptr(),
                    token.as_ptr(),
                    resource,
                    false,
                    logging_on,
                    environment,
                    Some(log_message_fmi3),
                ),
                _ => ptr::null_mut(),
            }
        };
        drop(call);
        let Some(instance) = NonNull::new(instance) else {
            return Err(CallError::InstantiationFailed {
                function,
                instance: name.to_owned(),
                log: log.since(mark),
            });
        };
        Self {
            instance,
            name: name.to_owned(),
            black_box,
            shadow: api.starts.clone(),
            functions,
            api,
            log,
            _fmu: fmu,
            _strings: [instance_name, token],
            _resource_path: resource_path,
            event_mode_used,
            interface,
            mode: Mode::Instantiated,
            set_since_step: false,
            experiment: (None, 0.0, None),
            last_successful_time: f64::NAN,
            terminated: false,
            plans: Vec::new(),
            float64: Vec::new(),
            int32: Vec::new(),
            int64: Vec::new(),
            booleans: Vec::new(),
            strings: Vec::new(),
            states: Vec::new(),
            words: Vec::new(),
            binaries: Vec::new(),
            binary_sizes: Vec::new(),
        }
        .configured()
    }

    /// Sets the structural parameters the view was built for (`fmi3/view.rs`) in
    /// Configuration Mode: `fmi3EnterConfigurationMode` from Instantiated, their values,
    /// `fmi3ExitConfigurationMode` back to Instantiated (FMI 3.0, 3.2.2 and 4.2.2). Nothing
    /// when the view is that of their start values.
    fn configured(mut self) -> Result<Self, CallError> {
        self.configure()?;
        Ok(self)
    }

    fn configure(&mut self) -> Result<(), CallError> {
        if self.api.configured.is_empty() {
            return Ok(());
        }
        let enter = self.functions.enter_configuration_mode;
        self.only(
            "fmi3EnterConfigurationMode",
            const { crate::blackbox::function("fmi3EnterConfigurationMode") },
            enter,
        )?;
        let references = self.api.configured.clone();
        for group in [
            Group::Real,
            Group::Integer,
            Group::Boolean,
            Group::String,
            Group::Word,
            Group::Binary,
        ] {
            let vrs: Vec<u32> = references
                .iter()
                .copied()
                .filter(|&vr| Group::of(self.api.elements[vr as usize].kind) == group)
                .collect();
            if !vrs.is_empty() {
                self.set_group(group, &vrs)?;
            }
        }
        let exit = self.functions.exit_configuration_mode;
        self.only(
            "fmi3ExitConfigurationMode",
            const { crate::blackbox::function("fmi3ExitConfigurationMode") },
            exit,
        )?;
        Ok(())
    }

    pub(crate) fn name(&self) -> &str {
        &self.name
    }

    pub(crate) fn log(&self) -> &Arc<LogEnv> {
        &self.log
    }

    /// Whether a get may follow a set at one communication point: Event Mode is used, or
    /// the instance is Model Exchange (no Step Mode).
    pub(crate) fn event_mode_used(&self) -> bool {
        self.event_mode_used || self.interface == Interface::ModelExchange
    }

    fn c(&self) -> fmi3Instance {
        self.instance.as_ptr()
    }

    fn check(
        &self,
        function: &'static str,
        mark: LogMark,
        raw: fmi3Status,
    ) -> Result<Success, FmiError> {
        Status::from_raw(fmi_abi::fmi2::fmi2Status(raw.0))
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

    fn only(
        &mut self,
        function: &'static str,
        noted_as: u32,
        call: crate::tables::fmi3::Only,
    ) -> Result<Success, FmiError> {
        let mark = self.log.mark();
        let noted = crate::blackbox::enter(self.black_box, noted_as);
        // SAFETY: a live instance; the function takes nothing else.
        let raw = unsafe { call(self.c()) };
        drop(noted);
        self.check(function, mark, raw)
    }

    pub(crate) fn set_debug_logging(
        &mut self,
        logging_on: bool,
        categories: &[&str],
    ) -> Result<Success, CallError> {
        const F: &str = "fmi3SetDebugLogging";
        let owned = categories
            .iter()
            .map(|category| {
                CString::new(*category).map_err(|_| {
                    self.invalid(F, format!("category {category:?} contains a NUL byte"))
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        let pointers: Vec<fmi3String> = owned.iter().map(|c| c.as_ptr()).collect();
        let mark = self.log.mark();
        // SAFETY: `pointers` holds `len` valid C strings for the duration of the call.
        let raw = unsafe {
            (self.functions.set_debug_logging)(
                self.c(),
                logging_on,
                pointers.len(),
                if pointers.is_empty() {
                    ptr::null()
                } else {
                    pointers.as_ptr()
                },
            )
        };
        Ok(self.check(F, mark, raw)?)
    }

    /// FMI 3.0 has no `fmi3SetupExperiment`: the values go to `fmi3EnterInitializationMode`.
    pub(crate) fn setup_experiment(
        &mut self,
        tolerance: Option<f64>,
        start_time: f64,
        stop_time: Option<f64>,
    ) -> Result<Success, FmiError> {
        self.experiment = (tolerance, start_time, stop_time);
        Ok(Success::Ok)
    }

    pub(crate) fn enter_initialization_mode(&mut self) -> Result<Success, FmiError> {
        let (tolerance, start, stop) = self.experiment;
        let mark = self.log.mark();
        // SAFETY: plain values only.
        let raw = unsafe {
            (self.functions.enter_initialization_mode)(
                self.c(),
                tolerance.is_some(),
                tolerance.unwrap_or(0.0),
                start,
                stop.is_some(),
                stop.unwrap_or(0.0),
            )
        };
        let success = self.check("fmi3EnterInitializationMode", mark, raw)?;
        self.mode = Mode::Initialization;
        self.last_successful_time = start;
        Ok(success)
    }

    /// Into Event Mode with `eventModeUsed`, else Step Mode (FMI 3.0, 4.2.1).
    pub(crate) fn exit_initialization_mode(&mut self) -> Result<Success, FmiError> {
        let call = self.functions.exit_initialization_mode;
        let success = self.only(
            "fmi3ExitInitializationMode",
            const { crate::blackbox::function("fmi3ExitInitializationMode") },
            call,
        )?;
        // Model Exchange always leaves initialization into Event Mode (FMI 3.0, 3.2).
        self.mode = if self.event_mode_used || self.interface == Interface::ModelExchange {
            Mode::Event
        } else {
            Mode::Step
        };
        self.set_since_step = false;
        Ok(success)
    }

    pub(crate) fn terminate(&mut self) -> Result<Success, FmiError> {
        let call = self.functions.terminate;
        let success = self.only(
            "fmi3Terminate",
            const { crate::blackbox::function("fmi3Terminate") },
            call,
        );
        self.mode = Mode::Terminated;
        success
    }

    pub(crate) fn reset(&mut self) -> Result<Success, FmiError> {
        let call = self.functions.reset;
        let success = self.only(
            "fmi3Reset",
            const { crate::blackbox::function("fmi3Reset") },
            call,
        )?;
        self.mode = Mode::Instantiated;
        self.set_since_step = false;
        self.terminated = false;
        self.shadow = self.api.starts.clone();
        // A reset returns the structural parameters to their start values.
        self.configure().map_err(|error| match error {
            CallError::Fmi(error) => error,
            other => FmiError::from_importer(
                "fmi3ExitConfigurationMode",
                &self.name,
                crate::version::FmiVersion::Fmi3,
                other.to_string(),
            ),
        })?;
        Ok(success)
    }

    fn enter_event_mode(&mut self) -> Result<(), FmiError> {
        let call = self.functions.enter_event_mode;
        self.only(
            "fmi3EnterEventMode",
            const { crate::blackbox::function("fmi3EnterEventMode") },
            call,
        )?;
        self.mode = Mode::Event;
        Ok(())
    }

    /// `fmi3UpdateDiscreteStates` until nothing needs an update, then `fmi3EnterStepMode`;
    /// true when the FMU asks to terminate (it then stays in Event Mode).
    fn leave_event_mode(&mut self) -> Result<bool, FmiError> {
        const F: &str = "fmi3UpdateDiscreteStates";
        // A bound against an FMU that never settles; our FMUs need one call.
        for _ in 0..1000 {
            let (mut again, mut terminate, mut nominals, mut values, mut defined, mut next) =
                (false, false, false, false, false, 0.0);
            let mark = self.log.mark();
            let noted =
                crate::blackbox::enter(self.black_box, const { crate::blackbox::function(F) });
            // SAFETY: a live instance and valid out-pointers.
            let raw = unsafe {
                (self.functions.update_discrete_states)(
                    self.c(),
                    &mut again,
                    &mut terminate,
                    &mut nominals,
                    &mut values,
                    &mut defined,
                    &mut next,
                )
            };
            drop(noted);
            self.check(F, mark, raw)?;
            if terminate {
                return Ok(true);
            }
            if !again {
                let Some(co_simulation) = self.functions.co_simulation else {
                    return Err(self.not_co_simulation("fmi3EnterStepMode"));
                };
                self.only(
                    "fmi3EnterStepMode",
                    const { crate::blackbox::function("fmi3EnterStepMode") },
                    co_simulation.enter_step_mode,
                )?;
                self.mode = Mode::Step;
                return Ok(false);
            }
        }
        Err(FmiError {
            function: F,
            instance: self.name.clone(),
            status: crate::status::Failure::Error,
            log: crate::logger::FmuLog(vec![]),
        })
    }

    /// One communication step from `current_time` over `step_size`: `fmi3DoStep` until it
    /// reaches the step's end, ends the run, or fails; an early return without termination
    /// is continued from `lastSuccessfulTime` (bounded: a step the FMU keeps cutting short
    /// without advancing is an error).
    pub(crate) fn do_step(
        &mut self,
        current_time: f64,
        step_size: f64,
    ) -> Result<StepStatus, FmiError> {
        let end = current_time + step_size;
        let mut from = current_time;
        for _ in 0..10_000 {
            // The master's own step size first: `(t + h) - t` can differ from `h` in its last
            // bit, and an FMU that integrates over what it is given would fly another
            // trajectory. After an early return, the rest of the step.
            let span = if from == current_time {
                step_size
            } else {
                end - from
            };
            match self.one_step(from, span)? {
                Stepped::Early(last) if last >= end => {
                    return Ok(StepStatus::Complete(Success::Ok))
                }
                // A return that does not advance is reported as the stop it is.
                Stepped::Early(last) if last <= from => {
                    return Ok(StepStatus::Discarded {
                        last_successful_time: last,
                        terminated: false,
                    })
                }
                Stepped::Early(last) => from = last,
                Stepped::Status(status) => return Ok(status),
            }
        }
        Err(FmiError::from_importer(
            "fmi3DoStep",
            &self.name,
            crate::version::FmiVersion::Fmi3,
            format!(
                "the step from t = {current_time} returned early 10,000 times without \
                 reaching t = {end}"
            ),
        ))
    }

    /// One `fmi3DoStep` from `current_time` over `step_size`, leaving Event Mode first.
    fn one_step(&mut self, current_time: f64, step_size: f64) -> Result<Stepped, FmiError> {
        const F: &str = "fmi3DoStep";
        let Some(co_simulation) = self
            .functions
            .co_simulation
            .filter(|_| self.interface == Interface::CoSimulation)
        else {
            return Err(self.not_co_simulation(F));
        };
        if self.mode == Mode::Event && self.leave_event_mode()? {
            self.terminated = true;
            self.last_successful_time = current_time;
            return Ok(Stepped::Status(StepStatus::Terminated {
                last_successful_time: current_time,
            }));
        }
        // Out-arguments start at what a quiet step reports.
        let (mut event, mut terminate, mut early, mut last) =
            (false, false, false, current_time + step_size);
        let mark = self.log.mark();
        // SAFETY: a live instance and valid out-pointers.
        let raw = unsafe {
            (co_simulation.do_step)(
                self.c(),
                current_time,
                step_size,
                false,
                &mut event,
                &mut terminate,
                &mut early,
                &mut last,
            )
        };
        self.set_since_step = false;
        let status = Status::from_raw(fmi_abi::fmi2::fmi2Status(raw.0)).into_result();
        match status {
            Ok(success) => {
                self.last_successful_time = last;
                if terminate {
                    self.terminated = true;
                    return Ok(Stepped::Status(StepStatus::Terminated {
                        last_successful_time: last,
                    }));
                }
                if event && self.event_mode_used {
                    self.enter_event_mode()?;
                    if self.leave_event_mode()? {
                        self.terminated = true;
                        return Ok(Stepped::Status(StepStatus::Terminated {
                            last_successful_time: last,
                        }));
                    }
                }
                if early {
                    return Ok(Stepped::Early(last));
                }
                Ok(Stepped::Status(StepStatus::Complete(success)))
            }
            Err(crate::status::Failure::Discard) => {
                self.last_successful_time = last;
                self.terminated = terminate;
                Ok(Stepped::Status(StepStatus::Discarded {
                    last_successful_time: last,
                    terminated: terminate,
                }))
            }
            Err(status) => Err(FmiError {
                function: F,
                instance: self.name.clone(),
                status,
                log: self.log.since(mark),
            }),
        }
    }

    pub(crate) fn last_successful_time(&self) -> f64 {
        self.last_successful_time
    }

    pub(crate) fn terminated(&self) -> bool {
        self.terminated
    }

    // ---- values ----

    /// The calls for `vrs` (element references of `group`), from the cache or made now.
    fn plan(
        &mut self,
        function: &'static str,
        group: Group,
        vrs: &[u32],
    ) -> Result<Vec<Call>, CallError> {
        if let Some(i) = self
            .plans
            .iter()
            .position(|p| p.group == group && p.key == vrs)
        {
            return Ok(std::mem::take(&mut self.plans[i].calls));
        }
        let elements: &[Element] = &self.api.elements;
        let mut calls: Vec<Call> = Vec::new();
        for (position, &vr) in vrs.iter().enumerate() {
            let element = elements
                .get(vr as usize)
                .filter(|e| group.admits(e.kind))
                .ok_or_else(|| {
                    self.invalid(
                        function,
                        format!("value reference {vr} is not a {} element", group.name()),
                    )
                })?;
            let call = match calls.iter().position(|c| c.kind == element.kind) {
                Some(i) => &mut calls[i],
                None => {
                    calls.push(Call {
                        kind: element.kind,
                        vrs: Vec::new(),
                        arrays: Vec::new(),
                        total: 0,
                        picks: Vec::new(),
                    });
                    calls.last_mut().expect("just pushed")
                }
            };
            let offset = match call.vrs.iter().position(|&v| v == element.value_reference) {
                Some(i) => call.arrays[..i].iter().map(|(_, len)| len).sum::<usize>(),
                None => {
                    let offset = call.total;
                    call.vrs.push(element.value_reference);
                    call.arrays.push((element.first, element.len));
                    call.total += element.len;
                    offset
                }
            };
            call.picks.push((position, offset + element.index));
        }
        Ok(calls)
    }

    /// Puts a plan back into the cache (or in for the first time).
    fn keep(&mut self, group: Group, vrs: &[u32], calls: Vec<Call>) {
        match self
            .plans
            .iter()
            .position(|p| p.group == group && p.key == vrs)
        {
            Some(i) => self.plans[i].calls = calls,
            None if self.plans.len() < PLAN_CACHE => self.plans.push(Plan {
                group,
                key: vrs.to_vec(),
                calls,
            }),
            None => {}
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

    fn not_co_simulation(&self, function: &'static str) -> FmiError {
        self.wrong_interface(function, "Co-Simulation")
    }

    fn wrong_interface(&self, function: &'static str, wanted: &str) -> FmiError {
        FmiError::from_importer(
            function,
            &self.name,
            crate::version::FmiVersion::Fmi3,
            format!(
                "{function} is a {wanted} function and this instance was made for {:?}",
                self.interface
            ),
        )
    }

    // ---- Model Exchange (FMI 3.0, 3) ----

    fn model_exchange(&self, function: &'static str) -> Result<Fmi3ModelExchange, FmiError> {
        match (self.interface, self.functions.model_exchange) {
            (Interface::ModelExchange, Some(table)) => Ok(table),
            _ => Err(self.wrong_interface(function, "Model Exchange")),
        }
    }

    /// `fmi3GetNumberOfContinuousStates` and `fmi3GetNumberOfEventIndicators`.
    pub(crate) fn model_exchange_sizes(&mut self) -> Result<(usize, usize), FmiError> {
        let table = self.model_exchange("fmi3GetNumberOfContinuousStates")?;
        let (mut states, mut indicators) = (0usize, 0usize);
        let mark = self.log.mark();
        // SAFETY: valid out-pointers.
        let raw = unsafe { (table.get_number_of_continuous_states)(self.c(), &mut states) };
        self.check("fmi3GetNumberOfContinuousStates", mark, raw)?;
        let mark = self.log.mark();
        // SAFETY: valid out-pointers.
        let raw = unsafe { (table.get_number_of_event_indicators)(self.c(), &mut indicators) };
        self.check("fmi3GetNumberOfEventIndicators", mark, raw)?;
        Ok((states, indicators))
    }

    pub(crate) fn set_time(&mut self, time: f64) -> Result<Success, FmiError> {
        const F: &str = "fmi3SetTime";
        let call = self.model_exchange(F)?.set_time;
        let mark = self.log.mark();
        // SAFETY: plain values only.
        let raw = unsafe { call(self.c(), time) };
        self.check(F, mark, raw)
    }

    pub(crate) fn set_continuous_states(&mut self, x: &[f64]) -> Result<Success, FmiError> {
        const F: &str = "fmi3SetContinuousStates";
        let call = self.model_exchange(F)?.set_continuous_states;
        let mark = self.log.mark();
        // SAFETY: `x` is valid for `x.len()` reads.
        let raw = unsafe { call(self.c(), x.as_ptr(), x.len()) };
        self.check(F, mark, raw)
    }

    pub(crate) fn get_vector(
        &mut self,
        which: MeVector,
        values: &mut [f64],
    ) -> Result<Success, FmiError> {
        let function = match which {
            MeVector::States => "fmi3GetContinuousStates",
            MeVector::Derivatives => "fmi3GetContinuousStateDerivatives",
            MeVector::EventIndicators => "fmi3GetEventIndicators",
            MeVector::Nominals => "fmi3GetNominalsOfContinuousStates",
        };
        let table = self.model_exchange(function)?;
        let call = match which {
            MeVector::States => table.get_continuous_states,
            MeVector::Derivatives => table.get_continuous_state_derivatives,
            MeVector::EventIndicators => table.get_event_indicators,
            MeVector::Nominals => table.get_nominals_of_continuous_states,
        };
        let mark = self.log.mark();
        // SAFETY: `values` is valid for `values.len()` writes.
        let raw = unsafe { call(self.c(), values.as_mut_ptr(), values.len()) };
        self.check(function, mark, raw)
    }

    pub(crate) fn enter_event_mode_me(&mut self) -> Result<Success, FmiError> {
        self.model_exchange("fmi3EnterEventMode")?;
        self.enter_event_mode()?;
        Ok(Success::Ok)
    }

    pub(crate) fn enter_continuous_time_mode(&mut self) -> Result<Success, FmiError> {
        const F: &str = "fmi3EnterContinuousTimeMode";
        let call = self.model_exchange(F)?.enter_continuous_time_mode;
        let success = self.only(F, const { crate::blackbox::function(F) }, call)?;
        self.mode = Mode::ContinuousTime;
        Ok(success)
    }

    /// One `fmi3UpdateDiscreteStates` of the event iteration.
    pub(crate) fn update_discrete_states(&mut self) -> Result<EventUpdate, FmiError> {
        const F: &str = "fmi3UpdateDiscreteStates";
        self.model_exchange(F)?;
        let (mut again, mut terminate, mut nominals, mut values, mut defined, mut next) =
            (false, false, false, false, false, 0.0);
        let mark = self.log.mark();
        // SAFETY: a live instance and valid out-pointers.
        let raw = unsafe {
            (self.functions.update_discrete_states)(
                self.c(),
                &mut again,
                &mut terminate,
                &mut nominals,
                &mut values,
                &mut defined,
                &mut next,
            )
        };
        self.check(F, mark, raw)?;
        Ok(EventUpdate {
            discrete_states_need_update: again,
            terminate_simulation: terminate,
            nominals_changed: nominals,
            states_changed: values,
            next_event_time: defined.then_some(next),
        })
    }

    /// `fmi3CompletedIntegratorStep` with `noSetFMUStatePriorToCurrentPoint = false`.
    pub(crate) fn completed_integrator_step(&mut self) -> Result<StepEnd, FmiError> {
        const F: &str = "fmi3CompletedIntegratorStep";
        let call = self.model_exchange(F)?.completed_integrator_step;
        let (mut enter_event_mode, mut terminate) = (false, false);
        let mark = self.log.mark();
        // SAFETY: valid out-pointers.
        let raw = unsafe { call(self.c(), false, &mut enter_event_mode, &mut terminate) };
        self.check(F, mark, raw)?;
        Ok(StepEnd {
            enter_event_mode,
            terminate_simulation: terminate,
        })
    }

    /// Refuses a get the standard forbids; FMI 3.0, 4.2.1, Step Mode.
    fn before_get(&self, function: &'static str) -> Result<(), CallError> {
        if self.mode == Mode::Step && self.set_since_step {
            return Err(self.invalid(
                function,
                "in Step Mode FMI 3.0 allows no get after a set without fmi3DoStep in \
                 between; a master that needs this instance's outputs at the instant its \
                 inputs are set must instantiate it for same-instant feedthrough (Event Mode)"
                    .to_owned(),
            ));
        }
        Ok(())
    }

    /// Event Mode at the first set after a step, when used; else the set is remembered.
    fn before_set(&mut self) -> Result<(), CallError> {
        if self.mode == Mode::Step {
            if self.event_mode_used {
                self.enter_event_mode()?;
            } else {
                self.set_since_step = true;
            }
        }
        Ok(())
    }

    /// Runs the get calls of `vrs`, handing each element's position and the call's buffer
    /// index to `store`.
    fn get_group(
        &mut self,
        group: Group,
        vrs: &[u32],
        values_len: usize,
        mut store: impl FnMut(&Self, &'static str, Fmi3Type, usize, usize) -> Result<(), CallError>,
    ) -> Result<Success, CallError> {
        let function = get_name(group);
        self.check_lengths(function, vrs.len(), values_len)?;
        self.before_get(function)?;
        if vrs.is_empty() {
            return Ok(Success::Ok);
        }
        let calls = self.plan(function, group, vrs)?;
        let mut outcome = Ok(Success::Ok);
        for call in &calls {
            let function = get_name_of(call.kind);
            // A word type's values into `self.words`, through a buffer of the C type.
            macro_rules! get_words {
                ($get:ident, $t:ty) => {{
                    let mut buffer: Vec<$t> = vec![<$t>::default(); call.total];
                    let raw = (self.functions.$get)(
                        self.c(),
                        call.vrs.as_ptr(),
                        call.vrs.len(),
                        buffer.as_mut_ptr(),
                        call.total,
                    );
                    self.words.clear();
                    self.words.extend(buffer.into_iter().map(Word::word));
                    raw
                }};
            }
            let mark = self.log.mark();
            let _noted = matches!(group, Group::Word | Group::Binary).then(|| {
                crate::blackbox::enter(
                    self.black_box,
                    crate::blackbox::function_at_run_time(function),
                )
            });
            // SAFETY: `call.vrs` and the buffer hold the lengths passed; each buffer is
            // resized to the call's element count first.
            let raw = unsafe {
                match call.kind {
                    Fmi3Type::Float64 => {
                        self.float64.resize(call.total, 0.0);
                        (self.functions.get_float64)(
                            self.c(),
                            call.vrs.as_ptr(),
                            call.vrs.len(),
                            self.float64.as_mut_ptr(),
                            call.total,
                        )
                    }
                    Fmi3Type::Int32 => {
                        self.int32.resize(call.total, 0);
                        (self.functions.get_int32)(
                            self.c(),
                            call.vrs.as_ptr(),
                            call.vrs.len(),
                            self.int32.as_mut_ptr(),
                            call.total,
                        )
                    }
                    Fmi3Type::Enumeration => {
                        self.int64.resize(call.total, 0);
                        (self.functions.get_int64)(
                            self.c(),
                            call.vrs.as_ptr(),
                            call.vrs.len(),
                            self.int64.as_mut_ptr(),
                            call.total,
                        )
                    }
                    Fmi3Type::Boolean => {
                        self.booleans.resize(call.total, false);
                        (self.functions.get_boolean)(
                            self.c(),
                            call.vrs.as_ptr(),
                            call.vrs.len(),
                            self.booleans.as_mut_ptr(),
                            call.total,
                        )
                    }
                    Fmi3Type::Float32 => get_words!(get_float32, f32),
                    Fmi3Type::Int8 => get_words!(get_int8, i8),
                    Fmi3Type::UInt8 => get_words!(get_uint8, u8),
                    Fmi3Type::Int16 => get_words!(get_int16, i16),
                    Fmi3Type::UInt16 => get_words!(get_uint16, u16),
                    Fmi3Type::UInt32 => get_words!(get_uint32, u32),
                    Fmi3Type::Int64 => get_words!(get_int64, i64),
                    Fmi3Type::UInt64 => get_words!(get_uint64, u64),
                    Fmi3Type::Binary => {
                        self.binaries.clear();
                        self.binaries.resize(call.total, ptr::null());
                        self.binary_sizes.clear();
                        self.binary_sizes.resize(call.total, 0);
                        (self.functions.get_binary)(
                            self.c(),
                            call.vrs.as_ptr(),
                            call.vrs.len(),
                            self.binary_sizes.as_mut_ptr(),
                            self.binaries.as_mut_ptr(),
                            call.total,
                        )
                    }
                    _ => {
                        self.strings.clear();
                        self.strings.resize(call.total, ptr::null());
                        (self.functions.get_string)(
                            self.c(),
                            call.vrs.as_ptr(),
                            call.vrs.len(),
                            self.strings.as_mut_ptr(),
                            call.total,
                        )
                    }
                }
            };
            let result = self
                .check(function, mark, raw)
                .map_err(CallError::from)
                .and_then(|success| {
                    for &(position, at) in &call.picks {
                        store(self, function, call.kind, position, at)?;
                    }
                    Ok(success)
                });
            match result {
                Ok(Success::Warning) => outcome = Ok(Success::Warning),
                Ok(Success::Ok) => {}
                Err(e) => {
                    outcome = Err(e);
                    break;
                }
            }
        }
        // The FMU's string and binary pointers die with its next call: none is kept.
        self.strings.iter_mut().for_each(|p| *p = ptr::null());
        self.binaries.iter_mut().for_each(|p| *p = ptr::null());
        self.keep(group, vrs, calls);
        outcome
    }

    /// Writes the touched arrays whole from the shadow values (already updated).
    fn set_group(&mut self, group: Group, vrs: &[u32]) -> Result<Success, CallError> {
        let function = set_name(group);
        let calls = self.plan(function, group, vrs)?;
        let mut outcome = Ok(Success::Ok);
        let mut owned: Vec<CString> = Vec::new();
        for call in &calls {
            let function = set_name_of(call.kind);
            let ranges = call.arrays.iter().map(|&(first, len)| first..first + len);
            match call.kind {
                Fmi3Type::Float64 => {
                    self.float64.clear();
                    for range in ranges {
                        self.float64.extend_from_slice(&self.shadow.float64[range]);
                    }
                }
                Fmi3Type::Int32 => {
                    self.int32.clear();
                    for range in ranges {
                        // Int32 elements are only ever set from i32 values.
                        self.int32
                            .extend(self.shadow.int[range].iter().map(|&i| i as i32));
                    }
                }
                Fmi3Type::Enumeration => {
                    self.int64.clear();
                    for range in ranges {
                        self.int64.extend_from_slice(&self.shadow.int[range]);
                    }
                }
                Fmi3Type::Boolean => {
                    self.booleans.clear();
                    for range in ranges {
                        self.booleans.extend_from_slice(&self.shadow.boolean[range]);
                    }
                }
                kind if crate::word::is_word(kind) => {
                    self.words.clear();
                    for range in ranges {
                        self.words.extend_from_slice(&self.shadow.words[range]);
                    }
                }
                Fmi3Type::Binary => {
                    self.binaries.clear();
                    self.binary_sizes.clear();
                    for range in ranges {
                        for bytes in &self.shadow.binary[range] {
                            self.binaries.push(bytes.as_ptr());
                            self.binary_sizes.push(bytes.len());
                        }
                    }
                }
                _ => {
                    owned.clear();
                    for range in ranges {
                        for text in &self.shadow.string[range] {
                            owned.push(CString::new(text.as_str()).map_err(|_| {
                                self.invalid(
                                    function,
                                    format!("value {text:?} contains a NUL byte"),
                                )
                            })?);
                        }
                    }
                    self.strings.clear();
                    self.strings.extend(owned.iter().map(|c| c.as_ptr()));
                }
            }
            let mark = self.log.mark();
            // The words of a word type as a buffer of its C type (each in range: checked
            // when set).
            macro_rules! set_words {
                ($set:ident, $t:ty, $c:ident, $vrs:ident, $n:ident) => {{
                    let buffer: Vec<$t> = self.words.iter().map(|&w| <$t>::from_word(w)).collect();
                    (self.functions.$set)($c, $vrs, $n, buffer.as_ptr(), call.total)
                }};
            }
            let _noted = matches!(group, Group::Word | Group::Binary).then(|| {
                crate::blackbox::enter(
                    self.black_box,
                    crate::blackbox::function_at_run_time(function),
                )
            });
            // SAFETY: `call.vrs` and the buffer filled above hold the lengths passed; the
            // strings and binaries outlive the call.
            let raw = unsafe {
                let (c, vrs, n) = (self.c(), call.vrs.as_ptr(), call.vrs.len());
                match call.kind {
                    Fmi3Type::Float64 => {
                        (self.functions.set_float64)(c, vrs, n, self.float64.as_ptr(), call.total)
                    }
                    Fmi3Type::Int32 => {
                        (self.functions.set_int32)(c, vrs, n, self.int32.as_ptr(), call.total)
                    }
                    Fmi3Type::Enumeration => {
                        (self.functions.set_int64)(c, vrs, n, self.int64.as_ptr(), call.total)
                    }
                    Fmi3Type::Boolean => {
                        (self.functions.set_boolean)(c, vrs, n, self.booleans.as_ptr(), call.total)
                    }
                    Fmi3Type::Float32 => set_words!(set_float32, f32, c, vrs, n),
                    Fmi3Type::Int8 => set_words!(set_int8, i8, c, vrs, n),
                    Fmi3Type::UInt8 => set_words!(set_uint8, u8, c, vrs, n),
                    Fmi3Type::Int16 => set_words!(set_int16, i16, c, vrs, n),
                    Fmi3Type::UInt16 => set_words!(set_uint16, u16, c, vrs, n),
                    Fmi3Type::UInt32 => set_words!(set_uint32, u32, c, vrs, n),
                    Fmi3Type::Int64 => set_words!(set_int64, i64, c, vrs, n),
                    Fmi3Type::UInt64 => set_words!(set_uint64, u64, c, vrs, n),
                    Fmi3Type::Binary => (self.functions.set_binary)(
                        c,
                        vrs,
                        n,
                        self.binary_sizes.as_ptr(),
                        self.binaries.as_ptr(),
                        call.total,
                    ),
                    _ => (self.functions.set_string)(c, vrs, n, self.strings.as_ptr(), call.total),
                }
            };
            match self.check(function, mark, raw) {
                Ok(Success::Warning) => outcome = Ok(Success::Warning),
                Ok(Success::Ok) => {}
                Err(e) => {
                    outcome = Err(e.into());
                    break;
                }
            }
        }
        self.strings.clear();
        self.binaries.clear();
        self.keep(group, vrs, calls);
        outcome
    }

    /// Checks the references and lengths of a set and leaves Step Mode when it must.
    fn begin_set(&mut self, group: Group, vrs: &[u32], values: usize) -> Result<bool, CallError> {
        let function = set_name(group);
        self.check_lengths(function, vrs.len(), values)?;
        if let Some(&vr) = vrs.iter().find(|&&vr| {
            self.api
                .elements
                .get(vr as usize)
                .is_none_or(|e| !group.admits(e.kind))
        }) {
            return Err(self.invalid(
                function,
                format!("value reference {vr} is not a {} element", group.name()),
            ));
        }
        if vrs.is_empty() {
            return Ok(false);
        }
        self.before_set()?;
        Ok(true)
    }

    pub(crate) fn set_real(&mut self, vrs: &[u32], values: &[f64]) -> Result<Success, CallError> {
        if !self.begin_set(Group::Real, vrs, values.len())? {
            return Ok(Success::Ok);
        }
        for (&vr, &value) in vrs.iter().zip(values) {
            self.shadow.float64[vr as usize] = value;
        }
        self.set_group(Group::Real, vrs)
    }

    pub(crate) fn get_real(
        &mut self,
        vrs: &[u32],
        values: &mut [f64],
    ) -> Result<Success, CallError> {
        self.get_group(
            Group::Real,
            vrs,
            values.len(),
            |this, _, _, position, at| {
                values[position] = this.float64[at];
                Ok(())
            },
        )
    }

    pub(crate) fn set_integer(
        &mut self,
        vrs: &[u32],
        values: &[i32],
    ) -> Result<Success, CallError> {
        if !self.begin_set(Group::Integer, vrs, values.len())? {
            return Ok(Success::Ok);
        }
        for (&vr, &value) in vrs.iter().zip(values) {
            self.shadow.int[vr as usize] = i64::from(value);
        }
        self.set_group(Group::Integer, vrs)
    }

    pub(crate) fn get_integer(
        &mut self,
        vrs: &[u32],
        values: &mut [i32],
    ) -> Result<Success, CallError> {
        self.get_group(
            Group::Integer,
            vrs,
            values.len(),
            |this, function, kind, position, at| {
                values[position] = if kind == Fmi3Type::Int32 {
                    this.int32[at]
                } else {
                    let value = this.int64[at];
                    i32::try_from(value).map_err(|_| {
                        this.invalid(
                            function,
                            format!("enumeration value {value} is outside the Integer range"),
                        )
                    })?
                };
                Ok(())
            },
        )
    }

    pub(crate) fn set_boolean(
        &mut self,
        vrs: &[u32],
        values: &[bool],
    ) -> Result<Success, CallError> {
        if !self.begin_set(Group::Boolean, vrs, values.len())? {
            return Ok(Success::Ok);
        }
        for (&vr, &value) in vrs.iter().zip(values) {
            self.shadow.boolean[vr as usize] = value;
        }
        self.set_group(Group::Boolean, vrs)
    }

    pub(crate) fn get_boolean(
        &mut self,
        vrs: &[u32],
        values: &mut [bool],
    ) -> Result<Success, CallError> {
        self.get_group(
            Group::Boolean,
            vrs,
            values.len(),
            |this, _, _, position, at| {
                values[position] = this.booleans[at];
                Ok(())
            },
        )
    }

    /// Booleans as C `int`s (0 or 1), as the FMI 2.0 backend exchanges them.
    pub(crate) fn set_boolean_raw(
        &mut self,
        vrs: &[u32],
        values: &[i32],
    ) -> Result<Success, CallError> {
        if !self.begin_set(Group::Boolean, vrs, values.len())? {
            return Ok(Success::Ok);
        }
        for (&vr, &value) in vrs.iter().zip(values) {
            self.shadow.boolean[vr as usize] = value != 0;
        }
        self.set_group(Group::Boolean, vrs)
    }

    pub(crate) fn get_boolean_raw(
        &mut self,
        vrs: &[u32],
        values: &mut [i32],
    ) -> Result<Success, CallError> {
        self.get_group(
            Group::Boolean,
            vrs,
            values.len(),
            |this, _, _, position, at| {
                values[position] = i32::from(this.booleans[at]);
                Ok(())
            },
        )
    }

    pub(crate) fn set_string(
        &mut self,
        vrs: &[u32],
        values: &[&str],
    ) -> Result<Success, CallError> {
        if !self.begin_set(Group::String, vrs, values.len())? {
            return Ok(Success::Ok);
        }
        for (&vr, &value) in vrs.iter().zip(values) {
            value.clone_into(&mut self.shadow.string[vr as usize]);
        }
        self.set_group(Group::String, vrs)
    }

    pub(crate) fn get_string_into(
        &mut self,
        vrs: &[u32],
        values: &mut [String],
    ) -> Result<Success, CallError> {
        self.get_group(
            Group::String,
            vrs,
            values.len(),
            |this, function, _, position, at| {
                let pointer = this.strings[at];
                if pointer.is_null() {
                    return Err(this.invalid(
                        function,
                        format!(
                            "the FMU returned NULL for value reference {}",
                            vrs[position]
                        ),
                    ));
                }
                // SAFETY: a non-null fmi3String returned by the FMU is NUL-terminated and
                // valid until the next call into the instance.
                let text = unsafe { CStr::from_ptr(pointer) }.to_string_lossy();
                values[position].clear();
                values[position].push_str(&text);
                Ok(())
            },
        )
    }
}

impl Fmi3Instance {
    /// Sets values of the word types, each refused unless its type holds it.
    pub(crate) fn set_words(&mut self, vrs: &[u32], words: &[u64]) -> Result<Success, CallError> {
        if !self.begin_set(Group::Word, vrs, words.len())? {
            return Ok(Success::Ok);
        }
        for (&vr, &word) in vrs.iter().zip(words) {
            let kind = self.api.elements[vr as usize].kind;
            let back = match kind {
                Fmi3Type::Float32 => f64::from(f32::from_word(word)).to_bits() == word,
                Fmi3Type::UInt64 => true,
                kind => crate::word::from_integer(kind, crate::word::to_integer(kind, word))
                    .is_some_and(|w| w == word),
            };
            if !back {
                return Err(self.invalid(
                    set_name_of(kind),
                    format!(
                        "value reference {vr}: word {word:#x} is not a {} value",
                        kind.name()
                    ),
                ));
            }
        }
        for (&vr, &word) in vrs.iter().zip(words) {
            self.shadow.words[vr as usize] = word;
        }
        self.set_group(Group::Word, vrs)
    }

    pub(crate) fn get_words(
        &mut self,
        vrs: &[u32],
        words: &mut [u64],
    ) -> Result<Success, CallError> {
        self.get_group(Group::Word, vrs, words.len(), |this, _, _, position, at| {
            words[position] = this.words[at];
            Ok(())
        })
    }

    pub(crate) fn set_binary(
        &mut self,
        vrs: &[u32],
        values: &[&[u8]],
    ) -> Result<Success, CallError> {
        if !self.begin_set(Group::Binary, vrs, values.len())? {
            return Ok(Success::Ok);
        }
        for (&vr, &value) in vrs.iter().zip(values) {
            let slot = &mut self.shadow.binary[vr as usize];
            slot.clear();
            slot.extend_from_slice(value);
        }
        self.set_group(Group::Binary, vrs)
    }

    /// The bytes are copied at once: the FMU's pointers are valid only until its next call.
    pub(crate) fn get_binary_into(
        &mut self,
        vrs: &[u32],
        values: &mut [Vec<u8>],
    ) -> Result<Success, CallError> {
        self.get_group(
            Group::Binary,
            vrs,
            values.len(),
            |this, function, _, position, at| {
                let (pointer, size) = (this.binaries[at], this.binary_sizes[at]);
                values[position].clear();
                if size == 0 {
                    return Ok(());
                }
                if pointer.is_null() {
                    return Err(this.invalid(
                        function,
                        format!(
                            "the FMU returned NULL with size {size} for value reference {}",
                            vrs[position]
                        ),
                    ));
                }
                // SAFETY: a non-null fmi3Binary of `size` bytes returned by the FMU, valid
                // until the next call into the instance.
                values[position]
                    .extend_from_slice(unsafe { std::slice::from_raw_parts(pointer, size) });
                Ok(())
            },
        )
    }
}

impl Drop for Fmi3Instance {
    fn drop(&mut self) {
        self.free_all_states();
        let _call = crate::blackbox::enter(
            self.black_box,
            const { crate::blackbox::function("fmi3FreeInstance") },
        );
        // SAFETY: the instance is live and never used again; the logger environment is
        // dropped only after this returns.
        unsafe { (self.functions.free_instance)(self.instance.as_ptr()) };
    }
}

fn get_name(group: Group) -> &'static str {
    match group {
        Group::Real => "fmi3GetFloat64",
        Group::Integer => "fmi3GetInt32",
        Group::Boolean => "fmi3GetBoolean",
        Group::String => "fmi3GetString",
        Group::Word => "fmi3Get{Float32,Int8,...,UInt64}",
        Group::Binary => "fmi3GetBinary",
    }
}

fn set_name(group: Group) -> &'static str {
    match group {
        Group::Real => "fmi3SetFloat64",
        Group::Integer => "fmi3SetInt32",
        Group::Boolean => "fmi3SetBoolean",
        Group::String => "fmi3SetString",
        Group::Word => "fmi3Set{Float32,Int8,...,UInt64}",
        Group::Binary => "fmi3SetBinary",
    }
}

fn get_name_of(kind: Fmi3Type) -> &'static str {
    match kind {
        Fmi3Type::Float64 => "fmi3GetFloat64",
        Fmi3Type::Float32 => "fmi3GetFloat32",
        Fmi3Type::Int8 => "fmi3GetInt8",
        Fmi3Type::UInt8 => "fmi3GetUInt8",
        Fmi3Type::Int16 => "fmi3GetInt16",
        Fmi3Type::UInt16 => "fmi3GetUInt16",
        Fmi3Type::Int32 => "fmi3GetInt32",
        Fmi3Type::UInt32 => "fmi3GetUInt32",
        Fmi3Type::Int64 | Fmi3Type::Enumeration => "fmi3GetInt64",
        Fmi3Type::UInt64 => "fmi3GetUInt64",
        Fmi3Type::Boolean => "fmi3GetBoolean",
        Fmi3Type::Binary => "fmi3GetBinary",
        _ => "fmi3GetString",
    }
}

fn set_name_of(kind: Fmi3Type) -> &'static str {
    match kind {
        Fmi3Type::Float64 => "fmi3SetFloat64",
        Fmi3Type::Float32 => "fmi3SetFloat32",
        Fmi3Type::Int8 => "fmi3SetInt8",
        Fmi3Type::UInt8 => "fmi3SetUInt8",
        Fmi3Type::Int16 => "fmi3SetInt16",
        Fmi3Type::UInt16 => "fmi3SetUInt16",
        Fmi3Type::Int32 => "fmi3SetInt32",
        Fmi3Type::UInt32 => "fmi3SetUInt32",
        Fmi3Type::Int64 | Fmi3Type::Enumeration => "fmi3SetInt64",
        Fmi3Type::UInt64 => "fmi3SetUInt64",
        Fmi3Type::Boolean => "fmi3SetBoolean",
        Fmi3Type::Binary => "fmi3SetBinary",
        _ => "fmi3SetString",
    }
}

/// A C value of a word type and its word (`crate::word`).
trait Word: Copy {
    fn word(self) -> u64;
    /// The value of a word known to be in range.
    fn from_word(word: u64) -> Self;
}

macro_rules! integer_word {
    ($($t:ty),+) => {$(
        impl Word for $t {
            fn word(self) -> u64 {
                // Sign- or zero-extended, as `crate::word` says.
                i128::from(self) as u64
            }
            fn from_word(word: u64) -> Self {
                word as $t
            }
        }
    )+};
}
integer_word!(i8, u8, i16, u16, u32, i64, u64);

impl Word for f32 {
    fn word(self) -> u64 {
        f64::from(self).to_bits()
    }
    fn from_word(word: u64) -> Self {
        f64::from_bits(word) as f32
    }
}
