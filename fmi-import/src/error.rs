//! Errors of loading an FMU and of calling into an instance.
use super::logger::FmuLog;
use super::status::Failure;
use model_description::VariableKind;
use std::path::PathBuf;

/// Why an FMU could not be loaded. Every variant names the file or item at fault; the
/// underlying cause, where there is one, is the error's `source()` (print the chain, e.g. with
/// anyhow's `{:#}`, to see both).
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    #[error("cannot read FMU {path}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("FMU {path} is not a readable zip archive")]
    Zip {
        path: PathBuf,
        #[source]
        source: zip::result::ZipError,
    },
    #[error("FMU {path} has no modelDescription.xml at its top level")]
    MissingModelDescription { path: PathBuf },
    /// An archive refused while it was unpacked: an entry that is a link, lands outside the
    /// extraction directory or is named twice, or the archive is past a bound. The message
    /// names the archive and the entry.
    #[error(transparent)]
    Unpack(fmi_abi::unpack::UnpackError),
    #[error("cannot read model description {path}")]
    ModelDescription {
        path: PathBuf,
        #[source]
        source: model_description::Error,
    },
    #[error("model description says fmiVersion=\"{found}\"; this loader reads FMI 2.0 and 3.0")]
    UnsupportedFmiVersion { found: String },
    #[error("model '{model_name}' has neither a <CoSimulation> nor a <ModelExchange> element")]
    NotCoSimulation { model_name: String },
    /// An FMI 3.0 FMU that needs what the harness does not do (clocks, Model Exchange only,
    /// structural parameters), refused before any instance is made.
    #[error("model '{model_name}' (FMI 3.0) cannot be run: {reason}")]
    UnsupportedFmi3 { model_name: String, reason: String },
    #[error("model description declares the variable name '{name}' twice")]
    DuplicateVariableName { name: String },
    #[error(
        "variable '{name}' has no type element (Real, Integer, Boolean, String or Enumeration)"
    )]
    UntypedVariable { name: String },
    #[error(
        "FMU binary {path} not found (expected binaries/{platform}/<modelIdentifier>.{extension})"
    )]
    MissingBinary {
        path: PathBuf,
        platform: &'static str,
        extension: &'static str,
    },
    #[error("cannot load FMU binary {path}")]
    Library {
        path: PathBuf,
        #[source]
        source: libloading::Error,
    },
    #[error("FMU binary {binary} does not export {symbol}")]
    MissingSymbol {
        symbol: &'static str,
        binary: PathBuf,
        #[source]
        source: libloading::Error,
    },
    #[error("FMU binary {binary}: {function} returned \"{found}\", expected \"{expected}\"")]
    BinaryMismatch {
        binary: PathBuf,
        function: &'static str,
        found: String,
        expected: &'static str,
    },
}

/// A call the FMU answered with `Discard`, `Error`, `Fatal` (or, in FMI 2.0, `fmi2Pending`),
/// with what the FMU logged during that call.
#[derive(Debug, Clone, thiserror::Error)]
#[error("{function} on instance '{instance}' returned {}{log}", status_name(function, *status))]
pub struct FmiError {
    pub function: &'static str,
    pub instance: String,
    pub status: Failure,
    pub log: FmuLog,
}

impl FmiError {
    /// A call the importer refused or gave up on itself (the FMU was not asked, or no longer
    /// answers usefully), with the reason as the one message of its log.
    pub(crate) fn from_importer(
        function: &'static str,
        instance: &str,
        version: crate::version::FmiVersion,
        message: String,
    ) -> Self {
        FmiError {
            function,
            instance: instance.to_owned(),
            status: Failure::Error,
            log: FmuLog(vec![crate::LogMessage {
                instance_name: instance.to_owned(),
                status: crate::Status::Error,
                version,
                category: "importer".into(),
                message,
            }]),
        }
    }
}

/// A name that does not resolve to a variable of the requested type.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum VariableError {
    #[error("model '{model}' has no variable named '{name}'")]
    Unknown { model: String, name: String },
    #[error("variable '{name}' of model '{model}' is {actual:?}, not {requested:?}")]
    TypeMismatch {
        model: String,
        name: String,
        actual: VariableKind,
        requested: VariableKind,
    },
}

/// Any failure of an instance call that checks its arguments before reaching the FMU.
#[derive(Debug, Clone, thiserror::Error)]
pub enum CallError {
    #[error(transparent)]
    Fmi(#[from] FmiError),
    #[error(transparent)]
    Variable(#[from] VariableError),
    #[error("{function} on instance '{instance}': {reason}")]
    InvalidArgument {
        function: &'static str,
        instance: String,
        reason: String,
    },
    #[error("{function} returned NULL for instance '{instance}'{log}")]
    InstantiationFailed {
        function: &'static str,
        instance: String,
        log: FmuLog,
    },
}

/// The status in the words of the function's standard: `fmi2Error` or `fmi3Error`.
fn status_name(function: &str, status: Failure) -> String {
    let name = status.to_string();
    match (function.starts_with("fmi3"), name.strip_prefix("fmi2")) {
        (true, Some(rest)) => format!("fmi3{rest}"),
        _ => name,
    }
}
