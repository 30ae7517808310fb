//! What a model implements: a variable table and a step function. A model never sees a
//! pointer, a C string or an FMI state; the layer (see `abi`) does all of that.
use crate::variable::Variable;
use serde::{de::DeserializeOwned, Serialize};

/// Severity of a message a model reports; the layer maps it to an FMI status and a log category.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Level {
    /// Informational; logged under `logStatusOK` when debug logging is on.
    Info,
    /// Logged under `logStatusWarning`; the call returns `fmi2Warning`.
    Warning,
}

/// Messages a model produces during a call. The layer forwards them to the FMI logger
/// after the call and turns a warning into `fmi2Warning`.
#[derive(Debug, Default)]
pub struct Log {
    pub entries: Vec<(Level, String)>,
}

impl Log {
    pub fn info(&mut self, msg: impl Into<String>) {
        self.entries.push((Level::Info, msg.into()));
    }
    pub fn warning(&mut self, msg: impl Into<String>) {
        self.entries.push((Level::Warning, msg.into()));
    }
    pub fn has_warning(&self) -> bool {
        self.entries.iter().any(|(l, _)| *l == Level::Warning)
    }
}

/// How a successful `do_step` ended.
#[derive(Debug, Clone, PartialEq)]
pub enum StepEnd {
    /// The step reached `t + h`.
    Complete,
    /// The model stopped early at `time` (`t <= time <= t + h`), e.g. on touchdown. The layer
    /// answers `fmi2Discard`, reports `fmi2LastSuccessfulTime = time`, and `fmi2Terminated`
    /// when `terminated` is set; `reason` is logged.
    Stopped {
        time: f64,
        terminated: bool,
        reason: String,
    },
}

/// A model's refusal. The layer logs it (naming the FMI function) and returns `fmi2Error`.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ModelError {
    #[error("parameter {name} = {value}: {reason}")]
    InvalidParameter {
        name: &'static str,
        value: String,
        reason: String,
    },
    #[error("input {name} = {value}: {reason}")]
    InvalidInput {
        name: &'static str,
        value: String,
        reason: String,
    },
    #[error("{0}")]
    Other(String),
}

/// Default experiment written to the model description.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Experiment {
    pub start_time: f64,
    pub stop_time: f64,
    pub step_size: f64,
    pub tolerance: Option<f64>,
}

/// An FMI 2.0 co-simulation model. `Default` gives a fresh instance before the start values
/// of the variable table are applied; `Clone` + serde give FMU-state copies and serialization.
pub trait Model: Default + Clone + Send + Serialize + DeserializeOwned + 'static {
    /// `modelIdentifier` (also the shared-library name in the FMU).
    const MODEL_IDENTIFIER: &'static str;
    /// `modelName`/`description` in the model description.
    const MODEL_NAME: &'static str;
    const DESCRIPTION: &'static str;
    const DEFAULT_EXPERIMENT: Experiment;
    /// Bumped by hand when the serialized state of the model changes shape.
    const STATE_VERSION: u32 = 1;

    /// The variable table: each variable declared exactly once.
    fn variables() -> &'static [Variable<Self>];

    /// Enumeration types used by `Variable::enumeration` entries (name, items as (name, value, description)).
    fn enumeration_types() -> &'static [EnumerationDecl] {
        &[]
    }

    /// The inputs `output` depends on within one communication point (direct feedthrough),
    /// written to `ModelStructure/Outputs`. The default, every input, is always safe; a
    /// model whose outputs are pure functions of its state says `NoInputs`, which lets a
    /// master close a loop through it without an algebraic loop.
    fn output_dependencies(_output: &str) -> Dependencies {
        Dependencies::AllInputs
    }

    /// Recompute outputs (and calculated parameters) from the current parameters, inputs and
    /// state, so that a `get` sees consistent values (outputs with direct feedthrough, initial
    /// unknowns in initialization mode). The layer calls it before a `fmi2Get*` whenever a
    /// `fmi2Set*`, `fmi2DoStep`, `fmi2SetFMUstate` or mode change happened since the last call.
    /// Must not fail; a warning in `log` turns the get's status into `fmi2Warning`.
    fn calculate_values(&mut self, _log: &mut Log) {}

    /// `fmi2ExitInitializationMode`: check parameters (naming the offending one) and set up the
    /// state from them. `start_time` is the value given to `fmi2SetupExperiment`.
    fn exit_initialization(&mut self, start_time: f64, log: &mut Log) -> Result<(), ModelError>;

    /// Advance from `t` to `t + h` (`h > 0`, all inputs finite, checked by the layer).
    fn do_step(&mut self, t: f64, h: f64, log: &mut Log) -> Result<StepEnd, ModelError>;
}

/// Direct feedthrough of one output, see [`Model::output_dependencies`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Dependencies {
    AllInputs,
    NoInputs,
    /// These inputs, by name.
    Inputs(&'static [&'static str]),
}

/// An enumeration type (`<SimpleType><Enumeration>`).
#[derive(Debug, Clone, Copy)]
pub struct EnumerationDecl {
    pub name: &'static str,
    pub description: &'static str,
    pub items: &'static [(&'static str, i32, &'static str)],
}
