//! The Model Exchange accessors, once for both versions, for a model that implements
//! [`ContinuousModel`].
//!
//! What a master's solver hands in is checked before the model sees it (length, finite
//! elements, a time not before the start), and the model may refuse a state it cannot
//! evaluate; both leave the instance as it was, usable with a valid state. What goes out is
//! checked too: a derivative, event indicator, state or nominal that is not finite is never
//! written with status OK: the call answers Error naming the element.
use crate::instance::Instance;
use crate::state::State;
use crate::status::{CallError, Success};
use crate::version::Abi;
use crate::{describe_model_error, time_tolerance};
use fmi_model::continuous::{check_length, check_states};
use fmi_model::{readable, ContinuousModel, EventUpdate, Log};

/// The vectors a master reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Vector {
    States,
    Derivatives,
    EventIndicators,
    Nominals,
}

/// The name of element `i` of the state vector (or, `derivative`, of its derivative) as the
/// model description declares it: `attitude_state[2]`.
pub fn state_element_name<M: ContinuousModel>(i: usize, derivative: bool) -> String {
    let mut start = 0;
    for &(state, der) in M::STATE_DERIVATIVES {
        let name = if derivative { der } else { state };
        let len = M::declarations()
            .iter()
            .find(|d| d.name == state)
            .map_or(1, |d| d.shape().len());
        if i < start + len {
            return if len > 1 {
                format!("{name}[{}]", i - start + 1)
            } else {
                name.to_string()
            };
        }
        start += len;
    }
    format!("element {i}")
}

fn element_name<M: ContinuousModel>(vector: Vector, i: usize) -> String {
    match vector {
        Vector::States => format!("state {i} ({})", state_element_name::<M>(i, false)),
        Vector::Nominals => format!("nominal {i} ({})", state_element_name::<M>(i, false)),
        Vector::Derivatives => format!("derivative {i} ({})", state_element_name::<M>(i, true)),
        Vector::EventIndicators => match M::EVENT_INDICATOR_VARIABLES.get(i) {
            Some(name) => format!("event indicator {i} ({name})"),
            None => format!("event indicator {i}"),
        },
    }
}

/// The time of the model between solver steps.
pub fn set_time<M: ContinuousModel, A: Abi>(
    inst: &mut Instance<M, A>,
    time: f64,
) -> Result<Success, CallError> {
    if !time.is_finite() {
        return Err(CallError::InvalidArgument(format!(
            "time {time} is not finite"
        )));
    }
    // Against the start time, which a restored state guarantees finite: the instance's
    // own time may be what is corrupt.
    let start = inst.core.start_time;
    if time < start - time_tolerance(start) {
        return Err(CallError::InvalidArgument(format!(
            "time {} is before the start time {}",
            readable(time),
            readable(start)
        )));
    }
    inst.core.time = time;
    inst.core.model.set_time(time);
    inst.dirty = true;
    Ok(Success::Ok)
}

/// The solver's states. A vector the model cannot evaluate is refused by the model and
/// changes nothing: the instance stays in its state.
pub fn set_states<M: ContinuousModel, A: Abi>(
    inst: &mut Instance<M, A>,
    x: &[f64],
) -> Result<Success, CallError> {
    check_states(&inst.core.model, x).map_err(|reason| {
        CallError::InvalidArgument(match x.iter().position(|v| !v.is_finite()) {
            Some(i) => format!(
                "{} = {}: not finite",
                element_name::<M>(Vector::States, i),
                x[i]
            ),
            None => reason,
        })
    })?;
    inst.core
        .model
        .set_states(x)
        .map_err(|e| CallError::Model(describe_model_error::<M>(&e)))?;
    inst.dirty = true;
    Ok(Success::Ok)
}

/// One of the vectors, into `values` (of the model's length); every element finite.
pub fn read<M: ContinuousModel, A: Abi>(
    inst: &mut Instance<M, A>,
    f: A::Function,
    vector: Vector,
    values: &mut [f64],
) -> Result<Success, CallError> {
    let model = &inst.core.model;
    let (what, expected) = match vector {
        Vector::EventIndicators => ("event indicators", model.event_indicator_count()),
        Vector::Derivatives => ("derivatives", model.state_count()),
        Vector::States => ("states", model.state_count()),
        Vector::Nominals => ("nominals", model.state_count()),
    };
    check_length::<M>(what, values.len(), expected).map_err(CallError::InvalidArgument)?;
    // Outputs the derivatives depend on are the model's own: refresh first.
    let success = inst.refresh(f);
    let model = &mut inst.core.model;
    let computed = match vector {
        Vector::Derivatives => model.derivatives(values),
        Vector::EventIndicators => model.event_indicators(values),
        Vector::States => {
            model.states(values);
            Ok(())
        }
        Vector::Nominals => {
            model.nominals(values);
            Ok(())
        }
    };
    // The model could not evaluate its state: it is the state that is wrong, and the
    // master may set a valid one, so the instance stays usable.
    computed.map_err(|e| CallError::Model(describe_model_error::<M>(&e)))?;
    if let Some(i) = values.iter().position(|v| !v.is_finite()) {
        let value = values[i];
        values.fill(0.0);
        return Err(CallError::Model(format!(
            "{} = {value} at the current state: not finite; set a state the model can \
             evaluate",
            element_name::<M>(vector, i)
        )));
    }
    Ok(success)
}

/// The model's event update; the instance's terminated flag records a request to end.
pub fn update_discrete_states<M: ContinuousModel, A: Abi>(
    inst: &mut Instance<M, A>,
    f: A::Function,
) -> Result<(Success, EventUpdate), CallError> {
    let mut log = Log::default();
    let result = inst.core.model.update_discrete_states(&mut log);
    inst.dirty = true;
    let success = inst.forward(f, &log);
    let update = result.map_err(|e| inst.model_failure(e))?;
    inst.core.terminated |= update.terminate;
    Ok((success, update))
}

pub fn enter_event_mode<M: ContinuousModel, A: Abi>(
    inst: &mut Instance<M, A>,
) -> Result<Success, CallError> {
    inst.core.state = State::EventMode;
    Ok(Success::Ok)
}

pub fn enter_continuous_time_mode<M: ContinuousModel, A: Abi>(
    inst: &mut Instance<M, A>,
) -> Result<Success, CallError> {
    inst.core.state = State::ContinuousTimeMode;
    Ok(Success::Ok)
}
