//! A restored FMU state (`fmi2SetFMUstate`, `fmi2DeSerializeFMUstate`) is checked before it
//! replaces the instance's: a crafted buffer carries a valid header and checksum as easily
//! as a genuine one, so only a state the instance could have reached is accepted. A refusal
//! names the field at fault and leaves the instance as it was. The checks themselves are
//! version-neutral ([`fmi_model::restored`]), shared with the FMI 3.0 layer.
use crate::error::CallError;
use crate::instance::{describe_model_error, Core};
use crate::model::Model;
use crate::state::State;
use crate::variable::Variable;
use fmi_model::restored::{check_bookkeeping, check_declared_values, Bookkeeping};

/// `Ok` if `core` is a state an instance of `M` could have been in.
pub fn validate<M: Model>(table: &[Variable<M>], core: &Core<M>) -> Result<(), CallError> {
    let bookkeeping = Bookkeeping {
        time: core.time,
        start_time: core.start_time,
        last_successful_time: Some(core.last_successful_time),
        stop_time: core.stop_time,
        fatal: core.state == State::Fatal,
    };
    check_bookkeeping(&bookkeeping, crate::abi::TIME_TOLERANCE)
        .and_then(|()| check_declared_values(&core.model))
        .map_err(CallError::InvalidArgument)?;
    // The model's own invariants (validated parameters, admissible state).
    let initialized = !matches!(core.state, State::Instantiated | State::InitializationMode);
    core.model.validate_restored(initialized).map_err(|e| {
        CallError::Model(format!(
            "FMU state refused: {}",
            describe_model_error(table, &e)
        ))
    })
}
