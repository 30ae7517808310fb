//! What reaches the master's logger, under which category, with which arguments; for both
//! FMI versions (FMI 2.0's logger is variadic and gets the instance name; FMI 3.0's gets
//! the instance environment only, and a message the FMU formatted).
use crate::common;

use common::{vr, Osc, Status, Version};
use fmi_testkit::Record;

fn category(r: &Record) -> &str {
    r.category.as_deref().unwrap_or_default()
}

fn environment_and_instance_name_are_passed_back_on_every_message<D: Osc>() {
    let fmu = D::open_as(common::Interface::CoSimulation, "lander-1", true);
    fmu.initialize();
    fmu.set_real(vr::U, f64::NAN);
    let records = fmu.logger().all();
    assert!(records.len() > 3);
    // Every message reached this instance's logger through the environment it was given
    // (the sink is read through it); FMI 2.0 passes the instance name with each, FMI 3.0's
    // logMessage has no such argument.
    let expected = match D::VERSION {
        Version::Fmi2 => Some("lander-1".to_string()),
        Version::Fmi3 => None,
    };
    assert!(records.iter().all(|r| r.instance_name == expected));
}

/// The layer passes every message as the argument of a fixed "%s" format (FMI 2.0), or as
/// the message itself (FMI 3.0): text with conversion specifiers in it reaches the master
/// unchanged (the kit's FMI 2.0 logger formats with vsnprintf, as a C master does).
fn a_message_with_conversion_specifiers_arrives_verbatim<D: Osc>() {
    let fmu = D::open(true);
    let label = "100% %s %d %n %%";
    assert_eq!(fmu.set_string(vr::LABEL, label), Status::Ok);
    fmu.initialize();
    assert!(
        fmu.messages()
            .iter()
            .any(|m| m.contains(&format!("{label}: x0 ="))),
        "{:?}",
        fmu.messages()
    );
}

fn with_logging_off_only_warnings_errors_and_fatals_are_passed_on<D: Osc>() {
    let fmu = D::open(false);
    fmu.set_boolean(vr::STOP_AT_THRESHOLD, true);
    fmu.set_real(vr::THRESHOLD, 0.99999);
    fmu.initialize();
    // The threshold ends the run: FMI 2.0 fmi2Discard; FMI 3.0 fmi3OK with
    // terminateSimulation (neither is a warning or an error).
    let step = fmu.step(0.0, 0.01);
    assert!(step.terminated, "{step:?}");
    match D::VERSION {
        Version::Fmi2 => assert_eq!(step.status, Status::Discard),
        Version::Fmi3 => assert_eq!(step.status, Status::Ok),
    }
    let records = fmu.logger().all();
    assert!(records.is_empty(), "no trace, info or discard: {records:?}");
    fmu.set_real(vr::U, f64::NAN);
    let records = fmu.logger().all();
    assert_eq!(records.len(), 1);
    assert_eq!(category(&records[0]), "logStatusError");
}

fn with_logging_on_calls_are_traced_with_their_arguments<D: Osc>() {
    let fmu = D::open(true);
    fmu.initialize();
    fmu.clear_log();
    assert_eq!(fmu.set_reals(&[vr::U, vr::K], &[0.25, 2.0]), Status::Ok);
    fmu.step(0.0, 0.01);
    let calls: Vec<String> = fmu
        .logger()
        .all()
        .into_iter()
        .filter(|r| category(r) == "logCalls")
        .filter_map(|r| r.message)
        .collect();
    let expected = match D::VERSION {
        Version::Fmi2 => [
            "fmi2SetReal(nvr=2, vr=[4, 1], value=[0.25, 2.0])",
            "fmi2DoStep(currentCommunicationPoint=0, communicationStepSize=0.01, noSetFMUStatePriorToCurrentPoint=1)",
        ],
        Version::Fmi3 => [
            "fmi3SetFloat64(vr=[4, 1], values=[0.25, 2.0])",
            "fmi3DoStep(currentCommunicationPoint=0, communicationStepSize=0.01, noSetFMUStatePriorToCurrentPoint=true)",
        ],
    };
    assert_eq!(calls, expected);
}

fn model_info_messages_are_logged_under_status_ok_when_on<D: Osc>() {
    let fmu = D::open(true);
    fmu.set_string(vr::LABEL, "osc-7");
    fmu.initialize();
    let info = fmu
        .logger()
        .all()
        .into_iter()
        .find(|r| category(r) == "logStatusOK")
        .expect("info");
    assert_eq!(Status::from(info.status), Status::Ok);
    assert_eq!(
        info.message.as_deref().unwrap_or_default(),
        format!(
            "{}: osc-7: x0 = 1 m, k = 1 N/m, c = 0.1 N.s/m",
            D::f("ExitInitializationMode")
        )
    );
}

/// SetDebugLogging with categories switches exactly those; with none, all of them.
fn set_debug_logging_switches_the_named_categories<D: Osc>() {
    let fmu = D::open(false);
    assert_eq!(
        fmu.set_debug_logging_categories(true, &["logCalls"]),
        Status::Ok
    );
    fmu.clear_log();
    fmu.initialize();
    let categories: Vec<String> = fmu
        .logger()
        .all()
        .iter()
        .map(|r| category(r).to_string())
        .collect();
    // FMI 2.0: fmi2SetupExperiment, then enter and exit; FMI 3.0: enter and exit.
    let calls = match D::VERSION {
        Version::Fmi2 => 3,
        Version::Fmi3 => 2,
    };
    assert_eq!(
        categories,
        vec!["logCalls"; calls],
        "trace only, no info message"
    );

    assert_eq!(fmu.set_debug_logging_categories(false, &[]), Status::Ok);
    fmu.clear_log();
    fmu.step(0.0, 0.01);
    assert!(fmu.logger().all().is_empty());
}

/// A warning that comes at every step is logged once, with the time it first came; each
/// step still answers Warning; termination says how often it came; a reset starts afresh.
fn a_repeated_warning_is_logged_once_and_summarised_at_termination<D: Osc>() {
    const H: f64 = 0.01;
    let fmu = D::open(false);
    fmu.set_real(vr::K, 1e4);
    fmu.set_integer(vr::SUBSTEPS, 1);
    fmu.initialize();
    // The first step warns; the repeats, counted and not logged, leave the status OK (a
    // Warning is a message for the master to show, and there is none).
    for k in 0..100 {
        let expected = if k == 0 { Status::Warning } else { Status::Ok };
        assert_eq!(fmu.step(k as f64 * H, H).status, expected, "step {k}");
    }
    let coarse = |m: &String| m.contains("is coarse");
    let messages = fmu.messages();
    assert_eq!(
        messages.iter().filter(|m| coarse(m)).count(),
        1,
        "{messages:?}"
    );
    assert!(messages[0].contains("[first at t = 0 s;"), "{messages:?}");
    fmu.clear_log();
    assert_eq!(fmu.terminate(), Status::Warning);
    let summary = fmu.messages();
    assert_eq!(summary.len(), 1, "{summary:?}");
    assert!(
        summary[0].starts_with(&format!(
            "{}: this warning came 100 times from t = 0 s to t = 0.99",
            D::f("Terminate")
        )) && summary[0].contains("sub-step 0.01 s is coarse"),
        "{summary:?}"
    );
    // AND after a reset the same warning is news again, and a run without repeats ends
    // without a summary
    assert_eq!(fmu.reset(), Status::Ok);
    fmu.set_real(vr::K, 1e4);
    fmu.set_integer(vr::SUBSTEPS, 1);
    fmu.initialize();
    fmu.clear_log();
    assert_eq!(fmu.step(0.0, H).status, Status::Warning);
    assert_eq!(fmu.messages().iter().filter(|m| coarse(m)).count(), 1);
    fmu.clear_log();
    assert_eq!(fmu.terminate(), Status::Ok);
    assert!(fmu.messages().is_empty(), "{:?}", fmu.messages());
}

both!(
    a_repeated_warning_is_logged_once_and_summarised_at_termination,
    environment_and_instance_name_are_passed_back_on_every_message,
    a_message_with_conversion_specifiers_arrives_verbatim,
    with_logging_off_only_warnings_errors_and_fatals_are_passed_on,
    with_logging_on_calls_are_traced_with_their_arguments,
    model_info_messages_are_logged_under_status_ok_when_on,
    set_debug_logging_switches_the_named_categories,
);
