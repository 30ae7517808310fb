//! What reaches the master's logger, under which category, with which arguments.
mod common;

use common::{vr, Fmu};
use fmi_testkit::fmi2::*;
use fmu_testmodel as fmu;
use std::ptr::null;

#[test]
fn environment_and_instance_name_are_passed_back_on_every_message() {
    let fmu = Fmu::named("lander-1", true);
    fmu.init();
    fmu.set_real(vr::U, f64::NAN);
    let records = fmu.records();
    assert!(records.len() > 3);
    // Every message reached this instance's logger through the environment it was given
    // (the C shim reads the sink through it), with the instance name.
    assert!(records.iter().all(|r| r.instance == "lander-1"));
}

/// The layer passes every message as the argument of a fixed "%s" format: text with
/// conversion specifiers in it reaches the master unchanged (the test kit's logger formats
/// with vsnprintf, as a C master does).
#[test]
fn a_message_with_conversion_specifiers_arrives_verbatim() {
    let fmu = Fmu::new(true);
    let label = "100% %s %d %n %%";
    assert_eq!(fmu.set_string(vr::LABEL, label), fmi2OK);
    fmu.init();
    assert!(
        fmu.messages()
            .iter()
            .any(|m| m.contains(&format!("{label}: x0 ="))),
        "{:?}",
        fmu.messages()
    );
}

#[test]
fn with_logging_off_only_warnings_errors_and_fatals_are_passed_on() {
    let fmu = Fmu::new(false);
    fmu.set_boolean(vr::STOP_AT_THRESHOLD, true);
    fmu.set_real(vr::THRESHOLD, 0.99999);
    fmu.init();
    assert_eq!(fmu.step(0.0, 0.01), fmi2Discard);
    assert!(
        fmu.records().is_empty(),
        "no trace, info or discard: {:?}",
        fmu.records()
    );
    fmu.set_real(vr::U, f64::NAN);
    let records = fmu.records();
    assert_eq!(records.len(), 1);
    assert_eq!(records[0].category, "logStatusError");
}

#[test]
fn with_logging_on_calls_are_traced_with_their_arguments() {
    let fmu = Fmu::new(true);
    fmu.init();
    fmu.clear();
    let refs = [vr::U, vr::K];
    let values = [0.25, 2.0];
    unsafe { fmu::fmi2SetReal(fmu.c, refs.as_ptr(), 2, values.as_ptr()) };
    fmu.step(0.0, 0.01);
    let calls: Vec<String> = fmu
        .records()
        .into_iter()
        .filter(|r| r.category == "logCalls")
        .map(|r| r.message)
        .collect();
    assert_eq!(
        calls,
        [
            "fmi2SetReal(nvr=2, vr=[4, 1], value=[0.25, 2.0])",
            "fmi2DoStep(currentCommunicationPoint=0, communicationStepSize=0.01, noSetFMUStatePriorToCurrentPoint=1)",
        ]
    );
}

#[test]
fn model_info_messages_are_logged_under_status_ok_when_on() {
    let fmu = Fmu::new(true);
    fmu.set_string(vr::LABEL, "osc-7");
    fmu.init();
    let info = fmu
        .records()
        .into_iter()
        .find(|r| r.category == "logStatusOK")
        .expect("info");
    assert_eq!(info.status, fmi2OK);
    assert_eq!(
        info.message,
        "fmi2ExitInitializationMode: osc-7: x0 = 1 m, k = 1 N/m, c = 0.1 N.s/m"
    );
}

/// SetDebugLogging with categories switches exactly those; with none, all of them.
#[test]
fn set_debug_logging_switches_the_named_categories() {
    let fmu = Fmu::new(false);
    let calls = [c"logCalls".as_ptr()];
    assert_eq!(
        unsafe { fmu::fmi2SetDebugLogging(fmu.c, fmi2True, 1, calls.as_ptr()) },
        fmi2OK
    );
    fmu.clear();
    fmu.init();
    let categories: Vec<String> = fmu.records().into_iter().map(|r| r.category).collect();
    assert_eq!(categories, ["logCalls"; 3], "trace only, no info message");

    assert_eq!(
        unsafe { fmu::fmi2SetDebugLogging(fmu.c, fmi2False, 0, null()) },
        fmi2OK
    );
    fmu.clear();
    fmu.step(0.0, 0.01);
    assert!(fmu.records().is_empty());
}
