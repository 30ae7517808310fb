//! The Rust side of the FMU logger: each instance's messages go to the `log` crate and into
//! a bounded per-instance buffer, so that errors can carry what the FMU said.
#![allow(unsafe_code)]

use super::ffi::{self, fmi2String};
use super::status::Status;
use std::collections::VecDeque;
use std::ffi::c_char;
use std::fmt;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Mutex, MutexGuard};

/// Messages kept per instance; older ones are dropped so a long run with logging on stays bounded.
pub const LOG_CAPACITY: usize = 4096;

/// One message an FMU passed to the logger callback, already formatted.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LogMessage {
    pub instance_name: String,
    /// The FMI 3.0 status of the same number when `version` is FMI 3.0.
    pub status: Status,
    pub version: crate::version::FmiVersion,
    pub category: String,
    pub message: String,
}

impl fmt::Display for LogMessage {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let status = self.status.to_string();
        let status = match (self.version, status.strip_prefix("fmi2")) {
            (crate::version::FmiVersion::Fmi3, Some(rest)) => format!("fmi3{rest}"),
            _ => status,
        };
        write!(f, "[{status}] {}: {}", self.category, self.message)
    }
}

/// Messages attached to an error, printed one per line.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct FmuLog(pub Vec<LogMessage>);

impl fmt::Display for FmuLog {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.0.is_empty() {
            return f.write_str("; the FMU logged nothing");
        }
        f.write_str("; FMU log:")?;
        for message in &self.0 {
            write!(f, "\n  {message}")?;
        }
        Ok(())
    }
}

/// What `componentEnvironment` points to. `#[repr(C)]` with the sink first, because the C
/// shim of `fmi-abi` reads it to reach Rust without a global symbol.
#[repr(C)]
pub(crate) struct LogEnv {
    sink: ffi::LogSink,
    /// Sequence number of the next message; read without the lock on every FMI call.
    next_sequence: AtomicU64,
    buffer: Mutex<VecDeque<(u64, LogMessage)>>,
    /// The instance's name, for FMI 3.0, whose logger callback passes none.
    instance_name: String,
}

/// A position in an instance's log, to collect what one call produced.
#[derive(Debug, Clone, Copy)]
pub(crate) struct LogMark(u64);

impl LogEnv {
    pub(crate) fn new() -> Self {
        Self {
            sink: ffi::LogSink {
                forward: forward_log_message,
            },
            next_sequence: AtomicU64::new(0),
            buffer: Mutex::new(VecDeque::new()),
            instance_name: String::new(),
        }
    }

    /// A sink for an FMI 3.0 instance named `name` (see [`log_message_fmi3`]).
    pub(crate) fn named(name: &str) -> Self {
        Self {
            instance_name: name.to_owned(),
            ..Self::new()
        }
    }

    /// The callback struct handed to `fmi2Instantiate`, with this sink as its environment.
    /// The caller keeps `self` alive (and at a fixed address) as long as the FMU may log.
    pub(crate) fn callbacks(&self) -> ffi::fmi2CallbackFunctions {
        ffi::LogSink::callbacks(self)
    }

    fn lock(&self) -> MutexGuard<'_, VecDeque<(u64, LogMessage)>> {
        // A panic while holding the lock leaves only a possibly missing message behind.
        self.buffer
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner())
    }

    pub(crate) fn mark(&self) -> LogMark {
        LogMark(self.next_sequence.load(Ordering::Acquire))
    }

    pub(crate) fn since(&self, mark: LogMark) -> FmuLog {
        FmuLog(
            self.lock()
                .iter()
                .filter(|(sequence, _)| *sequence >= mark.0)
                .map(|(_, message)| message.clone())
                .collect(),
        )
    }

    pub(crate) fn all(&self) -> Vec<LogMessage> {
        self.lock()
            .iter()
            .map(|(_, message)| message.clone())
            .collect()
    }

    pub(crate) fn clear(&self) {
        self.lock().clear();
    }

    fn push(&self, message: LogMessage) {
        let mut messages = self.lock();
        if messages.len() == LOG_CAPACITY {
            messages.pop_front();
        }
        // Numbered under the lock so sequence order is buffer order.
        let sequence = self.next_sequence.fetch_add(1, Ordering::AcqRel);
        messages.push_back((sequence, message));
    }
}

fn level_of(status: Status) -> log::Level {
    match status {
        // FMUs log call traces and progress as fmi2OK; keep them out of a normal run's output.
        Status::Ok | Status::Pending => log::Level::Debug,
        Status::Warning | Status::Discard => log::Level::Warn,
        Status::Error | Status::Fatal | Status::Unknown(_) => log::Level::Error,
    }
}

/// # Safety (of the C caller)
/// `env` is the `LogEnv` given to `fmi2Instantiate`; the strings are NUL-terminated or null.
extern "C" fn forward_log_message(
    sink: *const ffi::LogSink,
    instance_name: fmi2String,
    status: ffi::fmi2Status,
    category: fmi2String,
    message: fmi2String,
) {
    // The sink is the first field of a LogEnv (repr(C)), the environment we handed out.
    let env = sink as *const LogEnv;
    // Nothing may unwind into the FMU's C code.
    let _ = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: the shim passes back the environment pointer we gave fmi2Instantiate, and
        // the owning `Instance` keeps it alive until after fmi2FreeInstance returns.
        let Some(env) = (unsafe { env.as_ref() }) else {
            return;
        };
        let message = LogMessage {
            instance_name: text(instance_name),
            status: Status::from_raw(status),
            version: crate::version::FmiVersion::Fmi2,
            category: text(category),
            message: text(message),
        };
        log::log!(
            target: "harness::fmu",
            level_of(message.status),
            "{}: {}",
            message.instance_name,
            message
        );
        env.push(message);
    }));
}

/// The FMI 3.0 `logMessage` callback (not variadic: the FMU formats the message); its
/// `instanceEnvironment` is the instance's `LogEnv`. The status travels as the FMI 2.0 status
/// of the same number (FMI 3.0 has the same first five).
///
/// # Safety (of the C caller)
/// `environment` is the `LogEnv` given to `fmi3InstantiateCoSimulation`; the strings are
/// NUL-terminated or null.
pub(crate) unsafe extern "C" fn log_message_fmi3(
    environment: fmi_abi::fmi3::fmi3InstanceEnvironment,
    status: fmi_abi::fmi3::fmi3Status,
    category: fmi_abi::fmi3::fmi3String,
    message: fmi_abi::fmi3::fmi3String,
) {
    let env = environment as *const LogEnv;
    let _ = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: the environment we handed out, kept alive by the owning instance until
        // after fmi3FreeInstance returns.
        let Some(env) = (unsafe { env.as_ref() }) else {
            return;
        };
        let message = LogMessage {
            instance_name: env.instance_name.clone(),
            status: Status::from_raw(ffi::fmi2Status(status.0)),
            version: crate::version::FmiVersion::Fmi3,
            category: text(category),
            message: text(message),
        };
        log::log!(
            target: "harness::fmu",
            level_of(message.status),
            "{}: {}",
            message.instance_name,
            message
        );
        env.push(message);
    }));
}

fn text(pointer: *const c_char) -> String {
    // SAFETY: strings from the FMU and the shim are NULL or NUL-terminated C strings that
    // stay valid for the duration of the callback.
    unsafe { ffi::text(pointer) }.unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::ffi::CStr;
    use std::ffi::CString;

    fn call_shim(env: &LogEnv, format: &CStr, argument: &CStr) {
        let callbacks = env.callbacks();
        let logger = callbacks.logger.expect("logger set");
        let name = CString::new("inst").unwrap();
        let category = CString::new("logStatusError").unwrap();
        // SAFETY: the environment is alive and every string is NUL-terminated; the format
        // consumes exactly one `char *` argument, which is passed.
        unsafe {
            logger(
                callbacks.componentEnvironment,
                name.as_ptr(),
                ffi::fmi2Error,
                category.as_ptr(),
                format.as_ptr(),
                argument.as_ptr(),
            );
        }
    }

    #[test]
    fn the_c_shim_formats_printf_arguments_before_reaching_rust() {
        let env = LogEnv::new();
        call_shim(&env, c"value %s refused", c"x = NaN");
        let log = env.all();
        assert_eq!(log.len(), 1);
        assert_eq!(log[0].message, "value x = NaN refused");
        assert_eq!(log[0].status, Status::Error);
        assert_eq!(log[0].category, "logStatusError");
        assert_eq!(log[0].instance_name, "inst");
    }

    #[test]
    fn a_message_longer_than_the_stack_buffer_arrives_whole() {
        let env = LogEnv::new();
        let long = "y".repeat(10_000);
        let argument = CString::new(long.clone()).unwrap();
        call_shim(&env, c"<%s>", &argument);
        assert_eq!(env.all()[0].message, format!("<{long}>"));
    }

    #[test]
    fn the_buffer_keeps_only_the_newest_messages() {
        let env = LogEnv::new();
        for i in 0..LOG_CAPACITY + 3 {
            let argument = CString::new(i.to_string()).unwrap();
            call_shim(&env, c"%s", &argument);
        }
        let log = env.all();
        assert_eq!(log.len(), LOG_CAPACITY);
        assert_eq!(log[0].message, "3");
        assert_eq!(
            log[LOG_CAPACITY - 1].message,
            (LOG_CAPACITY + 2).to_string()
        );
    }

    #[test]
    fn since_returns_only_what_came_after_the_mark() {
        let env = LogEnv::new();
        call_shim(&env, c"%s", c"before");
        let mark = env.mark();
        call_shim(&env, c"%s", c"after");
        let log = env.since(mark);
        assert_eq!(log.0.len(), 1);
        assert_eq!(log.0[0].message, "after");
    }

    #[test]
    fn null_environment_and_null_strings_are_ignored_safely() {
        let env = LogEnv::new();
        let callbacks = env.callbacks();
        let logger = callbacks.logger.unwrap();
        // SAFETY: the shim must tolerate a null environment and null strings (a careless FMU).
        unsafe {
            logger(
                std::ptr::null_mut(),
                std::ptr::null(),
                ffi::fmi2OK,
                std::ptr::null(),
                std::ptr::null(),
            );
            logger(
                callbacks.componentEnvironment,
                std::ptr::null(),
                ffi::fmi2OK,
                std::ptr::null(),
                std::ptr::null(),
            );
        }
        let log = env.all();
        assert_eq!(log.len(), 1);
        assert_eq!(log[0].message, "");
        assert_eq!(log[0].instance_name, "");
    }
}
