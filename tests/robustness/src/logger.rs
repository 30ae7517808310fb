//! A recording logger: every message an instance passes to `fmi2CallbackLogger`, formatted
//! by the C shim (`csrc/logger.c`) and kept in memory for the tests to inspect.
#![allow(unsafe_code)]

use crate::ffi::{self, fmi2CallbackFunctions, fmi2Status, fmi2String};
use std::ffi::{c_char, c_int, CStr};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::{Mutex, MutexGuard};

extern "C" {
    fn robust_fmi2_logger(
        component_environment: *mut std::ffi::c_void,
        instance_name: *const c_char,
        status: c_int,
        category: *const c_char,
        message: *const c_char,
        ...
    );
}

/// One logged message.
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

type Forward = extern "C" fn(*const LogSink, fmi2String, c_int, fmi2String, fmi2String);

/// What `componentEnvironment` points to; `#[repr(C)]` with `forward` first, as the shim reads it.
#[repr(C)]
pub struct LogSink {
    forward: Forward,
    records: Mutex<Vec<Record>>,
}

impl Default for LogSink {
    fn default() -> Self {
        LogSink {
            forward,
            records: Mutex::new(Vec::new()),
        }
    }
}

impl std::fmt::Debug for LogSink {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LogSink")
            .field("records", &*self.lock())
            .finish()
    }
}

impl LogSink {
    /// Callbacks whose environment is this sink. The caller keeps the sink alive and at a
    /// fixed address (boxed) for as long as an instance may log.
    pub fn callbacks(&self) -> fmi2CallbackFunctions {
        fmi2CallbackFunctions {
            logger: Some(robust_fmi2_logger as ffi::Logger),
            allocate_memory: None,
            free_memory: None,
            step_finished: None,
            component_environment: self as *const LogSink as *mut std::ffi::c_void,
        }
    }

    fn lock(&self) -> MutexGuard<'_, Vec<Record>> {
        self.records.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Everything logged since the last `take`.
    pub fn take(&self) -> Vec<Record> {
        std::mem::take(&mut *self.lock())
    }

    pub fn all(&self) -> Vec<Record> {
        self.lock().clone()
    }

    pub fn len(&self) -> usize {
        self.lock().len()
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

fn text(p: *const c_char) -> Option<String> {
    // SAFETY: the FMU and the shim pass NUL-terminated strings or NULL.
    (!p.is_null()).then(|| unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned())
}

extern "C" fn forward(
    sink: *const LogSink,
    instance_name: fmi2String,
    status: c_int,
    category: fmi2String,
    message: fmi2String,
) {
    // Nothing may unwind into the FMU.
    let _ = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: the shim hands back the environment given to fmi2Instantiate, a live sink.
        let Some(sink) = (unsafe { sink.as_ref() }) else {
            return;
        };
        sink.lock().push(Record {
            instance_name: text(instance_name),
            status,
            category: text(category),
            message: text(message),
        });
    }));
}
