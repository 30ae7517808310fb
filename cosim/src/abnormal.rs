//! How a worker ended without finishing, told with the call it was in: what a run that failed
//! this way reports (`MasterError::Abnormal`), below the master and the supervisor alike.
use fmi_import::blackbox::LastCall;

/// Why the parent had no answer from its worker.
#[derive(Debug, Clone, PartialEq)]
pub enum How {
    /// The process exited (FMU code calling `exit`, or the worker giving up) with this code.
    Exited(i32),
    /// Killed by this signal (a crash, `abort`, the kernel's out-of-memory killer).
    Signal(i32),
    /// One call (or a stretch without any call) took longer than the call timeout, in s.
    CallTimeout(f64),
    /// The run took longer than the run timeout, in s.
    RunTimeout(f64),
    /// The worker said something the parent could not read, or could not be started.
    Broken(String),
}

/// A run that ended without an answer: how, and the last FMI call the worker started.
#[derive(Debug, Clone, PartialEq)]
pub struct Abnormal {
    pub how: How,
    pub last_call: Option<LastCall>,
    /// The address-space limit the worker ran under, in bytes (0: none), for the reader of
    /// a crash that may be an allocation refused.
    pub memory_limit_bytes: u64,
}

impl Abnormal {
    /// The instance of the call it ended in (or after), if any call was made.
    pub fn instance(&self) -> Option<&str> {
        self.last_call.as_ref().map(|c| c.instance.as_str())
    }

    pub fn function(&self) -> Option<&str> {
        self.last_call.as_ref().map(|c| c.function.as_str())
    }

    pub fn time(&self) -> Option<f64> {
        self.last_call.as_ref().map(|c| c.time)
    }
}

/// The signal's name and what it usually means for FMU code.
#[cfg(unix)]
pub fn signal_name(signal: i32) -> String {
    let known = [
        (libc::SIGSEGV, "SIGSEGV, invalid memory access"),
        (libc::SIGBUS, "SIGBUS, invalid memory access"),
        (libc::SIGABRT, "SIGABRT, abort() or a failed allocation"),
        (libc::SIGFPE, "SIGFPE, arithmetic fault"),
        (libc::SIGILL, "SIGILL, illegal instruction"),
        (
            libc::SIGKILL,
            "SIGKILL, killed from outside, e.g. by the kernel out of memory",
        ),
        (libc::SIGTERM, "SIGTERM"),
        (libc::SIGINT, "SIGINT"),
        (libc::SIGPIPE, "SIGPIPE"),
    ];
    match known.iter().find(|(s, _)| *s == signal) {
        Some((_, name)) => format!("signal {signal} ({name})"),
        None => format!("signal {signal}"),
    }
}

/// No signals end a process outside Unix.
#[cfg(not(unix))]
pub fn signal_name(signal: i32) -> String {
    format!("signal {signal}")
}

impl std::fmt::Display for How {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            How::Exited(0) => write!(
                f,
                "the worker process exited with status 0 before the run had finished (FMU \
                 code calling exit?)"
            ),
            How::Exited(code) => write!(f, "the worker process exited with status {code}"),
            How::Signal(signal) => write!(
                f,
                "the worker process was killed by {}",
                signal_name(*signal)
            ),
            How::CallTimeout(limit) => write!(
                f,
                "no call returned or started for {limit} s (the call timeout), so the worker \
                 process was killed"
            ),
            How::RunTimeout(limit) => write!(
                f,
                "the run took longer than {limit} s (the run timeout), so the worker process \
                 was killed"
            ),
            How::Broken(reason) => write!(f, "the worker process failed: {reason}"),
        }
    }
}

impl std::fmt::Display for Abnormal {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match &self.last_call {
            Some(call) if call.in_call => write!(
                f,
                "instance '{}' did not return from {} at t = {} s: {}",
                call.instance, call.function, call.time, self.how
            )?,
            Some(call) => write!(
                f,
                "{} after instance '{}' returned from {} at t = {} s",
                self.how, call.instance, call.function, call.time
            )?,
            None => write!(f, "{} before any FMU call", self.how)?,
        }
        if self.memory_limit_bytes > 0 && matches!(self.how, How::Signal(_)) {
            write!(
                f,
                " (the worker's memory limit is {:.0} MB: an allocation beyond it fails)",
                self.memory_limit_bytes as f64 / 1e6
            )?;
        }
        Ok(())
    }
}

impl std::error::Error for Abnormal {}
