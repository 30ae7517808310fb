//! The FMU's side of the logger callback: categories, filtering and the C call.
//!
//! Which messages reach the master (FMI 2.0.4 §2.1.3 and §2.1.5): `fmi2Warning`, `fmi2Error`
//! and `fmi2Fatal` say that "the logger was called", so those messages are always passed on,
//! whatever the debug-logging flags. `fmi2Discard` and `fmi2OK` messages and the call trace
//! are debug logging: passed on only when their category is switched on (by `loggingOn` of
//! `fmi2Instantiate` or by `fmi2SetDebugLogging`).
use crate::ffi::{
    fmi2CallbackLogger, fmi2ComponentEnvironment, fmi2Discard, fmi2Error, fmi2Fatal, fmi2Status,
    fmi2Warning,
};
use std::ffi::{CStr, CString};

/// The `LogCategories` of the model description.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Category {
    StatusOk,
    StatusWarning,
    StatusDiscard,
    StatusError,
    StatusFatal,
    Calls,
}

impl Category {
    pub const ALL: [Category; 6] = [
        Category::StatusOk,
        Category::StatusWarning,
        Category::StatusDiscard,
        Category::StatusError,
        Category::StatusFatal,
        Category::Calls,
    ];

    pub const fn name(self) -> &'static CStr {
        match self {
            Category::StatusOk => c"logStatusOK",
            Category::StatusWarning => c"logStatusWarning",
            Category::StatusDiscard => c"logStatusDiscard",
            Category::StatusError => c"logStatusError",
            Category::StatusFatal => c"logStatusFatal",
            Category::Calls => c"logCalls",
        }
    }

    pub const fn description(self) -> &'static str {
        match self {
            Category::StatusOk => "Informational messages (debug logging)",
            Category::StatusWarning => "Warnings; always logged",
            Category::StatusDiscard => {
                "Discarded steps, e.g. a step that ended early (debug logging)"
            }
            Category::StatusError => "Errors, e.g. refused calls and invalid values; always logged",
            Category::StatusFatal => "Internal failures; always logged",
            Category::Calls => "Trace of every fmi2 call with its arguments (debug logging)",
        }
    }

    /// The category a message of this status is filed under.
    #[allow(non_upper_case_globals)] // the header's names, used as patterns
    pub fn for_status(status: fmi2Status) -> Category {
        match status {
            fmi2Warning => Category::StatusWarning,
            fmi2Discard => Category::StatusDiscard,
            fmi2Error => Category::StatusError,
            fmi2Fatal => Category::StatusFatal,
            // fmi2OK and fmi2Pending; no other value is ever logged by this layer.
            _ => Category::StatusOk,
        }
    }

    const fn always_logged(self) -> bool {
        matches!(
            self,
            Category::StatusWarning | Category::StatusError | Category::StatusFatal
        )
    }

    const fn bit(self) -> u8 {
        1 << self as u8
    }

    pub fn from_name(name: &[u8]) -> Option<Category> {
        Category::ALL
            .into_iter()
            .find(|c| c.name().to_bytes() == name)
    }
}

/// The copied callback and instance name, plus which debug categories are on.
#[derive(Debug, Clone)]
pub struct Logger {
    callback: fmi2CallbackLogger,
    environment: fmi2ComponentEnvironment,
    instance_name: CString,
    enabled: u8,
}

// SAFETY: the environment pointer is only handed back to the master's logger, never
// dereferenced by us; FMI 2.0 lets the master drive an instance from any thread (one
// thread at a time), so the master must accept its logger being called from that thread.
#[allow(unsafe_code)]
unsafe impl Send for Logger {}

impl Logger {
    pub fn new(
        callback: fmi2CallbackLogger,
        environment: fmi2ComponentEnvironment,
        instance_name: CString,
        logging_on: bool,
    ) -> Logger {
        let mut logger = Logger {
            callback,
            environment,
            instance_name,
            enabled: 0,
        };
        logger.set_all(logging_on);
        logger
    }

    pub fn instance_name(&self) -> &CStr {
        &self.instance_name
    }

    pub fn set_all(&mut self, on: bool) {
        for c in Category::ALL {
            self.set(c, on);
        }
    }

    pub fn set(&mut self, category: Category, on: bool) {
        if on {
            self.enabled |= category.bit();
        } else {
            self.enabled &= !category.bit();
        }
    }

    /// Whether a message of `category` would reach the master; lets callers skip formatting.
    pub fn is_on(&self, category: Category) -> bool {
        category.always_logged() || self.enabled & category.bit() != 0
    }

    /// A message under the category of its status.
    pub fn status(&self, status: fmi2Status, message: &str) {
        self.log(status, Category::for_status(status), message);
    }

    pub fn log(&self, status: fmi2Status, category: Category, message: &str) {
        if !self.is_on(category) {
            return;
        }
        let Some(callback) = self.callback else {
            return;
        };
        let message = sanitize(message);
        // SAFETY: the callback was non-null at instantiation and the master promises it
        // stays callable for the instance's lifetime; all strings are NUL-terminated and
        // outlive the call. The fixed "%s" format means no master ever interprets our text.
        #[allow(unsafe_code)]
        unsafe {
            callback(
                self.environment,
                self.instance_name.as_ptr(),
                status,
                category.name().as_ptr(),
                c"%s".as_ptr(),
                message.as_ptr(),
            );
        }
    }
}

/// The message as a C string; an interior NUL (which would silently cut the message short)
/// becomes U+FFFD.
pub fn sanitize(message: &str) -> CString {
    CString::new(message).unwrap_or_else(|_| {
        let cleaned = message.replace('\0', "\u{FFFD}");
        CString::new(cleaned).unwrap_or_default()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interior_nul_is_replaced_not_truncated() {
        let s = sanitize("a\0b");
        assert_eq!(s.to_str().unwrap(), "a\u{FFFD}b");
    }

    #[test]
    fn category_names_round_trip() {
        for c in Category::ALL {
            assert_eq!(Category::from_name(c.name().to_bytes()), Some(c));
        }
        assert_eq!(Category::from_name(b"logAll"), None);
    }

    #[test]
    fn errors_and_warnings_are_always_on_debug_categories_follow_the_flags() {
        let mut logger = Logger::new(None, std::ptr::null_mut(), c"i".to_owned(), false);
        assert!(logger.is_on(Category::StatusError));
        assert!(logger.is_on(Category::StatusWarning));
        assert!(logger.is_on(Category::StatusFatal));
        assert!(!logger.is_on(Category::StatusDiscard));
        assert!(!logger.is_on(Category::Calls));
        logger.set(Category::Calls, true);
        assert!(logger.is_on(Category::Calls));
        assert!(!logger.is_on(Category::StatusOk));
        logger.set_all(true);
        assert!(logger.is_on(Category::StatusOk));
    }
}
