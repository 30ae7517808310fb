//! Each class of bad input: its status and the one log line naming function, variable and
//! value; a refused call changes nothing.
use crate::common;

use common::{callbacks, guid, records_of, vr, Fmu, Sink};
use fmi_testkit::fmi2::*;
use fmu_testmodel as fmu;
use std::ffi::CString;
use std::ptr::{null, null_mut};

fn refused(fmu: &Fmu, status: fmi2Status, line: &str) {
    assert_eq!(status, fmi2Error, "{:?}", fmu.messages());
    let last = fmu.records().pop().expect("a log line");
    assert_eq!(last.status, fmi2Error);
    assert_eq!(last.category, "logStatusError");
    assert_eq!(last.message, line);
}

#[test]
fn null_instance_is_an_error() {
    unsafe {
        assert_eq!(fmu::fmi2DoStep(null_mut(), 0.0, 0.1, 0), fmi2Error);
        assert_eq!(fmu::fmi2SetReal(null_mut(), &0, 1, &1.0), fmi2Error);
        assert_eq!(fmu::fmi2Reset(null_mut()), fmi2Error);
    }
}

#[test]
fn null_arrays_with_nvr_above_zero_are_errors_and_nvr_zero_is_fine() {
    let fmu = Fmu::new(false);
    fmu.init();
    let mut x = 0.0;
    refused(
        &fmu,
        unsafe { fmu::fmi2GetReal(fmu.c, null(), 1, &mut x) },
        "fmi2GetReal: argument vr is NULL",
    );
    refused(
        &fmu,
        unsafe { fmu::fmi2GetReal(fmu.c, &vr::X, 1, null_mut()) },
        "fmi2GetReal: argument value is NULL",
    );
    refused(
        &fmu,
        unsafe { fmu::fmi2SetString(fmu.c, &vr::LABEL, 1, null()) },
        "fmi2SetString: argument value is NULL",
    );
    assert_eq!(
        unsafe { fmu::fmi2GetReal(fmu.c, null(), 0, null_mut()) },
        fmi2OK
    );
    assert_eq!(
        unsafe { fmu::fmi2SetInteger(fmu.c, null(), 0, null()) },
        fmi2OK
    );
}

#[test]
fn unknown_and_wrongly_typed_value_references_are_named() {
    let fmu = Fmu::new(false);
    fmu.init();
    let mut i = 0;
    refused(
        &fmu,
        fmu.set_real(99, 1.0),
        "fmi2SetReal: unknown value reference 99 for type Real",
    );
    // vr 5 is the Real x; there is no Integer 5.
    refused(
        &fmu,
        unsafe { fmu::fmi2GetInteger(fmu.c, &vr::X, 1, &mut i) },
        "fmi2GetInteger: unknown value reference 5 for type Integer",
    );
}

#[test]
fn variables_that_cannot_be_set_are_refused_by_causality_variability_and_state() {
    let fmu = Fmu::new(false);
    refused(
        &fmu,
        fmu.set_real(vr::MASS, 2.0),
        "fmi2SetReal: variable mass (vr 8) cannot be set: a constant is never settable",
    );
    refused(
        &fmu,
        fmu.set_real(vr::X, 2.0),
        "fmi2SetReal: variable x (vr 5) cannot be set: an output is computed by the FMU",
    );
    refused(&fmu, fmu.set_real(vr::OMEGA_N, 2.0), "fmi2SetReal: variable omega_n (vr 7) cannot be set: a calculated parameter is computed by the FMU");
    fmu.init();
    refused(
        &fmu,
        fmu.set_real(vr::X0, 2.0),
        "fmi2SetReal: variable x0 (vr 0) cannot be set: a fixed parameter can only be set before the end of initialization",
    );
    assert_eq!(fmu.get_real(vr::X0), 1.0);
    // Tunable parameters and inputs may change between steps.
    assert_eq!(fmu.set_real(vr::K, 2.0), fmi2OK);
    assert_eq!(fmu.set_real(vr::U, 2.0), fmi2OK);
    assert_eq!(
        fmu.get_real(vr::OMEGA_N),
        2f64.sqrt(),
        "calculated parameter follows k"
    );
}

#[test]
fn non_finite_reals_are_refused_naming_variable_and_value() {
    let fmu = Fmu::new(false);
    fmu.init();
    refused(
        &fmu,
        fmu.set_real(vr::U, f64::NAN),
        "fmi2SetReal: variable u (vr 4): value NaN is not finite",
    );
    refused(
        &fmu,
        fmu.set_real(vr::U, f64::INFINITY),
        "fmi2SetReal: variable u (vr 4): value inf is not finite",
    );
    refused(
        &fmu,
        fmu.set_real(vr::THRESHOLD, f64::NEG_INFINITY),
        "fmi2SetReal: variable threshold (vr 3): value -inf is not finite",
    );
}

#[test]
fn bounds_of_the_table_are_enforced() {
    let fmu = Fmu::new(false);
    refused(
        &fmu,
        fmu.set_real(vr::K, -1.0),
        "fmi2SetReal: variable k (vr 1): value -1 N/m is outside [0, inf) N/m",
    );
    refused(
        &fmu,
        fmu.set_integer(vr::SUBSTEPS, 0),
        "fmi2SetInteger: variable substeps (vr 13): value 0 is outside [1, 1000]",
    );
    refused(
        &fmu,
        fmu.set_integer(vr::SUBSTEPS, 1001),
        "fmi2SetInteger: variable substeps (vr 13): value 1001 is outside [1, 1000]",
    );
    refused(
        &fmu,
        fmu.set_integer(vr::CROSSING, 7),
        "fmi2SetInteger: variable crossing_direction (vr 14): value 7 is not an item of enumeration \
         Oscillator.Crossing: allowed 1 (either), 2 (falling), 3 (rising)",
    );
    assert_eq!(
        fmu.set_real(vr::K, 0.0),
        fmi2OK,
        "the bound itself is inside"
    );
}

/// One bad value in a batch: nothing of the batch is written.
#[test]
fn a_refused_batch_writes_nothing() {
    let fmu = Fmu::new(false);
    fmu.init();
    let refs = [vr::U, vr::K];
    let values = [5.0, -1.0];
    let status = unsafe { fmu::fmi2SetReal(fmu.c, refs.as_ptr(), 2, values.as_ptr()) };
    assert_eq!(status, fmi2Error);
    assert_eq!(fmu.get_real(vr::U), 0.0);
    assert_eq!(fmu.get_real(vr::K), 1.0);
}

#[test]
fn invalid_strings_are_refused() {
    let fmu = Fmu::new(false);
    let p: fmi2String = null();
    refused(
        &fmu,
        unsafe { fmu::fmi2SetString(fmu.c, &vr::LABEL, 1, &p) },
        "fmi2SetString: variable label (vr 16): value is a NULL string",
    );
    let latin1 = b"caf\xe9\0";
    let p = latin1.as_ptr() as fmi2String;
    refused(
        &fmu,
        unsafe { fmu::fmi2SetString(fmu.c, &vr::LABEL, 1, &p) },
        "fmi2SetString: variable label (vr 16): value is not valid UTF-8",
    );
}

#[test]
fn bad_step_sizes_and_communication_points_are_refused() {
    let fmu = Fmu::new(false);
    fmu.init();
    refused(
        &fmu,
        fmu.step(0.0, 0.0),
        "fmi2DoStep: communicationStepSize 0 is not a finite positive number",
    );
    refused(
        &fmu,
        fmu.step(0.0, -0.01),
        "fmi2DoStep: communicationStepSize -0.01 is not a finite positive number",
    );
    refused(
        &fmu,
        fmu.step(0.0, f64::NAN),
        "fmi2DoStep: communicationStepSize NaN is not a finite positive number",
    );
    refused(
        &fmu,
        fmu.step(0.5, 0.01),
        "fmi2DoStep: currentCommunicationPoint 0.5 does not match the FMU's time 0 (relative tolerance 1e-9)",
    );
    assert_eq!(fmu.step(1e-10, 0.01), fmi2OK, "inside the tolerance");
    refused(
        &fmu,
        fmu.step(0.01 + 2e-9, 0.01),
        &format!(
            "fmi2DoStep: currentCommunicationPoint {} does not match the FMU's time {} (relative tolerance 1e-9)",
            0.01 + 2e-9,
            1e-10 + 0.01
        ),
    );
    assert_eq!(
        fmu.get_integer(vr::STEP_COUNT),
        1,
        "refused steps did not run"
    );
}

#[test]
fn setup_experiment_refuses_a_stop_before_the_start() {
    let fmu = Fmu::new(false);
    refused(
        &fmu,
        fmu.setup(1.0, Some(0.5)),
        "fmi2SetupExperiment: stopTime 0.5 is not a finite time at or after startTime 1",
    );
    refused(
        &fmu,
        fmu.setup(f64::NAN, None),
        "fmi2SetupExperiment: startTime NaN is not finite",
    );
}

#[test]
fn unsupported_functions_log_and_refuse() {
    let fmu = Fmu::new(false);
    fmu.init();
    let mut x = 0.0;
    refused(
        &fmu,
        unsafe { fmu::fmi2GetDirectionalDerivative(fmu.c, &vr::X, 1, &vr::U, 1, &1.0, &mut x) },
        "fmi2GetDirectionalDerivative: not provided (providesDirectionalDerivative = false)",
    );
    refused(
        &fmu,
        unsafe { fmu::fmi2SetRealInputDerivatives(fmu.c, &vr::U, 1, &1, &1.0) },
        "fmi2SetRealInputDerivatives: not supported (canInterpolateInputs = false)",
    );
    refused(
        &fmu,
        unsafe { fmu::fmi2GetRealOutputDerivatives(fmu.c, &vr::X, 1, &1, &mut x) },
        "fmi2GetRealOutputDerivatives: not supported (maxOutputDerivativeOrder = 0)",
    );
    refused(
        &fmu,
        unsafe { fmu::fmi2CancelStep(fmu.c) },
        "fmi2CancelStep: illegal call in state StepComplete",
    );
}

#[test]
fn status_queries_answer_what_they_can_and_discard_the_rest() {
    let fmu = Fmu::new(true);
    fmu.init();
    let mut status = fmi2OK;
    let mut i = 0;
    let mut x = 0.0;
    assert_eq!(
        unsafe { fmu::fmi2GetStatus(fmu.c, fmi2DoStepStatus, &mut status) },
        fmi2Discard
    );
    assert_eq!(fmu.last_message(), "fmi2GetStatus: fmi2DoStepStatus is not available as an fmi2Status (no asynchronous steps here)");
    assert_eq!(
        unsafe { fmu::fmi2GetIntegerStatus(fmu.c, fmi2LastSuccessfulTime, &mut i) },
        fmi2Discard
    );
    assert_eq!(
        unsafe { fmu::fmi2GetRealStatus(fmu.c, fmi2Terminated, &mut x) },
        fmi2Discard
    );
    refused(
        &fmu,
        unsafe { fmu::fmi2GetRealStatus(fmu.c, 42, &mut x) },
        "fmi2GetRealStatus: status kind 42 is not an fmi2StatusKind",
    );
    refused(
        &fmu,
        unsafe { fmu::fmi2GetRealStatus(fmu.c, fmi2LastSuccessfulTime, null_mut()) },
        "fmi2GetRealStatus: argument value is NULL",
    );
}

#[test]
fn unknown_log_categories_are_refused_by_name() {
    let fmu = Fmu::new(false);
    let names = [c"logCalls".as_ptr(), c"logEverything".as_ptr()];
    refused(
        &fmu,
        unsafe { fmu::fmi2SetDebugLogging(fmu.c, fmi2True, 2, names.as_ptr()) },
        "fmi2SetDebugLogging: unknown log category \"logEverything\" (this FMU has logStatusOK, \
         logStatusWarning, logStatusDiscard, logStatusError, logStatusFatal, logCalls)",
    );
    // Nothing was switched on: a call is not traced.
    fmu.clear();
    fmu.setup(0.0, None);
    assert!(fmu.records().is_empty());
    refused(
        &fmu,
        unsafe { fmu::fmi2SetDebugLogging(fmu.c, fmi2True, 1, null()) },
        "fmi2SetDebugLogging: argument categories is NULL",
    );
}

/// Instantiate refuses every mismatch with NULL and a log line.
#[test]
fn instantiate_checks_type_guid_name_and_callbacks() {
    let sink = Sink::default();
    let functions = callbacks(&sink);
    let try_instantiate = |name: fmi2String,
                           kind: fmi2Type,
                           guid: fmi2String,
                           functions: *const fmi2CallbackFunctions| unsafe {
        fmu::fmi2Instantiate(name, kind, guid, null(), functions, fmi2False, fmi2False)
    };
    let last = || {
        records_of(&sink)
            .last()
            .map(|r| r.message.clone())
            .unwrap_or_default()
    };
    let g = guid();

    let c = try_instantiate(c"a".as_ptr(), fmi2ModelExchange, g.as_ptr(), &functions);
    assert!(c.is_null());
    assert_eq!(last(), "fmi2Instantiate: fmuType fmi2ModelExchange is not supported: Oscillator implements Co-Simulation (fmi2CoSimulation = 1) only");
    assert!(try_instantiate(c"a".as_ptr(), 7, g.as_ptr(), &functions).is_null());
    assert_eq!(
        last(),
        "fmi2Instantiate: fmuType 7 is neither fmi2ModelExchange (0) nor fmi2CoSimulation (1)"
    );

    let wrong = CString::new("{00000000-0000-0000-0000-000000000000}").unwrap();
    assert!(try_instantiate(c"a".as_ptr(), fmi2CoSimulation, wrong.as_ptr(), &functions).is_null());
    assert_eq!(
        last(),
        format!("fmi2Instantiate: fmuGUID \"{{00000000-0000-0000-0000-000000000000}}\" does not match this FMU's {}", g.to_str().unwrap())
    );
    assert!(try_instantiate(c"a".as_ptr(), fmi2CoSimulation, null(), &functions).is_null());
    assert!(last().starts_with("fmi2Instantiate: fmuGUID NULL does not match"));

    assert!(try_instantiate(c"".as_ptr(), fmi2CoSimulation, g.as_ptr(), &functions).is_null());
    assert_eq!(last(), "fmi2Instantiate: instanceName is NULL or empty");
    assert!(try_instantiate(null(), fmi2CoSimulation, g.as_ptr(), &functions).is_null());
    assert_eq!(last(), "fmi2Instantiate: instanceName is NULL or empty");

    // Without callbacks or logger there is nobody to tell: just NULL.
    let before = sink.len();
    assert!(try_instantiate(c"a".as_ptr(), fmi2CoSimulation, g.as_ptr(), null()).is_null());
    let no_logger = fmi2CallbackFunctions {
        logger: None,
        ..functions
    };
    assert!(try_instantiate(c"a".as_ptr(), fmi2CoSimulation, g.as_ptr(), &no_logger).is_null());
    assert_eq!(sink.len(), before);

    // allocateMemory/freeMemory may be NULL: canNotUseMemoryManagementFunctions = true.
    let c = try_instantiate(c"a".as_ptr(), fmi2CoSimulation, g.as_ptr(), &functions);
    assert!(!c.is_null());
    unsafe { fmu::fmi2FreeInstance(c) };
}

/// The instance copies its strings: the caller's buffers may die right after Instantiate.
#[test]
fn instantiate_copies_the_strings_it_is_given() {
    let sink = Box::<Sink>::default();
    let functions = callbacks(&sink);
    let name = CString::new("short-lived").unwrap();
    let g = guid();
    let c = unsafe {
        fmu::fmi2Instantiate(
            name.as_ptr(),
            fmi2CoSimulation,
            g.as_ptr(),
            null(),
            &functions,
            0,
            0,
        )
    };
    drop(name);
    drop(g);
    unsafe { fmu::fmi2DoStep(c, 0.0, 1.0, 0) };
    let record = records_of(&sink).pop().unwrap();
    assert_eq!(record.instance, "short-lived");
    unsafe { fmu::fmi2FreeInstance(c) };
}

// ---- Both versions, through the kit's driver ----

use common::{Osc, Status};

/// Values outside the declared bounds, non-finite values and variables that may not be set
/// are refused naming the variable, in each version, and change nothing.
fn bad_values_are_refused_by_name_in_each_version<D: Osc>() {
    let fmu = D::open(false);
    assert_eq!(fmu.enter_initialization_mode(0.0, None), Status::Ok);
    let refused = |status: Status, line: String| {
        assert_eq!(status, Status::Error, "{line}");
        assert_eq!(fmu.last_message(), line);
    };
    let set = D::real_fn(true);
    refused(
        fmu.set_real(vr::MASS, 2.0),
        format!("{set}: variable mass (vr 8) cannot be set: a constant is never settable"),
    );
    refused(
        fmu.set_real(vr::U, f64::NAN),
        format!("{set}: variable u (vr 4): value NaN is not finite"),
    );
    refused(
        fmu.set_real(vr::K, -1.0),
        format!("{set}: variable k (vr 1): value -1 N/m is outside [0, inf) N/m"),
    );
    refused(
        fmu.set_integer(vr::SUBSTEPS, 0),
        format!(
            "{}: variable substeps (vr 13): value 0 is outside [1, 1000]",
            D::integer_setter()
        ),
    );
    assert_eq!(fmu.real(vr::K), 1.0, "a refused set changes nothing");
    assert_eq!(fmu.integer(vr::SUBSTEPS), 8);
}

both!(bad_values_are_refused_by_name_in_each_version);
