//! The FMU's side of the master's logger: categories, filtering, and the call through the
//! version's [`Abi::emit`].
//!
//! Which messages reach the master: Warning, Error and Fatal say that "the logger was
//! called" in both standards, so those messages are always passed on, whatever the
//! debug-logging flags. OK and Discard messages, events and the call trace are debug
//! logging: passed on only when their category is switched on (by `loggingOn` at
//! instantiation or by the version's `SetDebugLogging`).
use crate::status::Status;
use crate::version::Abi;
use std::ffi::{CStr, CString};

/// The `LogCategories` of the model descriptions.
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
                "Events: touchdown, propellant exhaustion, a step ended at an event (debug logging)"
            }
            Category::Calls => "Trace of every call with its arguments (debug logging)",
        }
    }

    /// The category a message of this status is filed under.
    pub const fn for_status(status: Status) -> Category {
        match status {
            Status::Ok => Category::StatusOk,
            Status::Warning => Category::StatusWarning,
            Status::Discard => Category::StatusDiscard,
            Status::Error => Category::StatusError,
            Status::Fatal => Category::StatusFatal,
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

    /// A category of `among` by its name.
    pub fn from_name(name: &[u8], among: &[Category]) -> Option<Category> {
        among.iter().copied().find(|c| c.name().to_bytes() == name)
    }
}

/// The master's logger as it was given at instantiation: the callback (`C`, the version's
/// optional function pointer; none, nothing is logged), the environment pointer handed back
/// with every line, and the instance name (FMI 2.0's logger takes it with every line).
#[derive(Debug, Clone)]
pub struct Sink<C> {
    pub callback: C,
    pub environment: *mut std::os::raw::c_void,
    pub instance_name: CString,
}

// SAFETY: the environment pointer is only handed back to the master's logger, never
// dereferenced by us; both standards let the master drive an instance from any thread (one
// thread at a time), so the master must accept its logger being called from that thread.
#[allow(unsafe_code)]
unsafe impl<C: Send> Send for Sink<C> {}

/// The copied callback, plus which debug categories are on.
pub struct Logger<A: Abi> {
    sink: Sink<A::Callback>,
    enabled: u8,
}

impl<A: Abi> Clone for Logger<A> {
    fn clone(&self) -> Self {
        Logger {
            sink: self.sink.clone(),
            enabled: self.enabled,
        }
    }
}

impl<A: Abi> std::fmt::Debug for Logger<A> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Logger")
            .field("enabled", &self.enabled)
            .finish()
    }
}

impl<A: Abi> Logger<A> {
    pub fn new(sink: Sink<A::Callback>, logging_on: bool) -> Logger<A> {
        let mut logger = Logger { sink, enabled: 0 };
        logger.set_all(logging_on);
        logger
    }

    pub fn sink(&self) -> &Sink<A::Callback> {
        &self.sink
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
    #[inline]
    pub fn is_on(&self, category: Category) -> bool {
        category.always_logged() || self.enabled & category.bit() != 0
    }

    /// A message under the category of its status.
    pub fn status(&self, status: Status, message: &str) {
        self.log(status, Category::for_status(status), message);
    }

    pub fn log(&self, status: Status, category: Category, message: &str) {
        if self.is_on(category) {
            A::emit(&self.sink, status, category, &sanitize(message));
        }
    }
}

/// The message as a C string; an interior NUL (which would silently cut the message short)
/// becomes U+FFFD.
pub fn sanitize(message: &str) -> CString {
    CString::new(message)
        .unwrap_or_else(|_| CString::new(message.replace('\0', "\u{FFFD}")).unwrap_or_default())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interior_nul_is_replaced_not_truncated() {
        assert_eq!(sanitize("a\0b").to_str().unwrap(), "a\u{FFFD}b");
    }

    #[test]
    fn category_names_round_trip() {
        for c in Category::ALL {
            assert_eq!(
                Category::from_name(c.name().to_bytes(), &Category::ALL),
                Some(c)
            );
        }
        assert_eq!(Category::from_name(b"logAll", &Category::ALL), None);
        assert_eq!(Category::from_name(b"logEvents", &[Category::Calls]), None);
    }
}
