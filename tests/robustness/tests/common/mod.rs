//! Assertions shared by the table tests.
#![allow(dead_code)]

use robustness_tests::ffi::{status_name, ERROR};
use robustness_tests::instance::Instance;
use robustness_tests::logger::Record;

/// The call returned fmi2Error and logged one error message naming `function` and
/// containing every `needle` (the variable, the value, the reason).
pub fn assert_refused(inst: &Instance, status: i32, function: &str, needles: &[&str]) {
    let log = inst.take_log();
    assert_refused_log(&log, status, function, needles);
}

pub fn assert_refused_log(log: &[Record], status: i32, function: &str, needles: &[&str]) {
    assert_eq!(
        status,
        ERROR,
        "{function} returned {}, expected fmi2Error; log: {log:#?}",
        status_name(status)
    );
    let found = log.iter().any(|r| {
        r.status == ERROR
            && r.category.as_deref() == Some("logStatusError")
            && r.message().starts_with(&format!("{function}:"))
            && needles.iter().all(|n| r.message().contains(n))
    });
    assert!(
        found,
        "no error message naming {function} and {needles:?}: {log:#?}"
    );
}
