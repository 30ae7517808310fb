//! FMI status as a Rust `Result`: `Ok(Success)` is `fmi2OK`/`fmi2Warning`, `Err(CallError)`
//! is `fmi2Discard`/`fmi2Error`/`fmi2Fatal` together with the one log line that explains it.
use crate::ffi::{fmi2Discard, fmi2Error, fmi2OK, fmi2Status, fmi2Warning};
use crate::state::State;
use fmi_model::snapshot::SnapshotError;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Success {
    Ok,
    Warning,
}

impl Success {
    pub fn status(self) -> fmi2Status {
        match self {
            Success::Ok => fmi2OK,
            Success::Warning => fmi2Warning,
        }
    }
}

/// Why a call was refused or failed. The layer prefixes the function name when logging.
#[derive(Debug, thiserror::Error)]
pub enum CallError {
    #[error("illegal call in state {0:?}")]
    IllegalCall(State),
    #[error("argument {0} is NULL")]
    NullArgument(&'static str),
    #[error("unknown value reference {vr} for type {type_name}")]
    UnknownValueReference { vr: u32, type_name: &'static str },
    #[error("variable {name} (vr {vr}) cannot be set: {reason}")]
    NotSettable {
        name: String,
        vr: u32,
        reason: &'static str,
    },
    #[error("variable {name} (vr {vr}): value {value} is not finite")]
    NonFinite { name: String, vr: u32, value: f64 },
    #[error("variable {name} (vr {vr}): value {value} is outside {range}")]
    OutOfRange {
        name: String,
        vr: u32,
        value: String,
        range: String,
    },
    #[error("variable {name} (vr {vr}): {reason}")]
    InvalidValue {
        name: String,
        vr: u32,
        reason: String,
    },
    #[error("{0}")]
    InvalidArgument(String),
    #[error("{0}")]
    Unsupported(&'static str),
    #[error("FMU state: {0}")]
    Snapshot(#[from] SnapshotError),
    /// A model's refusal, with the fields it names mapped to the declared variables.
    #[error("{0}")]
    Model(String),
    /// The standard's `fmi2Discard`: the request was valid but not (fully) served.
    #[error("{0}")]
    Discard(String),
}

impl CallError {
    pub fn status(&self) -> fmi2Status {
        match self {
            CallError::Discard(_) => fmi2Discard,
            _ => fmi2Error,
        }
    }
}

impl From<fmi_abi::args::ArgError> for CallError {
    fn from(error: fmi_abi::args::ArgError) -> Self {
        match error {
            fmi_abi::args::ArgError::Null(name) => CallError::NullArgument(name),
            other => CallError::InvalidArgument(other.to_string()),
        }
    }
}
