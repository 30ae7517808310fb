//! Assertions shared by the table tests.
#![allow(dead_code)]

use robustness_tests::ffi::{fmi2Error, fmi2Status};
use robustness_tests::instance::Instance;
use robustness_tests::logger::Record;

/// The call returned fmi2Error and logged one error message naming `function` and
/// containing every `needle` (the variable, the value, the reason).
pub fn assert_refused(inst: &Instance, status: fmi2Status, function: &str, needles: &[&str]) {
    let log = inst.take_log();
    assert_refused_log(&log, status, function, needles);
}

pub fn assert_refused_log(log: &[Record], status: fmi2Status, function: &str, needles: &[&str]) {
    assert_eq!(
        status,
        fmi2Error,
        "{function} returned {}, expected fmi2Error; log: {log:#?}",
        status.label()
    );
    let found = log.iter().any(|r| {
        r.status == fmi2Error
            && r.category.as_deref() == Some("logStatusError")
            && r.message().starts_with(&format!("{function}:"))
            && needles.iter().all(|n| r.message().contains(n))
    });
    assert!(
        found,
        "no error message naming {function} and {needles:?}: {log:#?}"
    );
}
