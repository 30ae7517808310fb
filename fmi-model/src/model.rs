//! What a model implements. A model never sees a pointer, a C string, an FMI version or an
//! FMI state; the layers do all of that.
use crate::declaration::{Declaration, Dependencies};
use serde::{de::DeserializeOwned, Serialize};

/// Severity of a message a model reports; a layer maps it to a status and a log category.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Level {
    /// Informational; logged when debug logging is on.
    Info,
    /// Always logged; the call returns a warning status.
    Warning,
}

/// Messages a model produces during a call; the layer forwards them to the master's logger
/// after the call and turns a warning into a warning status.
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
    #[inline]
    pub fn has_warning(&self) -> bool {
        self.entries.iter().any(|(l, _)| *l == Level::Warning)
    }
}

/// How a successful `do_step` ended.
#[derive(Debug, Clone, PartialEq)]
pub enum StepEnd {
    /// The step reached `t + h`.
    Complete,
    /// The model stopped early at `time` (`t <= time <= t + h`), e.g. on touchdown; the
    /// layer reports it as its standard says; `terminated` ends the simulation; `reason`
    /// is logged.
    Stopped {
        time: f64,
        terminated: bool,
        reason: String,
    },
}

/// A model's refusal. The layer logs it (naming the function and, for a field, the
/// variable declared for it) and returns an error status.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ModelError {
    /// The parameter stored in `field` (a path as in the declaration's `field`, e.g.
    /// `inertia_body_kgm2`; `index` is the 0-based element of a vector) is refused.
    #[error("parameter {field}{} = {value}: {reason}", index.map(|i| format!("[{i}]")).unwrap_or_default())]
    InvalidParameter {
        field: &'static str,
        index: Option<usize>,
        value: String,
        reason: String,
    },
    /// As [`ModelError::InvalidParameter`], for an input.
    #[error("input {field}{} = {value}: {reason}", index.map(|i| format!("[{i}]")).unwrap_or_default())]
    InvalidInput {
        field: &'static str,
        index: Option<usize>,
        value: String,
        reason: String,
    },
    /// The model could not compute what was asked and changed nothing (e.g. a step longer
    /// than it can take at once): the layer refuses the call and the instance stays as it
    /// was, in its state, usable.
    #[error("{0}")]
    Refused(String),
    /// The model failed; the layer moves the instance to state Error.
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

/// A model, for every FMI version and interface type. `Default` is a fresh instance and
/// holds every start value (layers read start values from it, never from a second
/// literal); `Clone` + serde give FMU-state copies and serialization.
///
/// Model Exchange is the optional [`ContinuousModel`](crate::ContinuousModel) on top.
pub trait Model: Default + Clone + Send + Serialize + DeserializeOwned + 'static {
    /// `modelIdentifier` (also the shared-library name in the FMU).
    const MODEL_IDENTIFIER: &'static str;
    const MODEL_NAME: &'static str;
    /// The model description's `version`: the FMU crate's own `env!("CARGO_PKG_VERSION")`,
    /// so a released FMU says which release it is.
    const VERSION: &'static str;
    const DESCRIPTION: &'static str;
    const DEFAULT_EXPERIMENT: Experiment;
    /// Bumped by hand when the serialized state of the model changes shape.
    const STATE_VERSION: u32 = 1;

    /// Every variable, declared once.
    fn declarations() -> &'static [Declaration<Self>];

    /// The groups of variables a tool connects as one (FMI 3.0 terminals); none by default.
    fn terminals() -> &'static [crate::Terminal] {
        &[]
    }

    /// The inputs `output` (a declaration name) depends on within one step. The default,
    /// every input, is always safe; a model whose outputs are functions of its state says
    /// `NoInputs`, which lets a master close a loop through it without an algebraic loop.
    fn output_dependencies(_output: &str) -> Dependencies {
        Dependencies::AllInputs
    }

    /// Recompute outputs (and calculated parameters) from the current parameters, inputs and
    /// state, so that a get sees consistent values. The layer calls it before a get
    /// whenever something changed since the last call. Must not fail; a warning in `log`
    /// turns the get's status into a warning.
    fn calculate_values(&mut self, _log: &mut Log) {}

    /// End of initialization: check parameters (naming the offending field) and set up the
    /// state from them. `start_time` is the simulation's start time.
    fn exit_initialization(&mut self, start_time: f64, log: &mut Log) -> Result<(), ModelError>;

    /// A restored FMU state (set or de-serialized) is about to replace the instance's: `Ok`
    /// only if the model could have reached it. `initialized` says whether the state is past
    /// exit_initialization (the layer's state machine knows). Once initialized, every parameter passes the
    /// checks of [`exit_initialization`](Model::exit_initialization) and every state value is
    /// finite and admissible (masses, unit quaternions, ordered times, memories consistent
    /// with the parameters); the error names the field at fault. Layers have already checked
    /// their own bookkeeping and that each Real parameter and input is settable to its value.
    /// The default accepts: a model with invariants must say them here.
    fn validate_restored(&self, _initialized: bool) -> Result<(), ModelError> {
        Ok(())
    }

    /// Whether [`directional_derivative`](Model::directional_derivative) is implemented:
    /// the layers write `providesDirectionalDerivative(s)` (and FMI 3.0
    /// `providesAdjointDerivatives`) from it and refuse the calls when it is false.
    const PROVIDES_DIRECTIONAL_DERIVATIVES: bool = false;

    /// Exact directional derivative at the instance's current values (parameters, inputs,
    /// continuous states, time), changing none of them: `sensitivity[i] = sum_j
    /// d unknowns[i] / d knowns[j] * seed[j]`. Knowns are Real inputs and, under Model
    /// Exchange, continuous states; unknowns are Real outputs and, under Model Exchange,
    /// state derivatives. Computed exactly (automatic differentiation or derived by
    /// hand), never by differencing. The layer has checked the lengths, a finite seed, and
    /// that every known and unknown is of those kinds (under Co-Simulation no state and no
    /// state derivative); a model refuses (naming the variable) what it cannot
    /// differentiate, and its refusal leaves the instance as it was.
    fn directional_derivative(
        &mut self,
        _unknowns: &[crate::ScalarRef],
        _knowns: &[crate::ScalarRef],
        _seed: &[f64],
        _sensitivity: &mut [f64],
    ) -> Result<(), ModelError> {
        Err(ModelError::Refused(
            "this model provides no directional derivatives".into(),
        ))
    }

    /// Co-Simulation: advance from `t` to `t + h` (`h > 0`, inputs finite, checked by the
    /// layer).
    fn do_step(&mut self, t: f64, h: f64, log: &mut Log) -> Result<StepEnd, ModelError>;
}
