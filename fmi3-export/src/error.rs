//! FMI 3.0 status as a Rust `Result`: `Ok(Success)` is `fmi3OK`/`fmi3Warning`,
//! `Err(CallError)` is `fmi3Discard`/`fmi3Error` with the one log line that explains it.
use crate::ffi::*;
use crate::state::Refusal;
use fmi_model::snapshot::SnapshotError;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Success {
    Ok,
    Warning,
}

impl Success {
    pub fn status(self) -> fmi3Status {
        match self {
            Success::Ok => fmi3OK,
            Success::Warning => fmi3Warning,
        }
    }
}

/// Why a call was refused or failed; the layer prefixes the function name when logging.
#[derive(Debug, thiserror::Error)]
pub enum CallError {
    #[error("{0}")]
    Refused(Refusal),
    #[error("argument {0} is NULL")]
    NullArgument(&'static str),
    #[error("unknown value reference {vr} for {type_name}")]
    UnknownValueReference { vr: u32, type_name: &'static str },
    #[error("variable {name} (vr {vr}) cannot be set: {reason}")]
    NotSettable {
        name: &'static str,
        vr: u32,
        reason: &'static str,
    },
    #[error("variable {name} (vr {vr}): {reason}")]
    InvalidValue {
        name: &'static str,
        vr: u32,
        reason: String,
    },
    #[error("{0}")]
    InvalidArgument(String),
    #[error("FMU state: {0}")]
    Snapshot(#[from] SnapshotError),
    #[error("{0}")]
    Model(String),
    /// The request was valid but not (fully) served.
    #[error("{0}")]
    Discard(String),
}

impl CallError {
    pub fn status(&self) -> fmi3Status {
        match self {
            CallError::Discard(_) => fmi3Discard,
            _ => fmi3Error,
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
