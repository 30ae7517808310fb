//! The master's side of the FMI 2.0 callbacks: the variadic logger (formatted in C, see
//! `csrc/callbacks.c`) and calloc/free for `allocateMemory`/`freeMemory`.
//!
//! A master embeds a [`LogSink`] as the *first* field of a `#[repr(C)]` struct of its own
//! and passes that struct as `componentEnvironment`; the shim calls `sink.forward` with the
//! finished message, and `forward` casts the sink pointer back to the master's struct.
#![allow(unsafe_code)]

use crate::fmi2::{fmi2CallbackFunctions, fmi2ComponentEnvironment, fmi2Status, fmi2String};
use std::ffi::{c_char, c_void, CStr};

/// Receives one formatted message: `(sink, instance name, status, category, message)`; any
/// string may be NULL (the FMU passed NULL).
pub type ForwardFn = extern "C" fn(*const LogSink, fmi2String, fmi2Status, fmi2String, fmi2String);

/// What the shim reads through `componentEnvironment`.
#[repr(C)]
#[derive(Debug)]
pub struct LogSink {
    pub forward: ForwardFn,
}

extern "C" {
    /// `fmi2CallbackLogger`: formats `message` with the variadic arguments and forwards it.
    pub fn fmi_abi_fmi2_logger(
        component_environment: fmi2ComponentEnvironment,
        instance_name: fmi2String,
        status: fmi2Status,
        category: fmi2String,
        message: fmi2String,
        ...
    );
    /// `calloc`, as FMI 2.0 asks of `allocateMemory`.
    pub fn fmi_abi_fmi2_allocate_memory(n_objects: usize, size: usize) -> *mut c_void;
    /// `free`.
    pub fn fmi_abi_fmi2_free_memory(object: *mut c_void);
}

impl LogSink {
    /// The callbacks whose environment is `owner`, a `#[repr(C)]` struct whose first field
    /// is this sink. The caller keeps `owner` alive and at a fixed address (boxed) for as
    /// long as an instance may log.
    pub fn callbacks<T>(owner: &T) -> fmi2CallbackFunctions {
        fmi2CallbackFunctions {
            logger: Some(fmi_abi_fmi2_logger),
            allocateMemory: Some(fmi_abi_fmi2_allocate_memory),
            freeMemory: Some(fmi_abi_fmi2_free_memory),
            stepFinished: None,
            componentEnvironment: owner as *const T as *mut c_void,
        }
    }
}

/// A string the FMU or the shim passed, `None` for NULL.
///
/// # Safety
/// `p` is NULL or a NUL-terminated string valid for the duration of the call.
pub unsafe fn text(p: *const c_char) -> Option<String> {
    // SAFETY: as the caller promises.
    (!p.is_null()).then(|| unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned())
}
