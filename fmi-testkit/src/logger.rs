//! A recording logger: every message an instance passes to `fmi2CallbackLogger`, formatted
//! by the C shim of `fmi-abi` (as a C master formats it) and kept for the test to inspect.
use fmi_abi::callbacks::{text, LogSink};
use fmi_abi::fmi2::{fmi2CallbackFunctions, fmi2Status, fmi2String};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::{Mutex, MutexGuard};

/// One logged message; `None` where the FMU passed NULL.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Record {
    pub instance_name: Option<String>,
    pub status: fmi2Status,
    pub category: Option<String>,
    pub message: Option<String>,
}

impl Record {
    pub fn message(&self) -> &str {
        self.message.as_deref().unwrap_or("")
    }
}

/// What `componentEnvironment` points to: `#[repr(C)]`, the shim's sink first. Keep it boxed
/// (at a fixed address) for as long as an instance may log.
#[repr(C)]
#[derive(Debug)]
pub struct TestLogger {
    sink: LogSink,
    records: Mutex<Vec<Record>>,
}

impl Default for TestLogger {
    fn default() -> Self {
        TestLogger {
            sink: LogSink { forward },
            records: Mutex::new(Vec::new()),
        }
    }
}

impl TestLogger {
    /// The callbacks whose environment is this logger.
    pub fn callbacks(&self) -> fmi2CallbackFunctions {
        LogSink::callbacks(self)
    }

    fn lock(&self) -> MutexGuard<'_, Vec<Record>> {
        self.records.lock().unwrap_or_else(|p| p.into_inner())
    }

    pub(crate) fn push(&self, record: Record) {
        self.lock().push(record);
    }

    /// Everything logged since the last `take` (or `clear`).
    pub fn take(&self) -> Vec<Record> {
        std::mem::take(&mut *self.lock())
    }

    pub fn all(&self) -> Vec<Record> {
        self.lock().clone()
    }

    pub fn clear(&self) {
        self.lock().clear();
    }

    /// The message texts, in order.
    pub fn messages(&self) -> Vec<String> {
        self.lock()
            .iter()
            .map(|r| r.message().to_string())
            .collect()
    }

    pub fn len(&self) -> usize {
        self.lock().len()
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

extern "C" fn forward(
    sink: *const LogSink,
    instance_name: fmi2String,
    status: fmi2Status,
    category: fmi2String,
    message: fmi2String,
) {
    // Nothing may unwind into the FMU.
    let _ = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: the shim hands back the environment given to fmi2Instantiate: a live
        // TestLogger, whose first field (repr(C)) is this sink.
        let Some(logger) = (unsafe { (sink as *const TestLogger).as_ref() }) else {
            return;
        };
        // SAFETY: the FMU and the shim pass NUL-terminated strings or NULL.
        let record = unsafe {
            Record {
                instance_name: text(instance_name),
                status,
                category: text(category),
                message: text(message),
            }
        };
        logger.lock().push(record);
    }));
}
