//! FMI 2.0 status codes as Rust results: `Ok(Ok | Warning)`, `Err(Discard | Error | Fatal | Pending)`.
use super::ffi;
use std::fmt;

/// A status the standard counts as success: the call's results are valid.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Success {
    Ok,
    /// Results are valid but the FMU logged something the user should see.
    Warning,
}

/// A status the standard counts as failure.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Failure {
    /// The call could not be completed as asked (e.g. a step stopped early); the instance is usable.
    Discard,
    /// The instance is unusable until it is reset or freed.
    Error,
    /// The FMU (all its instances) is unusable; only freeing is allowed.
    Fatal,
    /// An asynchronous step is still running; the harness never asks for one.
    Pending,
}

/// The raw `fmi2Status` of a call, as logged messages carry it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Status {
    Ok,
    Warning,
    Discard,
    Error,
    Fatal,
    Pending,
    /// A value outside the enumeration, which only a broken FMU returns.
    Unknown(i32),
}

impl Status {
    #[allow(non_upper_case_globals)] // the header's names, used as patterns
    pub(crate) fn from_raw(raw: ffi::fmi2Status) -> Self {
        match raw {
            ffi::fmi2OK => Self::Ok,
            ffi::fmi2Warning => Self::Warning,
            ffi::fmi2Discard => Self::Discard,
            ffi::fmi2Error => Self::Error,
            ffi::fmi2Fatal => Self::Fatal,
            ffi::fmi2Pending => Self::Pending,
            other => Self::Unknown(other.0),
        }
    }

    /// Splits the status into success and failure; an out-of-range value is treated as fatal,
    /// since nothing the FMU says afterwards can be trusted.
    pub fn into_result(self) -> Result<Success, Failure> {
        match self {
            Self::Ok => Ok(Success::Ok),
            Self::Warning => Ok(Success::Warning),
            Self::Discard => Err(Failure::Discard),
            Self::Error => Err(Failure::Error),
            Self::Fatal | Self::Unknown(_) => Err(Failure::Fatal),
            Self::Pending => Err(Failure::Pending),
        }
    }
}

impl fmt::Display for Status {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Ok => f.write_str("fmi2OK"),
            Self::Warning => f.write_str("fmi2Warning"),
            Self::Discard => f.write_str("fmi2Discard"),
            Self::Error => f.write_str("fmi2Error"),
            Self::Fatal => f.write_str("fmi2Fatal"),
            Self::Pending => f.write_str("fmi2Pending"),
            Self::Unknown(raw) => write!(f, "invalid fmi2Status {raw}"),
        }
    }
}

impl fmt::Display for Failure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let status = match self {
            Self::Discard => Status::Discard,
            Self::Error => Status::Error,
            Self::Fatal => Status::Fatal,
            Self::Pending => Status::Pending,
        };
        status.fmt(f)
    }
}

/// How a `do_step` ended, when it did not fail.
///
/// `fmi2Discard` from `fmi2DoStep` is the standard's way to stop a step early (touchdown, a
/// threshold): an expected outcome a master acts on, not an error, so it is reported here.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StepStatus {
    /// The step reached `t + h`.
    Complete(Success),
    /// The FMU stopped at `last_successful_time` (`t <= time <= t + h`); `terminated` says the
    /// simulation cannot be continued (`fmi2Terminated`).
    Discarded {
        last_successful_time: f64,
        terminated: bool,
    },
    /// FMI 3.0: the step returned `fmi3OK` (or `fmi3Warning`) with `terminateSimulation`:
    /// the FMU ended the run, its outputs valid at `last_successful_time` (the step's end
    /// `t + h`, the harness not allowing early return).
    Terminated { last_successful_time: f64 },
}

impl StepStatus {
    /// The FMU ended the run: FMI 2.0's `fmi2Discard` with `fmi2Terminated`, FMI 3.0's
    /// `terminateSimulation`. Its time is that of the row to record last.
    pub fn ended_run(&self) -> Option<f64> {
        match *self {
            StepStatus::Discarded {
                last_successful_time,
                terminated: true,
            }
            | StepStatus::Terminated {
                last_successful_time,
            } => Some(last_successful_time),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn raw_status_values_follow_the_standard_enumeration() {
        // fmi2FunctionTypes.h: fmi2OK, fmi2Warning, fmi2Discard, fmi2Error, fmi2Fatal, fmi2Pending.
        let expected = [
            Status::Ok,
            Status::Warning,
            Status::Discard,
            Status::Error,
            Status::Fatal,
            Status::Pending,
        ];
        for (raw, status) in expected.into_iter().enumerate() {
            assert_eq!(Status::from_raw(ffi::fmi2Status(raw as i32)), status);
        }
    }

    #[test]
    fn only_ok_and_warning_are_success() {
        assert_eq!(Status::Ok.into_result(), Ok(Success::Ok));
        assert_eq!(Status::Warning.into_result(), Ok(Success::Warning));
        assert_eq!(Status::Discard.into_result(), Err(Failure::Discard));
        assert_eq!(Status::Error.into_result(), Err(Failure::Error));
        assert_eq!(Status::Fatal.into_result(), Err(Failure::Fatal));
        assert_eq!(Status::Pending.into_result(), Err(Failure::Pending));
    }

    #[test]
    fn an_out_of_range_status_is_fatal_not_success() {
        assert_eq!(Status::from_raw(ffi::fmi2Status(6)), Status::Unknown(6));
        assert_eq!(
            Status::from_raw(ffi::fmi2Status(-1)).into_result(),
            Err(Failure::Fatal)
        );
    }
}
