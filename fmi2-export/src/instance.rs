//! What an `fmi2Component` points to.
use crate::error::{CallError, Success};
use crate::ffi::{fmi2OK, fmi2Warning};
use crate::index::VariableIndex;
use crate::logging::{Category, Logger};
use crate::model::{Level, Log, Model, ModelError};
use crate::state::{Function, State};
use crate::variable::Variable;
use fmi_model::prepared::{PreparedGet, PreparedSet};
use serde::{Deserialize, Serialize};
use std::any::TypeId;
use std::collections::HashSet;
use std::ffi::CString;

/// Everything an FMU state copies: the model and the simulation bookkeeping. Callbacks,
/// names and logging flags belong to the instance and are not part of an FMU state.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(bound = "M: Model")]
pub struct Core<M> {
    pub model: M,
    pub state: State,
    /// The current communication point.
    pub time: f64,
    pub start_time: f64,
    pub stop_time: Option<f64>,
    /// `fmi2LastSuccessfulTime`.
    pub last_successful_time: f64,
    /// `fmi2Terminated`: the model asked to end the simulation.
    pub terminated: bool,
}

impl<M: Model> Core<M> {
    /// A freshly instantiated model: `M::default()`, which holds every start value.
    pub fn fresh() -> Core<M> {
        Core {
            model: M::default(),
            state: State::Instantiated,
            time: 0.0,
            start_time: 0.0,
            stop_time: None,
            last_successful_time: 0.0,
            terminated: false,
        }
    }
}

/// First field of every instance, so that a live instance of another model linked into the
/// same process is refused instead of being used as an `Instance<M>`. Freed and unknown
/// pointers never get this far: the layer's registry of live instances refuses them first.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(C)]
pub struct Tag {
    magic: u64,
    model: TypeId,
}

const MAGIC: u64 = u64::from_le_bytes(*b"fmi2inst");

impl Tag {
    pub fn of<M: Model>() -> Tag {
        Tag {
            magic: MAGIC,
            model: TypeId::of::<M>(),
        }
    }

    pub fn cleared() -> Tag {
        Tag {
            magic: 0,
            model: TypeId::of::<()>(),
        }
    }
}

#[repr(C)]
pub struct Instance<M: Model> {
    pub tag: Tag,
    pub core: Core<M>,
    /// Set by every call that can change values; `calculate_values` runs before the next get.
    pub dirty: bool,
    pub logger: Logger,
    pub guid: uuid::Uuid,
    pub resource_location: Option<CString>,
    /// The FMI 2.0 scalars of `M`.
    pub table: Box<[Variable<M>]>,
    pub index: VariableIndex<M>,
    /// The last lists of references set and read as Reals, looked up.
    pub prepared_set: PreparedSet<M>,
    pub prepared_get: PreparedGet<M>,
    /// Keeps the strings returned by `fmi2GetString` alive until the next call of it.
    pub returned_strings: Vec<CString>,
    /// Addresses of the FMU states handed out by this instance and not yet freed.
    pub fmu_states: HashSet<usize>,
    /// Instantiated as `fmi2ModelExchange` (else Co-Simulation): decides where
    /// `fmi2ExitInitializationMode` leads.
    pub model_exchange: bool,
}

impl<M: Model> Instance<M> {
    pub fn new(
        logger: Logger,
        guid: uuid::Uuid,
        resource_location: Option<CString>,
        model_exchange: bool,
    ) -> Instance<M> {
        let table = crate::variables::<M>().into_boxed_slice();
        Instance {
            tag: Tag::of::<M>(),
            core: Core::fresh(),
            dirty: true,
            logger,
            guid,
            resource_location,
            index: VariableIndex::new(&table),
            prepared_set: PreparedSet::default(),
            prepared_get: PreparedGet::default(),
            table,
            returned_strings: Vec::new(),
            fmu_states: HashSet::new(),
            model_exchange,
        }
    }

    /// Runs `calculate_values` if anything changed since the last get.
    pub fn refresh(&mut self, function: Function) -> Success {
        if !self.dirty {
            return Success::Ok;
        }
        let mut log = Log::default();
        self.core.model.calculate_values(&mut log);
        self.dirty = false;
        self.forward(function, &log)
    }

    /// Passes a model's messages to the logger; a warning makes the call's status `fmi2Warning`.
    #[inline(always)]
    pub fn forward(&self, function: Function, log: &Log) -> Success {
        if log.entries.is_empty() {
            return Success::Ok;
        }
        self.forward_entries(function, log)
    }

    /// [`forward`](Self::forward) of a log that has something to say (rare: out of line).
    #[cold]
    #[inline(never)]
    fn forward_entries(&self, function: Function, log: &Log) -> Success {
        for (level, message) in &log.entries {
            let (status, category) = match level {
                Level::Info => (fmi2OK, Category::StatusOk),
                Level::Warning => (fmi2Warning, Category::StatusWarning),
            };
            if self.logger.is_on(category) {
                self.logger
                    .log(status, category, &format!("{}: {message}", function.name()));
            }
        }
        if log.has_warning() {
            Success::Warning
        } else {
            Success::Ok
        }
    }

    /// A model failure: per the standard the instance is then in state Error (from which
    /// `fmi2Reset`, `fmi2SetFMUstate` or `fmi2FreeInstance` lead on).
    pub fn fail(&mut self, error: impl Into<CallError>) -> CallError {
        self.core.state = State::Error;
        error.into()
    }

    /// A model's refusal, its field named as the variable declared for it.
    pub fn model_failure(&mut self, error: ModelError) -> CallError {
        self.core.state = State::Error;
        CallError::Model(describe_model_error(&self.table, &error))
    }
}

/// `error` in the master's words: the field it names becomes the declared variable (FMI 2.0
/// scalar name of the element, e.g. `inertia_body[2]`). A name that is no declared field is
/// kept as the model wrote it.
pub fn describe_model_error<M: Model>(table: &[Variable<M>], error: &ModelError) -> String {
    let (kind, field, index, value, reason) = match error {
        ModelError::InvalidParameter {
            field,
            index,
            value,
            reason,
        } => ("parameter", field, index, value, reason),
        ModelError::InvalidInput {
            field,
            index,
            value,
            reason,
        } => ("input", field, index, value, reason),
        ModelError::Other(text) => return text.clone(),
    };
    let declarations = M::declarations();
    let declared = declarations
        .iter()
        .position(|d| d.has_field(field))
        .and_then(|d| {
            let element = index.unwrap_or(0);
            let scalars = table.iter().filter(|v| v.declaration == d);
            match index {
                // The whole vector (e.g. a quaternion refused for its norm): its base name.
                None if declarations[d].shape().len() > 1 => Some(declarations[d].name.into()),
                _ => scalars
                    .into_iter()
                    .find(|v| v.element() == element)
                    .map(|v| v.name()),
            }
        });
    let name = match declared {
        Some(name) => name.to_string(),
        None => match index {
            Some(i) => format!("{field}[{i}]"),
            None => field.to_string(),
        },
    };
    format!("{kind} {name} = {value}: {reason}")
}
