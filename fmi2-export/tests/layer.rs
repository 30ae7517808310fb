//! The layer with small models of its own, driven through the generic `abi` functions:
//! panics become fmi2Fatal, the GUID follows the interface only, `check_table` finds
//! broken tables.
#![allow(unsafe_code)]

use fmi2_export::ffi::*;
use fmi2_export::*;
use serde::{Deserialize, Serialize};
use std::ffi::{c_void, CStr, CString};
use std::sync::Mutex;

// ---- a model that panics in do_step ----------------------------------------------------

#[derive(Debug, Clone, Default, Serialize, Deserialize)]
struct Panicky {
    y: f64,
}

static PANICKY: [Variable<Panicky>; 1] = [Variable {
    name: "y",
    value_reference: 0,
    causality: Causality::Output,
    variability: Variability::Continuous,
    initial: None,
    unit: None,
    description: "",
    access: Access::Real {
        start: None,
        min: None,
        max: None,
        get: |m| m.y,
        set: None,
    },
}];

impl Model for Panicky {
    const MODEL_IDENTIFIER: &'static str = "Panicky";
    const MODEL_NAME: &'static str = "Panicky";
    const DESCRIPTION: &'static str = "panics in do_step";
    const DEFAULT_EXPERIMENT: Experiment = Experiment {
        start_time: 0.0,
        stop_time: 1.0,
        step_size: 0.1,
        tolerance: None,
    };
    fn variables() -> &'static [Variable<Self>] {
        &PANICKY
    }
    fn exit_initialization(&mut self, _: f64, _: &mut Log) -> Result<(), ModelError> {
        Ok(())
    }
    fn do_step(&mut self, _: f64, _: f64, _: &mut Log) -> Result<StepEnd, ModelError> {
        panic!("boom");
    }
}

type Lines = Mutex<Vec<(fmi2Status, String, String)>>;

extern "C" fn record(
    env: fmi2ComponentEnvironment,
    _name: fmi2String,
    status: fmi2Status,
    category: fmi2String,
    _format: fmi2String,
    message: fmi2String,
) {
    let text = |p| unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned();
    let lines = unsafe { &*(env as *const Lines) };
    lines
        .lock()
        .unwrap()
        .push((status, text(category), text(message)));
}

type FixedLogger = extern "C" fn(
    fmi2ComponentEnvironment,
    fmi2String,
    fmi2Status,
    fmi2String,
    fmi2String,
    fmi2String,
);

/// A panic inside a model call is caught: fmi2Fatal, a fatal log line, state Fatal (only
/// FreeInstance is accepted afterwards), and nothing unwinds into the caller.
#[test]
fn a_panic_becomes_fatal_and_never_unwinds() {
    let lines = Lines::default();
    let functions = fmi2CallbackFunctions {
        // Same argument registers as the variadic call with "%s" + one pointer (SysV, AAPCS64).
        logger: unsafe { std::mem::transmute::<FixedLogger, fmi2CallbackLogger>(record) },
        allocateMemory: None,
        freeMemory: None,
        stepFinished: None,
        componentEnvironment: &lines as *const Lines as *mut c_void,
    };
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
        abi::exit_initialization_mode::<Panicky>(c);
        assert_eq!(
            abi::do_step::<Panicky>(c, 0.0, 0.1, 0),
            fmi2Status::fmi2Fatal
        );
        let (status, category, message) = lines.lock().unwrap().last().cloned().unwrap();
        assert_eq!(status, fmi2Status::fmi2Fatal);
        assert_eq!(category, "logStatusFatal");
        assert_eq!(
            message,
            "fmi2DoStep: internal error, instance unusable: boom"
        );
        let mut y = 0.0;
        assert_eq!(
            abi::get_real::<Panicky>(c, &0, 1, &mut y),
            fmi2Status::fmi2Error
        );
        assert_eq!(
            lines.lock().unwrap().last().unwrap().2,
            "fmi2GetReal: illegal call in state Fatal"
        );
        assert_eq!(abi::reset::<Panicky>(c), fmi2Status::fmi2Error);
        abi::free_instance::<Panicky>(c);
    }
}

/// A component of another model type is refused, not used.
#[test]
fn a_component_of_another_model_is_refused() {
    let lines = Lines::default();
    let functions = fmi2CallbackFunctions {
        logger: unsafe { std::mem::transmute::<FixedLogger, fmi2CallbackLogger>(record) },
        allocateMemory: None,
        freeMemory: None,
        stepFinished: None,
        componentEnvironment: &lines as *const Lines as *mut c_void,
    };
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
        assert_eq!(abi::reset::<Small>(c), fmi2Status::fmi2Error);
        abi::free_instance::<Small>(c); // ignored: not a Small
        assert_eq!(abi::reset::<Panicky>(c), fmi2Status::fmi2OK);
        abi::free_instance::<Panicky>(c);
    }
}

// ---- GUID: interface only ----------------------------------------------------------------

macro_rules! small_model {
    ($name:ident, $table:ident, $var:expr) => {
        #[derive(Debug, Clone, Default, Serialize, Deserialize)]
        struct $name {
            a: f64,
        }
        static $table: [Variable<$name>; 1] = [$var];
        impl Model for $name {
            const MODEL_IDENTIFIER: &'static str = "Small";
            const MODEL_NAME: &'static str = "Small";
            const DESCRIPTION: &'static str = "";
            const DEFAULT_EXPERIMENT: Experiment = Experiment {
                start_time: 0.0,
                stop_time: 1.0,
                step_size: 0.1,
                tolerance: None,
            };
            fn variables() -> &'static [Variable<Self>] {
                &$table
            }
            fn exit_initialization(&mut self, _: f64, _: &mut Log) -> Result<(), ModelError> {
                Ok(())
            }
            fn do_step(&mut self, _: f64, _: f64, _: &mut Log) -> Result<StepEnd, ModelError> {
                Ok(StepEnd::Complete)
            }
        }
    };
}

macro_rules! input {
    ($model:ident, name: $n:expr, vr: $vr:expr, causality: $c:expr, unit: $u:expr, start: $s:expr, desc: $d:expr) => {
        Variable {
            name: $n,
            value_reference: $vr,
            causality: $c,
            variability: Variability::Continuous,
            initial: None,
            unit: $u,
            description: $d,
            access: Access::Real {
                start: $s,
                min: None,
                max: None,
                get: |m: &$model| m.a,
                set: Some(|m: &mut $model, v| m.a = v),
            },
        }
    };
}

small_model!(
    Small,
    SMALL,
    input!(Small, name: "a", vr: 0, causality: Causality::Input, unit: Some("m"), start: Some(0.0), desc: "")
);
small_model!(
    Cosmetic,
    COSMETIC,
    input!(Cosmetic, name: "a", vr: 0, causality: Causality::Input, unit: Some("N"), start: Some(5.0), desc: "documented")
);
small_model!(
    Renamed,
    RENAMED,
    input!(Renamed, name: "b", vr: 0, causality: Causality::Input, unit: Some("m"), start: Some(0.0), desc: "")
);
small_model!(
    Renumbered,
    RENUMBERED,
    input!(Renumbered, name: "a", vr: 1, causality: Causality::Input, unit: Some("m"), start: Some(0.0), desc: "")
);
small_model!(
    Parameter,
    PARAMETER,
    Variable {
        variability: Variability::Tunable,
        ..input!(Parameter, name: "a", vr: 0, causality: Causality::Parameter, unit: Some("m"), start: Some(0.0), desc: "")
    }
);

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

static BROKEN: [Variable<Broken>; 7] = [
    // an input with an initial attribute and no start
    Variable {
        name: "a",
        value_reference: 0,
        causality: Causality::Input,
        variability: Variability::Continuous,
        initial: Some(Initial::Exact),
        unit: Some("furlong"),
        description: "",
        access: Access::Real {
            start: None,
            min: None,
            max: None,
            get: |m| m.a,
            set: Some(|m, v| m.a = v),
        },
    },
    // same name, same vr; an output with a setter
    Variable {
        name: "a",
        value_reference: 0,
        causality: Causality::Output,
        variability: Variability::Continuous,
        initial: None,
        unit: None,
        description: "",
        access: Access::Real {
            start: None,
            min: None,
            max: None,
            get: |m| m.a,
            set: Some(|m, v| m.a = v),
        },
    },
    // start outside [min, max], min > max
    Variable {
        name: "p",
        value_reference: 2,
        causality: Causality::Parameter,
        variability: Variability::Fixed,
        initial: None,
        unit: None,
        description: "",
        access: Access::Real {
            start: Some(5.0),
            min: Some(1.0),
            max: Some(0.0),
            get: |m| m.a,
            set: Some(|m, v| m.a = v),
        },
    },
    // a continuous Integer
    Variable {
        name: "n",
        value_reference: 0,
        causality: Causality::Output,
        variability: Variability::Continuous,
        initial: None,
        unit: None,
        description: "",
        access: Access::Integer {
            start: None,
            min: None,
            max: None,
            get: |m| m.n,
            set: None,
        },
    },
    // an undeclared enumeration type
    Variable {
        name: "e",
        value_reference: 1,
        causality: Causality::Parameter,
        variability: Variability::Fixed,
        initial: None,
        unit: None,
        description: "",
        access: Access::Enumeration {
            type_name: "Nope",
            start: Some(1),
            get: |m| m.n,
            set: Some(|m, v| m.n = v),
        },
    },
    // a constant whose getter disagrees with its start, a fixed output
    Variable {
        name: "k",
        value_reference: 3,
        causality: Causality::Local,
        variability: Variability::Constant,
        initial: None,
        unit: None,
        description: "",
        access: Access::Real {
            start: Some(2.0),
            min: None,
            max: None,
            get: |_| 3.0,
            set: None,
        },
    },
    Variable {
        name: "o",
        value_reference: 4,
        causality: Causality::Output,
        variability: Variability::Fixed,
        initial: None,
        unit: None,
        description: "",
        access: Access::Real {
            start: None,
            min: None,
            max: None,
            get: |m| m.a,
            set: None,
        },
    },
];

impl Model for Broken {
    const MODEL_IDENTIFIER: &'static str = "Broken-1";
    const MODEL_NAME: &'static str = "Broken";
    const DESCRIPTION: &'static str = "";
    const DEFAULT_EXPERIMENT: Experiment = Experiment {
        start_time: 0.0,
        stop_time: 0.0,
        step_size: 0.1,
        tolerance: None,
    };
    fn variables() -> &'static [Variable<Self>] {
        &BROKEN
    }
    fn exit_initialization(&mut self, _: f64, _: &mut Log) -> Result<(), ModelError> {
        Ok(())
    }
    fn do_step(&mut self, _: f64, _: f64, _: &mut Log) -> Result<StepEnd, ModelError> {
        Ok(StepEnd::Complete)
    }
}

#[test]
fn check_table_reports_every_problem() {
    let problems = check_table::<Broken>().unwrap_err().problems;
    let expected = [
        "modelIdentifier \"Broken-1\" is not a C identifier",
        "DefaultExperiment",
        "a: initial Exact is not allowed for Input/Continuous",
        "a: start value required",
        "a: unit \"furlong\" is not in the unit table",
        "a: name declared twice",
        "a: value reference 0 used twice among Real variables",
        "a: a setter must be present exactly for non-constant parameters and inputs (has one: true)",
        "p: min 1 > max 0",
        "p: start 5 is not finite within [min, max]",
        "n: only Real variables can be continuous",
        "e: enumeration type Nope is not declared",
        "k: start 2 but the getter returns 3",
        "o: causality Output with variability Fixed is not allowed",
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
