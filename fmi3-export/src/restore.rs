//! A restored FMU state (`fmi3SetFMUState`, `fmi3DeserializeFMUState`) is checked before it
//! replaces anything: a crafted buffer carries a valid header and checksum as easily as a
//! genuine one, so only a state the instance could have reached is accepted. The checks are
//! the FMI 2.0 layer's ([`fmi_model::restored`]); a refusal names the field at fault and
//! leaves the instance as it was.
use crate::abi::TIME_TOLERANCE;
use crate::error::CallError;
use crate::instance::{describe_model_error, Core};
use crate::state::State;
use fmi_model::restored::{check_bookkeeping, check_declared_values, Bookkeeping};
use fmi_model::Model;

/// `Ok` if `core` is a state an instance of `M` could have been in.
pub fn validate<M: Model>(core: &Core<M>) -> Result<(), CallError> {
    let bookkeeping = Bookkeeping {
        time: core.time,
        start_time: core.start_time,
        last_successful_time: None,
        stop_time: core.stop_time,
        fatal: core.state == State::Fatal,
    };
    check_bookkeeping(&bookkeeping, TIME_TOLERANCE)
        .and_then(|()| check_declared_values(&core.model))
        .map_err(CallError::InvalidArgument)?;
    // The model's own invariants (validated parameters, admissible state).
    let initialized = !matches!(core.state, State::Instantiated | State::InitializationMode);
    core.model.validate_restored(initialized).map_err(|e| {
        CallError::Model(format!(
            "FMU state refused: {}",
            describe_model_error::<M>(&e)
        ))
    })
}
