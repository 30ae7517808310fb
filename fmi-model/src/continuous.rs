//! The hook for Model Exchange: a model whose state is continuous exposes it, its
//! derivatives and its events, and a layer lets the master's solver integrate it.
//!
//! Declared here so that the FMI 2.0 and 3.0 layers (and a test driver with a fixed-step
//! integrator of its own) program against one interface; the plant implements it. A model
//! without it is exported for Co-Simulation only, and the layers answer the Model Exchange
//! functions with an error status and a log line.
use crate::declaration::Dependencies;
use crate::model::{Log, Model, ModelError};

/// What an event update found.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct EventUpdate {
    /// The model asks to end the simulation (e.g. touchdown).
    pub terminate: bool,
    /// The continuous states were changed by the update (the master must re-read them).
    pub states_changed: bool,
    /// The nominals changed.
    pub nominals_changed: bool,
}

/// Continuous states, derivatives and event indicators of a [`Model`].
///
/// Vectors have fixed lengths for a given set of parameters, known after
/// `exit_initialization` (e.g. actuator lag states only when a lag is configured).
pub trait ContinuousModel: Model {
    /// The continuous states as declarations, in state-vector order, each with the
    /// declaration of its derivative (same shape): `(state, derivative)` names. A layer
    /// writes them into its model description (FMI 2.0 `derivative` attributes and
    /// `ModelStructure/Derivatives`); their element count is the state count.
    const STATE_DERIVATIVES: &'static [(&'static str, &'static str)];
    /// Number of event indicators, fixed for the model description.
    const EVENT_INDICATORS: usize;
    /// The scalar declarations that publish the event indicators (FMI 3.0 declares each
    /// indicator as a variable), in indicator order.
    const EVENT_INDICATOR_VARIABLES: &'static [&'static str];

    /// Whether the model declares the dependencies of its outputs and state derivatives on
    /// the continuous states ([`state_dependencies`](Self::state_dependencies),
    /// [`derivative_input_dependencies`](Self::derivative_input_dependencies)). A master
    /// builds the sparsity of its Jacobians from the model description's `dependencies`, so
    /// a model that provides derivatives declares them. Without (the default) the
    /// description says nothing of the states: an output lists its inputs only, a state
    /// derivative no list (it depends on every known).
    const DECLARES_STATE_DEPENDENCIES: bool = false;

    /// Under Model Exchange, the continuous states (names of [`STATE_DERIVATIVES`]' states,
    /// every element) that `unknown` (an output or a state derivative, by declaration name)
    /// depends on (read when [`DECLARES_STATE_DEPENDENCIES`](Self::DECLARES_STATE_DEPENDENCIES)).
    /// The default, every state, is always safe.
    ///
    /// [`STATE_DERIVATIVES`]: ContinuousModel::STATE_DERIVATIVES
    fn state_dependencies(_unknown: &str) -> Option<&'static [&'static str]> {
        None
    }

    /// The inputs the state derivative `derivative` (a declaration name) depends on (read
    /// when [`DECLARES_STATE_DEPENDENCIES`](Self::DECLARES_STATE_DEPENDENCIES)); the default,
    /// every input, is always safe. (An output's inputs are [`Model::output_dependencies`].)
    fn derivative_input_dependencies(_derivative: &str) -> Dependencies {
        Dependencies::AllInputs
    }

    /// Element-level refinement of the declared dependencies, for a layer that writes
    /// scalars (FMI 2.0; FMI 3.0 lists whole arrays): whether element `unknown_element` of
    /// `unknown` (an output or a state derivative) depends on element `known_element` of
    /// `known` (a continuous state or an input), where the declarations say it may (read when
    /// [`DECLARES_STATE_DEPENDENCIES`](Self::DECLARES_STATE_DEPENDENCIES)). Default: every
    /// element.
    fn depends_on_element(
        _unknown: &str,
        _unknown_element: usize,
        _known: &str,
        _known_element: usize,
    ) -> bool {
        true
    }

    /// Number of continuous states.
    fn state_count(&self) -> usize;
    /// Number of event indicators.
    fn event_indicator_count(&self) -> usize;
    /// Set the time of the model (between solver steps).
    fn set_time(&mut self, t: f64);
    /// Copy the states into `x` (`x.len() == state_count()`).
    fn states(&self, x: &mut [f64]);
    /// Take the states from the solver.
    fn set_states(&mut self, x: &[f64]) -> Result<(), ModelError>;
    /// Whether the model can evaluate the state vector `x` (of the right length, every
    /// element finite): a vector whose derivatives or outputs would not be finite is refused
    /// here, naming the element (`InvalidInput` with the declaration's field), before
    /// `set_states` sees it; the instance stays usable. Default: every finite vector.
    fn check_state_vector(&self, _x: &[f64]) -> Result<(), ModelError> {
        Ok(())
    }
    /// Nominal magnitudes of the states (for the solver's error control).
    fn nominals(&self, nominal: &mut [f64]);
    /// Time derivatives of the states at the current time, states and inputs.
    fn derivatives(&mut self, dx: &mut [f64]) -> Result<(), ModelError>;
    /// Event indicators (an event is where one changes sign).
    fn event_indicators(&mut self, z: &mut [f64]) -> Result<(), ModelError>;
    /// Handle an event at the current time (e.g. freeze the touchdown outputs).
    fn update_discrete_states(&mut self, log: &mut Log) -> Result<EventUpdate, ModelError>;
}

/// A vector from a solver has the length the model expects: else the refusal to log.
pub fn check_length<M: ContinuousModel>(
    what: &str,
    given: usize,
    expected: usize,
) -> Result<(), String> {
    if given == expected {
        Ok(())
    } else {
        Err(format!(
            "{given} {what} given, {} has {expected}",
            M::MODEL_IDENTIFIER
        ))
    }
}

/// A state vector a solver sets: the model's length, every element finite; else the
/// refusal to log (the model then never sees it).
pub fn check_states<M: ContinuousModel>(model: &M, x: &[f64]) -> Result<(), String> {
    check_length::<M>("states", x.len(), model.state_count())?;
    if let Some(i) = x.iter().position(|v| !v.is_finite()) {
        return Err(format!("state {i} is {}: not finite", x[i]));
    }
    model
        .check_state_vector(x)
        .map_err(|e| state_refusal::<M>(&e))
}

/// A refusal of [`ContinuousModel::check_state_vector`] in the master's words: the field
/// becomes the declared variable, its element 1-based (`state attitude_state[2] = ...`).
fn state_refusal<M: Model>(error: &ModelError) -> String {
    let (field, index, value, reason) = match error {
        ModelError::InvalidInput {
            field,
            index,
            value,
            reason,
        }
        | ModelError::InvalidParameter {
            field,
            index,
            value,
            reason,
        } => (field, index, value, reason),
        ModelError::Other(text) | ModelError::Refused(text) => return text.clone(),
    };
    let name = M::declarations()
        .iter()
        .find(|d| d.has_field(field))
        .map_or(*field, |d| d.name);
    let element = index.map(|i| format!("[{}]", i + 1)).unwrap_or_default();
    format!("state {name}{element} = {value}: {reason}")
}
