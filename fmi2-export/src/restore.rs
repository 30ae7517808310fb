//! A restored FMU state (`fmi2SetFMUstate`, `fmi2DeSerializeFMUstate`) is checked before it
//! replaces the instance's: a crafted buffer carries a valid header and checksum as easily
//! as a genuine one, so only a state the instance could have reached is accepted. A refusal
//! names the field at fault and leaves the instance as it was.
use crate::error::CallError;
use crate::instance::{describe_model_error, Core};
use crate::model::Model;
use crate::rules::check_real;
use crate::state::State;
use crate::variable::{Access, Causality, Variable};

fn refused(what: &str, value: impl std::fmt::Display, reason: &str) -> CallError {
    CallError::InvalidArgument(format!("FMU state refused: {what} = {value}: {reason}"))
}

/// `Ok` if `core` is a state an instance of `M` could have been in.
pub fn validate<M: Model>(table: &[Variable<M>], core: &Core<M>) -> Result<(), CallError> {
    // The layer's bookkeeping: finite, ordered times.
    for (what, t) in [
        ("time", core.time),
        ("start time", core.start_time),
        ("last successful time", core.last_successful_time),
    ] {
        if !t.is_finite() {
            return Err(refused(what, t, "not finite"));
        }
    }
    let tolerance =
        crate::abi::TIME_TOLERANCE * core.start_time.abs().max(core.time.abs()).max(1.0);
    if core.time < core.start_time - tolerance {
        return Err(refused("time", core.time, "before the start time"));
    }
    if core.last_successful_time > core.time + tolerance
        || core.last_successful_time < core.start_time - tolerance
    {
        return Err(refused(
            "last successful time",
            core.last_successful_time,
            "outside [start time, time]",
        ));
    }
    if let Some(stop) = core.stop_time {
        if !stop.is_finite() || stop < core.start_time {
            return Err(refused(
                "stop time",
                stop,
                "not finite or before the start time",
            ));
        }
    }
    if core.state == State::Fatal {
        return Err(refused(
            "state",
            "Fatal",
            "an unusable instance cannot be restored",
        ));
    }
    // Every Real parameter and input holds a value an fmi2SetReal would have accepted.
    for var in table {
        if let (Causality::Parameter | Causality::Input, Access::Real { min, max, .. }) =
            (var.causality, &var.access)
        {
            if let Some(value) = var.real(&core.model) {
                check_real(var, value, *min, *max)
                    .map_err(|e| CallError::InvalidArgument(format!("FMU state refused: {e}")))?;
            }
        }
    }
    // The model's own invariants (validated parameters, admissible state).
    let initialized = !matches!(core.state, State::Instantiated | State::InitializationMode);
    core.model.validate_restored(initialized).map_err(|e| {
        CallError::Model(format!(
            "FMU state refused: {}",
            describe_model_error(table, &e)
        ))
    })
}
