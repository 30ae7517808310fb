//! What an `fmi3Instance` points to.
use crate::error::{CallError, Success};
use crate::ffi::*;
use crate::logging::{Category, Logger};
use crate::state::{Function, Interface, State};
use crate::variables::{Float64Slot, Index};
use fmi_model::prepared::{PreparedGet, PreparedSet};
use fmi_model::{Level, Log, Model, ModelError};
use serde::{Deserialize, Serialize};
use std::any::TypeId;
use std::collections::HashSet;
use std::ffi::CString;

/// Everything an FMU state copies: the model and the simulation bookkeeping.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(bound = "M: Model")]
pub struct Core<M> {
    pub model: M,
    pub state: State,
    pub time: f64,
    pub start_time: f64,
    pub stop_time: Option<f64>,
    /// The model asked to end the simulation.
    pub terminated: bool,
}

impl<M: Model> Core<M> {
    pub fn fresh() -> Core<M> {
        Core {
            model: M::default(),
            state: State::Instantiated,
            time: 0.0,
            start_time: 0.0,
            stop_time: None,
            terminated: false,
        }
    }
}

/// First field of every instance: a pointer to anything else is refused (best effort).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(C)]
pub struct Tag {
    magic: u64,
    model: TypeId,
}

const MAGIC: u64 = u64::from_le_bytes(*b"fmi3inst");

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
    /// Must stay the first field (see [`Tag`]).
    pub tag: Tag,
    pub core: Core<M>,
    /// Something changed since the last `calculate_values`.
    pub dirty: bool,
    pub logger: Logger,
    pub interface: Interface,
    pub token: uuid::Uuid,
    pub index: Index,
    /// The Float64 declarations by row, ready for the exchange.
    pub float64: Box<[Option<Float64Slot<M>>]>,
    /// The last lists of references set and read as Float64, looked up.
    pub prepared_set: PreparedSet<M>,
    pub prepared_get: PreparedGet<M>,
    /// Keeps the strings returned by `fmi3GetString` alive until its next call.
    pub returned_strings: Vec<CString>,
    /// Addresses of the FMU states handed out and not yet freed.
    pub fmu_states: HashSet<usize>,
}

impl<M: Model> Instance<M> {
    pub fn new(logger: Logger, interface: Interface) -> Instance<M> {
        Instance {
            tag: Tag::of::<M>(),
            core: Core::fresh(),
            dirty: true,
            logger,
            interface,
            token: crate::description::interface_uuid::<M>(),
            index: Index::new::<M>(),
            float64: Float64Slot::table(),
            prepared_set: PreparedSet::default(),
            prepared_get: PreparedGet::default(),
            returned_strings: Vec::new(),
            fmu_states: HashSet::new(),
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

    /// Passes a model's messages to the logger; a warning makes the status `fmi3Warning`.
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
                Level::Info => (fmi3OK, Category::StatusOk),
                Level::Warning => (fmi3Warning, Category::StatusWarning),
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

    /// A failure of the model itself: the instance is then in state Error.
    pub fn model_failure(&mut self, error: ModelError) -> CallError {
        self.core.state = State::Error;
        CallError::Model(describe_model_error::<M>(&error))
    }
}

/// `error` in the master's words: a field becomes the variable declared for it.
pub fn describe_model_error<M: Model>(error: &ModelError) -> String {
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
    let name = M::declarations()
        .iter()
        .find(|d| d.has_field(field))
        .map_or(*field, |d| d.name);
    let element = index.map(|i| format!("[{}]", i + 1)).unwrap_or_default();
    format!("{kind} {name}{element} = {value}: {reason}")
}
