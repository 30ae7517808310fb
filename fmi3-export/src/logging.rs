//! The FMU's side of the FMI 3.0 log-message callback: categories, filtering and the C call.
//!
//! As in the FMI 2.0 layer: warnings, errors and fatal messages always reach the master;
//! `fmi3OK`/`fmi3Discard` messages, events and the call trace only when their category is
//! on (`loggingOn` of the instantiation, or `fmi3SetDebugLogging`). FMI 3.0's callback is not
//! variadic and carries no instance name: the message is complete text.
#[cfg(test)]
use crate::ffi::{fmi3Error, fmi3OK};
use crate::ffi::{fmi3InstanceEnvironment, fmi3LogMessageCallback, fmi3Status};
use std::ffi::{CStr, CString};

/// The `LogCategories` of the model description.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Category {
    StatusOk,
    StatusWarning,
    StatusDiscard,
    StatusError,
    StatusFatal,
    Events,
    Calls,
}

impl Category {
    pub const ALL: [Category; 7] = [
        Category::StatusOk,
        Category::StatusWarning,
        Category::StatusDiscard,
        Category::StatusError,
        Category::StatusFatal,
        Category::Events,
        Category::Calls,
    ];

    pub const fn name(self) -> &'static CStr {
        match self {
            Category::StatusOk => c"logStatusOK",
            Category::StatusWarning => c"logStatusWarning",
            Category::StatusDiscard => c"logStatusDiscard",
            Category::StatusError => c"logStatusError",
            Category::StatusFatal => c"logStatusFatal",
            Category::Events => c"logEvents",
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
            Category::Events => {
                "Model Exchange events: touchdown, propellant exhaustion (debug logging)"
            }
            Category::Calls => "Trace of every fmi3 call with its arguments (debug logging)",
        }
    }

    /// The category a message of this status is filed under.
    pub const fn for_status(status: fmi3Status) -> Category {
        match status.0 {
            1 => Category::StatusWarning,
            2 => Category::StatusDiscard,
            3 => Category::StatusError,
            4 => Category::StatusFatal,
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

/// The copied callback and environment, plus which debug categories are on.
#[derive(Debug, Clone)]
pub struct Logger {
    callback: fmi3LogMessageCallback,
    environment: fmi3InstanceEnvironment,
    enabled: u8,
}

// SAFETY: the environment pointer is only handed back to the master's callback, never
// dereferenced by us; the master may drive an instance from any thread, one at a time.
#[allow(unsafe_code)]
unsafe impl Send for Logger {}

impl Logger {
    pub fn new(
        callback: fmi3LogMessageCallback,
        environment: fmi3InstanceEnvironment,
        logging_on: bool,
    ) -> Logger {
        let mut logger = Logger {
            callback,
            environment,
            enabled: 0,
        };
        logger.set_all(logging_on);
        logger
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
    pub fn status(&self, status: fmi3Status, message: &str) {
        self.log(status, Category::for_status(status), message);
    }

    pub fn log(&self, status: fmi3Status, category: Category, message: &str) {
        if !self.is_on(category) {
            return;
        }
        let Some(callback) = self.callback else {
            return;
        };
        let message = sanitize(message);
        // SAFETY: the callback was non-null at instantiation and stays callable for the
        // instance's lifetime; both strings are NUL-terminated and outlive the call.
        #[allow(unsafe_code)]
        unsafe {
            callback(
                self.environment,
                status,
                category.name().as_ptr(),
                message.as_ptr(),
            );
        }
    }
}

/// The message as a C string; an interior NUL (which would cut it short) becomes U+FFFD.
pub fn sanitize(message: &str) -> CString {
    CString::new(message)
        .unwrap_or_else(|_| CString::new(message.replace('\0', "\u{FFFD}")).unwrap_or_default())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Mutex;

    static SEEN: Mutex<Vec<(fmi3Status, String, String)>> = Mutex::new(Vec::new());

    #[allow(unsafe_code)]
    unsafe extern "C" fn record(
        _env: fmi3InstanceEnvironment,
        status: fmi3Status,
        category: crate::ffi::fmi3String,
        message: crate::ffi::fmi3String,
    ) {
        // SAFETY: the logger passes NUL-terminated strings.
        let text = |s| unsafe { CStr::from_ptr(s) }.to_string_lossy().into_owned();
        SEEN.lock()
            .unwrap()
            .push((status, text(category), text(message)));
    }

    #[test]
    fn errors_always_reach_the_master_debug_messages_only_when_on() {
        let mut logger = Logger::new(Some(record), std::ptr::null_mut(), false);
        logger.status(fmi3OK, "quiet");
        logger.status(fmi3Error, "fmi3DoStep: bad\0step");
        logger.set(Category::Events, true);
        logger.log(fmi3OK, Category::Events, "touchdown");
        let seen = SEEN.lock().unwrap().clone();
        assert_eq!(
            seen,
            [
                (
                    fmi3Error,
                    "logStatusError".to_owned(),
                    "fmi3DoStep: bad\u{FFFD}step".to_owned()
                ),
                (fmi3OK, "logEvents".to_owned(), "touchdown".to_owned()),
            ]
        );
    }

    #[test]
    fn category_names_round_trip() {
        for c in Category::ALL {
            assert_eq!(Category::from_name(c.name().to_bytes()), Some(c));
        }
        assert_eq!(Category::from_name(b"logAll"), None);
    }
}
