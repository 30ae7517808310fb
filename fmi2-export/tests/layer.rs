//! The layer with small models of its own, driven through the generic `abi` functions:
//! panics become fmi2Fatal, the GUID follows the interface only, `check_table` finds
//! broken tables, a repeated list of references is refused like a new one.
#![allow(unsafe_code)]

use fmi2_export::ffi::*;
use fmi2_export::*;
use fmi_model::Kind;
use fmi_testkit::TestLogger;
use serde::{Deserialize, Serialize};
use std::ffi::CString;

/// The FMI 2.0 face of the core's argument-free lifecycle calls (the layer exports them
/// through `export_shared!`).
mod lifecycle {
    use fmi2_export::ffi::{fmi2Component, fmi2Status};
    use fmi2_export::state::Function;
    use fmi2_export::{Fmi2, Model};
    use fmi_export::Abi;

    pub unsafe fn exit_initialization_mode<M: Model>(c: fmi2Component) -> fmi2Status {
        let f = Function::ExitInitializationMode;
        Fmi2::status(unsafe { fmi_export::raw::exit_initialization_mode::<M, Fmi2>(c, f) })
    }

    pub unsafe fn reset<M: Model>(c: fmi2Component) -> fmi2Status {
        Fmi2::status(unsafe { fmi_export::raw::reset::<M, Fmi2>(c, Function::Reset) })
    }
}

// ---- a model that panics in do_step ----------------------------------------------------

#[derive(Debug, Clone, Default, Serialize, Deserialize)]
struct Panicky {
    y: f64,
}

static PANICKY: [Declaration<Panicky>; 1] = [decl!(0, output y: y, "1", "")];

fmi_testkit::test_model!(
    Panicky,
    PANICKY,
    "panics in do_step",
    step = |_| panic!("boom")
);

/// A panic inside a model call is caught: fmi2Fatal, a fatal log line, state Fatal (only
/// FreeInstance is accepted afterwards), and nothing unwinds into the caller.
#[test]
fn a_panic_becomes_fatal_and_never_unwinds() {
    let logger = Box::<TestLogger>::default();
    let functions = logger.callbacks();
    let guid = CString::new(guid::<Panicky>()).unwrap();
    unsafe {
        let c = abi::instantiate::<Panicky>(
            c"p".as_ptr(),
            fmi2CoSimulation,
            guid.as_ptr(),
            std::ptr::null(),
            &functions,
            0,
            0,
        );
        assert!(!c.is_null());
        abi::setup_experiment::<Panicky>(c, 0, 0.0, 0.0, 0, 0.0);
        abi::enter_initialization_mode::<Panicky>(c);
        lifecycle::exit_initialization_mode::<Panicky>(c);
        assert_eq!(abi::do_step::<Panicky>(c, 0.0, 0.1, 0), fmi2Fatal);
        let last = logger.all().pop().unwrap();
        assert_eq!(last.status, fmi2Fatal);
        assert_eq!(last.category.as_deref(), Some("logStatusFatal"));
        assert_eq!(
            last.message(),
            "fmi2DoStep: internal error, instance unusable: boom"
        );
        let mut y = 0.0;
        assert_eq!(abi::get_real::<Panicky>(c, &0, 1, &mut y), fmi2Error);
        assert_eq!(
            logger.messages().pop().unwrap(),
            "fmi2GetReal: illegal call in state Fatal"
        );
        assert_eq!(lifecycle::reset::<Panicky>(c), fmi2Error);
        abi::free_instance::<Panicky>(c);
    }
}

/// A component of another model type is refused, not used.
#[test]
fn a_component_of_another_model_is_refused() {
    let logger = Box::<TestLogger>::default();
    let functions = logger.callbacks();
    let guid = CString::new(guid::<Panicky>()).unwrap();
    unsafe {
        let c = abi::instantiate::<Panicky>(
            c"p".as_ptr(),
            fmi2CoSimulation,
            guid.as_ptr(),
            std::ptr::null(),
            &functions,
            0,
            0,
        );
        assert_eq!(lifecycle::reset::<Small>(c), fmi2Error);
        abi::free_instance::<Small>(c); // ignored: not a Small
        assert_eq!(lifecycle::reset::<Panicky>(c), fmi2OK);
        abi::free_instance::<Panicky>(c);
    }
}

// ---- GUID: interface only ----------------------------------------------------------------

macro_rules! small_model {
    ($name:ident, $table:ident, $start:expr, $var:expr) => {
        #[derive(Debug, Clone, Serialize, Deserialize)]
        struct $name {
            a: f64,
        }
        impl Default for $name {
            fn default() -> Self {
                $name { a: $start }
            }
        }
        static $table: [Declaration<$name>; 1] = [$var];
        fmi_testkit::test_model!($name, $table, "", identifier = "Small");
    };
}

small_model!(Small, SMALL, 0.0, decl!(0, input a: a, "m", ""));
small_model!(
    Cosmetic,
    COSMETIC,
    5.0,
    decl!(0, input a: a, "N", "documented")
);
small_model!(Renamed, RENAMED, 0.0, decl!(0, input b: a, "m", ""));
small_model!(Renumbered, RENUMBERED, 0.0, decl!(1, input a: a, "m", ""));
small_model!(Parameter, PARAMETER, 0.0, decl!(0, tunable a: a, "m", ""));

#[test]
fn guid_changes_with_the_interface_and_only_then() {
    let g = guid::<Small>();
    assert!(
        g.starts_with('{') && g.ends_with('}') && g.len() == 38,
        "{g}"
    );
    assert_eq!(&g[15..16], "5", "a version-5 UUID");
    assert_eq!(g, guid::<Small>(), "deterministic");
    assert_eq!(
        g,
        guid::<Cosmetic>(),
        "unit, start and description are not interface"
    );
    assert_ne!(g, guid::<Renamed>());
    assert_ne!(g, guid::<Renumbered>());
    assert_ne!(g, guid::<Parameter>());
    check_table::<Small>().unwrap();
    check_table::<Parameter>().unwrap();
}

// ---- check_table finds broken tables --------------------------------------------------

#[derive(Debug, Clone, Default, Serialize, Deserialize)]
struct Broken {
    a: f64,
    n: i32,
}

static BROKEN: [Declaration<Broken>; 5] = [
    // an input with an initial attribute and an unknown unit
    Declaration {
        initial: Some(Initial::Exact),
        ..decl!(0, input a: a, "furlong", "")
    },
    // same name, same vr; an output with a setter
    Declaration {
        kind: Kind::Real {
            shape: Shape::Scalar,
            min: None,
            max: None,
            get: |m, _| m.a,
            set: Some(|m, _, v| m.a = v),
            place: None,
        },
        ..decl!(0, output a: a, "1", "")
    },
    // start (0) outside [min, max], min > max
    decl!(2, parameter p: a, "1", "", min = 1.0, max = -1.0),
    // a continuous Integer
    Declaration {
        variability: Variability::Continuous,
        ..decl!(0, output n: n as i32, "")
    },
    // a fixed output
    Declaration {
        variability: Variability::Fixed,
        ..decl!(4, output o: a, "1", "")
    },
];

fmi_testkit::test_model!(Broken, BROKEN, "", identifier = "Broken-1", stop = 0.0);

#[test]
fn check_table_reports_every_problem() {
    let problems = check_table::<Broken>().unwrap_err().problems;
    let expected = [
        "modelIdentifier \"Broken-1\" is not a C identifier",
        "DefaultExperiment",
        "a: initial Exact is not allowed for Input/Continuous",
        "a: unit \"furlong\" is not in the unit table",
        "a: declared twice",
        "a: FMI 2.0 name used twice",
        "a: value reference 0 used twice among Real variables",
        "a: a setter exactly for what may be set (has one: true)",
        "p: min 1 > max -1",
        "p: start 0 (element 0) is not finite within the bounds",
        "n: only Real variables can be continuous",
        "o: causality Output with variability Fixed is not allowed",
        "a: field a is declared by two variables",
        "p: field a is declared by two variables",
        "o: field a is declared by two variables",
    ];
    for e in expected {
        assert!(
            problems.iter().any(|p| p.starts_with(e)),
            "missing {e:?} in\n{problems:#?}"
        );
    }
    assert_eq!(problems.len(), expected.len(), "{problems:#?}");
}

#[test]
#[should_panic(expected = "invalid variable table of Broken-1")]
fn no_xml_is_written_for_a_broken_table() {
    model_description_xml::<Broken>();
}

// ---- a model with bounded inputs and a fixed parameter ----------------------------------

#[derive(Debug, Clone, Default, Serialize, Deserialize)]
struct Bounded {
    gain: f64,
    u: [f64; 2],
}

static BOUNDED: [Declaration<Bounded>; 3] = [
    decl!(0, parameter gain: gain, "1", ""),
    decl!(1, input u[2]: u, "1", "", min = 0.0, max = 1.0),
    decl!(3, output y: get |m, _| m.gain * (m.u[0] + m.u[1]), "1", ""),
];

fmi_testkit::test_model!(Bounded, BOUNDED, "bounded inputs");

/// A master repeating one list of references (the case the layer prepares once) gets every
/// refusal the first call of that list would get, with its reason, and a refused call
/// changes nothing.
#[test]
fn a_repeated_list_is_refused_as_a_new_one_and_changes_nothing() {
    let logger = Box::<TestLogger>::default();
    let functions = logger.callbacks();
    let guid = CString::new(guid::<Bounded>()).unwrap();
    let list = [0, 1, 2];
    let all = [0, 1, 2, 3];
    unsafe {
        let c = abi::instantiate::<Bounded>(
            c"b".as_ptr(),
            fmi2CoSimulation,
            guid.as_ptr(),
            std::ptr::null(),
            &functions,
            0,
            0,
        );
        let get = || {
            let mut values = [0.0; 4];
            assert_eq!(
                abi::get_real::<Bounded>(c, all.as_ptr(), 4, values.as_mut_ptr()),
                fmi2OK
            );
            values
        };
        let set = |values: [f64; 3]| abi::set_real::<Bounded>(c, list.as_ptr(), 3, values.as_ptr());
        abi::setup_experiment::<Bounded>(c, 0, 0.0, 0.0, 0, 0.0);
        abi::enter_initialization_mode::<Bounded>(c);
        assert_eq!(set([2.0, 0.25, 0.5]), fmi2OK);
        assert_eq!(get(), [2.0, 0.25, 0.5, 1.5]);
        for (values, name) in [
            ([3.0, 0.25, 1.5], "u[2]"),
            ([3.0, -1.0, 0.5], "u[1]"),
            ([f64::NAN, 0.25, 0.5], "gain"),
        ] {
            assert_eq!(set(values), fmi2Error, "{values:?}");
            let message = logger.messages().pop().unwrap();
            assert!(
                message.starts_with("fmi2SetReal: ") && message.contains(name),
                "{values:?}: {message}"
            );
            assert_eq!(get(), [2.0, 0.25, 0.5, 1.5], "{values:?}");
        }
        lifecycle::exit_initialization_mode::<Bounded>(c);
        // The same list after initialization: the fixed parameter is no longer settable.
        assert_eq!(set([2.0, 0.75, 0.5]), fmi2Error);
        let message = logger.messages().pop().unwrap();
        assert!(message.contains("gain"), "{message}");
        assert_eq!(get(), [2.0, 0.25, 0.5, 1.5]);
        let inputs = [1, 2];
        let values = [0.75, 1.0];
        assert_eq!(
            abi::set_real::<Bounded>(c, inputs.as_ptr(), 2, values.as_ptr()),
            fmi2OK
        );
        assert_eq!(get(), [2.0, 0.75, 1.0, 3.5]);
        abi::free_instance::<Bounded>(c);
    }
}

/// No NaN or infinity reaches the master with an OK status: a read whose value is not
/// finite is refused naming the variable, and the instance answers again once its inputs
/// give finite values.
#[test]
fn a_non_finite_output_is_refused_and_the_instance_stays_usable() {
    let logger = Box::<TestLogger>::default();
    let functions = logger.callbacks();
    let guid = CString::new(guid::<Bounded>()).unwrap();
    unsafe {
        let c = abi::instantiate::<Bounded>(
            c"b".as_ptr(),
            fmi2CoSimulation,
            guid.as_ptr(),
            std::ptr::null(),
            &functions,
            0,
            0,
        );
        abi::setup_experiment::<Bounded>(c, 0, 0.0, 0.0, 0, 0.0);
        abi::enter_initialization_mode::<Bounded>(c);
        // GIVEN a gain whose product with the inputs overflows
        let refs = [0, 1, 2];
        let huge = [f64::MAX, 1.0, 1.0];
        assert_eq!(
            abi::set_real::<Bounded>(c, refs.as_ptr(), 3, huge.as_ptr()),
            fmi2OK
        );
        // WHEN the output is read THEN it is refused, naming it
        let mut y = [0.0];
        assert_eq!(
            abi::get_real::<Bounded>(c, &3, 1, y.as_mut_ptr()),
            fmi2Error
        );
        let message = logger.messages().pop().unwrap();
        assert!(
            message.starts_with("fmi2GetReal: variable y (vr 3) is inf"),
            "{message}"
        );
        // AND with inputs that give a finite value the same read answers
        let fine = [0.25, 0.25];
        assert_eq!(
            abi::set_real::<Bounded>(c, refs[1..].as_ptr(), 2, fine.as_ptr()),
            fmi2OK
        );
        assert_eq!(abi::get_real::<Bounded>(c, &3, 1, y.as_mut_ptr()), fmi2OK);
        assert_eq!(y[0], f64::MAX * 0.5);
        abi::free_instance::<Bounded>(c);
    }
}

// ---- the fast paths of fmi2GetReal, fmi2SetReal and fmi2DoStep ---------------------------

/// A model whose Reals all lie in its own bytes (what the fast paths serve): `y = 2 u`
/// computed before a get, and a step that adds 1 to `u`. Its step also calls into the
/// instance it belongs to (the handle in `NESTED_INTO`), as a master's callback could.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
struct Doubler {
    u: f64,
    y: f64,
}

static DOUBLER: [Declaration<Doubler>; 2] = [
    decl!(0, input u: u, "1", ""),
    decl!(1, output y: y, "1", ""),
];

/// The instance a step of a `Doubler` calls into (0: none), and what those calls returned.
static NESTED_INTO: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
static NESTED_STATUSES: std::sync::Mutex<Vec<fmi2Status>> = std::sync::Mutex::new(Vec::new());

fmi_testkit::test_model!(
    Doubler,
    DOUBLER,
    "y = 2 u",
    calculate = |m| m.y = 2.0 * m.u,
    step = |m| {
        m.u += 1.0;
        let c = NESTED_INTO.load(std::sync::atomic::Ordering::SeqCst) as fmi2Component;
        if !c.is_null() {
            let (mut y, u) = (0.0, 0.5);
            let statuses = unsafe {
                [
                    abi::get_real::<Doubler>(c, &1, 1, &mut y),
                    abi::set_real::<Doubler>(c, &0, 1, &u),
                    abi::do_step::<Doubler>(c, 0.0, 0.1, 0),
                ]
            };
            NESTED_STATUSES.lock().unwrap().extend(statuses);
        }
    }
);

/// A `Doubler` in step mode at t = 0, with the logger's messages so far cleared.
unsafe fn stepping_doubler(logger: &TestLogger, logging_on: bool) -> fmi2Component {
    let functions = logger.callbacks();
    let guid = CString::new(guid::<Doubler>()).unwrap();
    unsafe {
        let c = abi::instantiate::<Doubler>(
            c"d".as_ptr(),
            fmi2CoSimulation,
            guid.as_ptr(),
            std::ptr::null(),
            &functions,
            0,
            fmi2Boolean::from(logging_on),
        );
        assert!(!c.is_null());
        assert_eq!(
            abi::setup_experiment::<Doubler>(c, 0, 0.0, 0.0, 0, 0.0),
            fmi2OK
        );
        assert_eq!(abi::enter_initialization_mode::<Doubler>(c), fmi2OK);
        assert_eq!(lifecycle::exit_initialization_mode::<Doubler>(c), fmi2OK);
        logger.clear();
        c
    }
}

/// The outputs a get returns are those of the inputs set and the steps taken just before,
/// whichever path serves the get.
#[test]
fn a_get_right_after_a_set_or_a_step_sees_the_new_outputs() {
    let logger = Box::<TestLogger>::default();
    unsafe {
        let c = stepping_doubler(&logger, false);
        let get = || {
            let mut y = f64::NAN;
            assert_eq!(abi::get_real::<Doubler>(c, &1, 1, &mut y), fmi2OK);
            y
        };
        assert_eq!(get(), 0.0);
        for u in [1.0, -3.0, 0.25] {
            assert_eq!(abi::set_real::<Doubler>(c, &0, 1, &u), fmi2OK);
            assert_eq!(get(), 2.0 * u);
            // Again, with nothing changed in between.
            assert_eq!(get(), 2.0 * u);
        }
        let mut t = 0.0;
        for k in 1..=3 {
            assert_eq!(abi::do_step::<Doubler>(c, t, 0.5, 0), fmi2OK);
            t += 0.5;
            assert_eq!(get(), 2.0 * (0.25 + f64::from(k)));
        }
        assert!(logger.is_empty(), "{:?}", logger.messages());
        abi::free_instance::<Doubler>(c);
    }
}

/// With `logCalls` switched on during a run, every get, set and step is traced from the
/// next call on; switched off again, none is.
#[test]
fn log_calls_switched_on_mid_run_traces_every_exchange_call() {
    let logger = Box::<TestLogger>::default();
    unsafe {
        let c = stepping_doubler(&logger, false);
        let u = 1.0;
        let exchange = |t: f64| {
            let mut y = 0.0;
            assert_eq!(abi::set_real::<Doubler>(c, &0, 1, &u), fmi2OK);
            assert_eq!(abi::get_real::<Doubler>(c, &1, 1, &mut y), fmi2OK);
            assert_eq!(abi::do_step::<Doubler>(c, t, 0.5, 0), fmi2OK);
        };
        exchange(0.0);
        assert!(logger.is_empty(), "{:?}", logger.messages());
        let calls = [c"logCalls".as_ptr()];
        assert_eq!(
            abi::set_debug_logging::<Doubler>(c, fmi2True, 1, calls.as_ptr()),
            fmi2OK
        );
        logger.clear();
        exchange(0.5);
        let traced: Vec<String> = logger.messages();
        assert_eq!(traced.len(), 3, "{traced:?}");
        for (message, function) in
            traced
                .iter()
                .zip(["fmi2SetReal(", "fmi2GetReal(", "fmi2DoStep("])
        {
            assert!(message.starts_with(function), "{traced:?}");
        }
        assert_eq!(
            abi::set_debug_logging::<Doubler>(c, fmi2False, 1, calls.as_ptr()),
            fmi2OK
        );
        logger.clear();
        exchange(1.0);
        assert!(logger.is_empty(), "{:?}", logger.messages());
        abi::free_instance::<Doubler>(c);
    }
}

/// A get, set or step on an instance while its step runs (here from inside the model, as
/// from a master's callback) is refused with fmi2Error and a log line, changes nothing,
/// and the outer step goes on.
#[test]
fn a_call_on_a_busy_instance_is_refused_and_logged() {
    let logger = Box::<TestLogger>::default();
    unsafe {
        let c = stepping_doubler(&logger, false);
        NESTED_INTO.store(c as usize, std::sync::atomic::Ordering::SeqCst);
        let status = abi::do_step::<Doubler>(c, 0.0, 0.5, 0);
        NESTED_INTO.store(0, std::sync::atomic::Ordering::SeqCst);
        assert_eq!(status, fmi2OK);
        assert_eq!(
            std::mem::take(&mut *NESTED_STATUSES.lock().unwrap()),
            [fmi2Error; 3]
        );
        let messages = logger.messages();
        assert_eq!(messages.len(), 3, "{messages:?}");
        for (message, function) in messages
            .iter()
            .zip(["fmi2GetReal", "fmi2SetReal", "fmi2DoStep"])
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
        let mut y = 0.0;
        assert_eq!(abi::get_real::<Doubler>(c, &1, 1, &mut y), fmi2OK);
        assert_eq!(y, 2.0);
        abi::free_instance::<Doubler>(c);
    }
}
