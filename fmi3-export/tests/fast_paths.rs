//! The fast paths of fmi3GetFloat64, fmi3SetFloat64 and fmi3DoStep on a model of their own
//! (exported into this test binary): tracing, fresh outputs, refusals as on the full path.
#![allow(unsafe_code)]

use fmi3_export::ffi::*;
use fmi_model::{decl, Declaration};
use fmi_testkit::{CoSimulationOptions, Fmi3Instance};
use serde::{Deserialize, Serialize};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

/// A model whose Float64s all lie in its own bytes (what the fast paths serve): `y = 2 u`
/// computed before a get, a bounded input `g` in [0, 1], and a step that adds 1 to `u`. Its
/// step also calls into the instance it belongs to (the handle in `NESTED_INTO`), as a
/// master's callback could.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
struct Doubler {
    u: f64,
    y: f64,
    g: f64,
}

static DOUBLER: [Declaration<Doubler>; 3] = [
    decl!(0, input u: u, "1", ""),
    decl!(1, output y: y, "1", ""),
    decl!(2, input g: g, "1", "", min = 0.0, max = 1.0),
];

/// The instance a step of a `Doubler` calls into (0: none), and what those calls returned.
static NESTED_INTO: AtomicUsize = AtomicUsize::new(0);
static NESTED_STATUSES: Mutex<Vec<fmi3Status>> = Mutex::new(Vec::new());

fmi_testkit::test_model!(
    Doubler,
    DOUBLER,
    "y = 2 u",
    calculate = |m| m.y = 2.0 * m.u,
    step = |m| {
        m.u += 1.0;
        // Taken, so that a nested step, were it admitted, would not nest again.
        let c = NESTED_INTO.swap(0, Ordering::SeqCst) as fmi3Instance;
        if !c.is_null() {
            let (mut y, u) = (0.0, 0.5);
            let (mut event, mut terminate, mut early, mut last) = (false, false, false, 0.0);
            let statuses = unsafe {
                [
                    fmi3GetFloat64(c, &1, 1, &mut y, 1),
                    fmi3SetFloat64(c, &0, 1, &u, 1),
                    fmi3DoStep(
                        c,
                        0.0,
                        0.1,
                        true,
                        &mut event,
                        &mut terminate,
                        &mut early,
                        &mut last,
                    ),
                ]
            };
            NESTED_STATUSES.lock().unwrap().extend(statuses);
        }
    }
);

fmi3_export::export_fmi3!(Doubler);

/// A `Doubler` in step mode at t = 0, with the logger's messages so far cleared.
fn stepping_doubler(functions: &fmi_testkit::Fmi3Functions) -> Fmi3Instance {
    let token = fmi3_export::instantiation_token::<Doubler>();
    let fmu = Fmi3Instance::co_simulation(functions, "d", &token, CoSimulationOptions::default())
        .expect("instantiated");
    assert_eq!(fmu.enter_initialization_mode(0.0, None), fmi3OK);
    assert_eq!(fmu.exit_initialization_mode(), fmi3OK);
    fmu.logger().clear();
    fmu
}

/// `fmi3SetDebugLogging` for the `logCalls` category alone.
fn log_calls(fmu: &Fmi3Instance, on: bool) -> fmi3Status {
    let categories = [c"logCalls".as_ptr()];
    // SAFETY: a live instance and one valid category name.
    unsafe { (fmu.functions().set_debug_logging)(fmu.instance(), on, 1, categories.as_ptr()) }
}

/// The outputs a get returns are those of the inputs set and the steps taken just before,
/// whichever path serves the get.
#[test]
fn a_get_right_after_a_set_or_a_step_sees_the_new_outputs() {
    let functions = fmi_testkit::fmi3_functions!(crate);
    let fmu = stepping_doubler(&functions);
    let get = || {
        let (status, y) = fmu.get_float64(&[1], 1);
        assert_eq!(status, fmi3OK);
        y[0]
    };
    assert_eq!(get(), 0.0);
    for u in [1.0, -3.0, 0.25] {
        assert_eq!(fmu.set_float64(&[0], &[u]), fmi3OK);
        assert_eq!(get(), 2.0 * u);
        // Again, with nothing changed in between.
        assert_eq!(get(), 2.0 * u);
    }
    let mut t = 0.0;
    for k in 1..=3 {
        assert_eq!(fmu.do_step(t, 0.5).status, fmi3OK);
        t += 0.5;
        assert_eq!(get(), 2.0 * (0.25 + f64::from(k)));
    }
    assert!(fmu.messages().is_empty(), "{:?}", fmu.messages());
}

/// With `logCalls` switched on during a run, every get, set and step is traced from the
/// next call on; switched off again, none is.
#[test]
fn log_calls_switched_on_mid_run_traces_every_exchange_call() {
    let functions = fmi_testkit::fmi3_functions!(crate);
    let fmu = stepping_doubler(&functions);
    let exchange = |t: f64| {
        assert_eq!(fmu.set_float64(&[0], &[1.0]), fmi3OK);
        assert_eq!(fmu.get_float64(&[1], 1).0, fmi3OK);
        assert_eq!(fmu.do_step(t, 0.5).status, fmi3OK);
    };
    exchange(0.0);
    assert!(fmu.messages().is_empty(), "{:?}", fmu.messages());
    assert_eq!(log_calls(&fmu, true), fmi3OK);
    fmu.logger().clear();
    exchange(0.5);
    let traced = fmu.messages();
    assert_eq!(traced.len(), 3, "{traced:?}");
    for (message, function) in
        traced
            .iter()
            .zip(["fmi3SetFloat64(", "fmi3GetFloat64(", "fmi3DoStep("])
    {
        assert!(message.starts_with(function), "{traced:?}");
    }
    assert_eq!(log_calls(&fmu, false), fmi3OK);
    fmu.logger().clear();
    exchange(1.0);
    assert!(fmu.messages().is_empty(), "{:?}", fmu.messages());
}

/// A get, set or step on an instance while its step runs (here from inside the model, as
/// from a master's callback) is refused with fmi3Error and a log line, changes nothing,
/// and the outer step goes on.
#[test]
fn a_call_on_a_busy_instance_is_refused_and_logged() {
    let functions = fmi_testkit::fmi3_functions!(crate);
    let fmu = stepping_doubler(&functions);
    NESTED_INTO.store(fmu.instance() as usize, Ordering::SeqCst);
    let step = fmu.do_step(0.0, 0.5);
    NESTED_INTO.store(0, Ordering::SeqCst);
    assert_eq!(step.status, fmi3OK);
    assert_eq!(
        std::mem::take(&mut *NESTED_STATUSES.lock().unwrap()),
        [fmi3Error; 3]
    );
    let messages = fmu.messages();
    assert_eq!(messages.len(), 3, "{messages:?}");
    for (message, function) in
        messages
            .iter()
            .zip(["fmi3GetFloat64", "fmi3SetFloat64", "fmi3DoStep"])
    {
        assert_eq!(
            *message,
            format!(
                "{function}: refused: another call on this instance has not returned yet \
                 (a call from inside one of its callbacks, or from a second thread)"
            )
        );
    }
    // The refused set changed nothing: u is 0 + 1 from the one step.
    assert_eq!(fmu.get_float64(&[1], 1), (fmi3OK, vec![2.0]));
}

/// A non-finite or out-of-bounds value is refused by fmi3SetFloat64 with the log line of
/// the full path (the path `logCalls` takes), and nothing it carried is written.
#[test]
fn a_bad_value_set_is_refused_as_on_the_full_path_and_changes_nothing() {
    let functions = fmi_testkit::fmi3_functions!(crate);
    let fmu = stepping_doubler(&functions);
    assert_eq!(fmu.set_float64(&[0, 2], &[0.5, 0.5]), fmi3OK);
    for (vrs, values) in [
        (&[0][..], &[f64::NAN][..]),
        (&[0], &[f64::INFINITY]),
        (&[2], &[1.5]),
        (&[2], &[-0.25]),
        (&[0, 2], &[0.75, f64::NEG_INFINITY]),
    ] {
        fmu.logger().clear();
        assert_eq!(fmu.set_float64(vrs, values), fmi3Error, "{values:?}");
        let fast = fmu.messages();
        assert_eq!(fast.len(), 1, "{fast:?}");
        // The same call through the full path (taken while calls are traced).
        assert_eq!(log_calls(&fmu, true), fmi3OK);
        fmu.logger().clear();
        assert_eq!(fmu.set_float64(vrs, values), fmi3Error, "{values:?}");
        assert_eq!(fmu.last_message(), fast[0]);
        assert_eq!(log_calls(&fmu, false), fmi3OK);
        assert!(fast[0].starts_with("fmi3SetFloat64: "), "{fast:?}");
        // Nothing written: neither u (through y) nor g changed.
        assert_eq!(fmu.get_float64(&[1, 2], 2), (fmi3OK, vec![1.0, 0.5]));
    }
}

/// A get whose value is not finite is refused, whichever path serves it, and answers
/// again once the inputs give a finite value.
#[test]
fn a_non_finite_output_is_refused_by_the_fast_get() {
    let functions = fmi_testkit::fmi3_functions!(crate);
    let fmu = stepping_doubler(&functions);
    assert_eq!(fmu.set_float64(&[0], &[f64::MAX]), fmi3OK);
    fmu.logger().clear();
    let (status, _) = fmu.get_float64(&[1], 1);
    assert_eq!(status, fmi3Error);
    let message = fmu.last_message();
    assert!(
        message.starts_with("fmi3GetFloat64: variable y (vr 1) is inf"),
        "{message}"
    );
    assert_eq!(fmu.set_float64(&[0], &[0.5]), fmi3OK);
    assert_eq!(fmu.get_float64(&[1], 1), (fmi3OK, vec![1.0]));
}
