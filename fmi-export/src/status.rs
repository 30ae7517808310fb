//! A call's result as a Rust `Result`: `Ok(Success)` is OK or Warning, `Err(CallError)` is
//! Discard, Error (or Fatal) together with the one log line that explains it. A version
//! layer maps [`Status`] onto its own C enumeration.
use crate::snapshot::SnapshotError;
use crate::state::{Interface, State};

/// The five statuses both FMI versions share (FMI 2.0's `fmi2Pending` is never returned),
/// with the codes both C enumerations give them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[repr(i32)]
pub enum Status {
    Ok = 0,
    Warning = 1,
    Discard = 2,
    Error = 3,
    Fatal = 4,
}

impl Status {
    /// The C code: `fmi2OK` = `fmi3OK` = 0, ..., `fmi2Fatal` = `fmi3Fatal` = 4.
    pub const fn code(self) -> std::os::raw::c_int {
        self as std::os::raw::c_int
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Success {
    Ok,
    Warning,
}

impl Success {
    pub fn status(self) -> Status {
        match self {
            Success::Ok => Status::Ok,
            Success::Warning => Status::Warning,
        }
    }

    /// The worse of two.
    pub fn and(self, other: Success) -> Success {
        if self == Success::Warning || other == Success::Warning {
            Success::Warning
        } else {
            Success::Ok
        }
    }
}

/// Why a call is refused before its body runs.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Refusal {
    /// A feature the FMU does not have (its functions are exported, as the standard
    /// requires, and refuse in every state).
    Unsupported(&'static str),
    /// A function of the other interface than this instance's (given).
    WrongInterface(Interface),
    /// Not allowed in this state; the name is the version's word for the state.
    IllegalState(State, &'static str),
}

impl std::fmt::Display for Refusal {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Refusal::Unsupported(feature) => write!(f, "not supported: this FMU has no {feature}"),
            Refusal::WrongInterface(interface) => write!(
                f,
                "not a {} function; this instance is {}",
                interface.name(),
                interface.name()
            ),
            Refusal::IllegalState(_, name) => write!(f, "illegal call in state {name}"),
        }
    }
}

/// Why a call was refused or failed. The layer prefixes the function name when logging.
#[derive(Debug, thiserror::Error)]
pub enum CallError {
    #[error("{0}")]
    Refused(Refusal),
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
    /// The request was valid but not (fully) served.
    #[error("{0}")]
    Discard(String),
}

impl CallError {
    pub fn status(&self) -> Status {
        match self {
            CallError::Discard(_) => Status::Discard,
            _ => Status::Error,
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
