//! What an instance handle leads to: the model, its bookkeeping, and what the instance
//! keeps for the master (logger, the Real exchange table, returned strings, FMU states).
use crate::fmu_state::FmuStates;
use crate::logging::{Category, Logger};
use crate::prepared::RealTable;
use crate::state::{Interface, State};
use crate::status::{CallError, Status, Success};
use crate::version::{Abi, Function};
use crate::warnings::WarningTally;
use fmi_model::{Level, Log, Model, ModelError};
use serde::{Deserialize, Serialize};
use std::any::TypeId;
use std::ffi::CString;
use std::os::raw::c_char;

/// Everything an FMU state copies: the model and the simulation bookkeeping. Callbacks,
/// names and logging flags belong to the instance and are not part of an FMU state.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(bound = "M: Model")]
pub struct Core<M> {
    pub model: M,
    pub state: State,
    /// The interface the state was taken in: a state of the other one is refused.
    pub interface: Interface,
    /// The current communication point (Model Exchange: the time last set).
    pub time: f64,
    pub start_time: f64,
    pub stop_time: Option<f64>,
    /// Where the last step ended (its end, or where it stopped early).
    pub last_successful_time: f64,
    /// The model asked to end the simulation.
    pub terminated: bool,
}

impl<M: Model> Core<M> {
    /// A freshly instantiated model: `M::default()`, which holds every start value.
    pub fn fresh(interface: Interface) -> Core<M> {
        Core {
            model: M::default(),
            state: State::Instantiated,
            interface,
            time: 0.0,
            start_time: 0.0,
            stop_time: None,
            last_successful_time: 0.0,
            terminated: false,
        }
    }
}

/// First field of every instance, so that a live instance of another model or version
/// linked into the same process is refused instead of being used as this one. Freed and
/// unknown handles never get this far: the version's registry refuses them first.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(C)]
pub struct Tag {
    magic: u64,
    model: TypeId,
}

const MAGIC: u64 = u64::from_le_bytes(*b"fmi-inst");

impl Tag {
    pub fn of<M: Model, A: Abi>() -> Tag {
        Tag {
            magic: MAGIC,
            model: TypeId::of::<(M, A)>(),
        }
    }

    /// Whether this is the tag of an instance of `M` and `A`. Only the type is compared:
    /// the registry has already found the address live in `A`'s table, so it is an instance
    /// of some model of `A`, whose tag was written whole at its creation.
    #[inline(always)]
    pub fn is_of<M: Model, A: Abi>(&self) -> bool {
        self.model == TypeId::of::<(M, A)>()
    }

    pub fn cleared() -> Tag {
        Tag {
            magic: 0,
            model: TypeId::of::<()>(),
        }
    }
}

/// What the master chose at instantiation beyond the interface (FMI 3.0 Co-Simulation;
/// FMI 2.0 instances keep the defaults).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Options {
    /// The master accepts a step that returns before its end at an event.
    pub early_return_allowed: bool,
    /// The master drives Event Mode in Co-Simulation.
    pub event_mode_used: bool,
}

#[repr(C)]
pub struct Instance<M: Model, A: Abi> {
    /// Must stay the first field (see [`Tag`]).
    pub tag: Tag,
    pub core: Core<M>,
    /// Set by every call that can change values; `calculate_values` runs before the next get.
    pub dirty: bool,
    pub logger: Logger<A>,
    pub options: Options,
    /// The model description's GUID / instantiation token (carried by serialized states).
    pub uuid: uuid::Uuid,
    pub resource_location: Option<CString>,
    /// The version's view of the variables.
    pub view: A::View<M>,
    /// Every Real element by value reference, for the gets and sets.
    pub reals: RealTable<M>,
    /// Keeps the strings returned by a string get alive until the next one.
    pub returned_strings: Vec<CString>,
    /// The FMU states handed out by this instance and not yet freed.
    pub fmu_states: FmuStates<M>,
    /// The model's warnings of this run, each kind logged once (not part of an FMU state:
    /// what the master was told belongs to its session).
    pub warnings: WarningTally,
}

impl<M: Model, A: Abi> Instance<M, A> {
    pub fn new(
        logger: Logger<A>,
        interface: Interface,
        options: Options,
        resource_location: Option<CString>,
    ) -> Instance<M, A> {
        Instance {
            tag: Tag::of::<M, A>(),
            core: Core::fresh(interface),
            dirty: true,
            logger,
            options,
            uuid: A::interface_uuid::<M>(),
            resource_location,
            view: A::view::<M>(),
            reals: RealTable::default(),
            returned_strings: Vec::new(),
            fmu_states: FmuStates::default(),
            warnings: WarningTally::default(),
        }
    }

    pub fn interface(&self) -> Interface {
        self.core.interface
    }

    /// Runs `calculate_values` if anything changed since the last get.
    #[inline]
    pub fn refresh(&mut self, function: A::Function) -> Success {
        if !self.dirty {
            return Success::Ok;
        }
        let mut log = Log::default();
        self.core.model.calculate_values(&mut log);
        self.dirty = false;
        self.forward(function, &log)
    }

    /// Passes a model's messages to the logger; a warning logged makes the call's status
    /// Warning. A warning of a kind already logged in this run is counted, not logged again
    /// (see [`crate::warnings`]), and leaves the status OK: both standards tie a Warning to a
    /// message the master is to show, and this one was shown; the summary comes at
    /// termination.
    #[inline(always)]
    pub fn forward(&mut self, function: A::Function, log: &Log) -> Success {
        if log.entries.is_empty() {
            return Success::Ok;
        }
        self.forward_entries(function, log)
    }

    /// [`forward`](Self::forward) of a log that has something to say (rare: out of line).
    #[cold]
    #[inline(never)]
    fn forward_entries(&mut self, function: A::Function, log: &Log) -> Success {
        let time_s = self.core.time;
        let mut warned = false;
        for (level, message) in &log.entries {
            let (status, category) = match level {
                Level::Info => (Status::Ok, Category::StatusOk),
                Level::Warning => (Status::Warning, Category::StatusWarning),
            };
            if *level == Level::Warning {
                if self.warnings.first_of_its_kind(message, time_s) {
                    warned = true;
                    self.logger.log(
                        status,
                        category,
                        &format!(
                            "{}: {message} [first at t = {time_s} s; repeats are counted, not \
                             logged, until termination]",
                            function.name()
                        ),
                    );
                }
            } else if self.logger.is_on(category) {
                self.logger
                    .log(status, category, &format!("{}: {message}", function.name()));
            }
        }
        if warned {
            Success::Warning
        } else {
            Success::Ok
        }
    }

    /// Hands the master pointers to `strings`, kept alive until the next string get (or the
    /// instance's end), as both standards require of returned strings.
    pub fn hand_out_strings(&mut self, strings: Vec<CString>, out: &mut [*const c_char]) {
        self.returned_strings = strings;
        for (value, s) in out.iter_mut().zip(&self.returned_strings) {
            *value = s.as_ptr();
        }
    }

    /// A failure of the model itself: the instance is then in state Error, as both
    /// standards' state machines say (reset, restoring an FMU state or freeing lead on).
    pub fn fail(&mut self, error: impl Into<CallError>) -> CallError {
        self.core.state = State::Error;
        error.into()
    }

    /// A model's failure, its field named as the variable declared for it; the instance
    /// goes to state Error unless the model only refused the request
    /// ([`ModelError::Refused`]: nothing changed, so nothing needs recovering from).
    pub fn model_failure(&mut self, error: ModelError) -> CallError {
        if !matches!(error, ModelError::Refused(_)) {
            self.core.state = State::Error;
        }
        CallError::Model(crate::describe_model_error::<M>(&error))
    }
}
