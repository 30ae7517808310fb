//! The declaration table: one line per variable gives shape, field, accessors and bounds.
use fmi_model::{
    check_declarations, decl, Causality, Declaration, EnumValue, Enumeration, Experiment, Kind,
    Limit, Log, Model, ModelError, Shape, StepEnd,
};
use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
enum Mode {
    Slow = 1,
    Fast = 3,
}

fmi_model::enumeration! {
    Mode = "Mode", "how fast" {
        Slow: "slow", "the slow one";
        Fast: "fast", "the fast one";
    }
}

#[derive(Debug, Clone, Serialize, Deserialize)]
struct Inner {
    gain_per_s: [f64; 3],
}

#[derive(Debug, Clone, Serialize, Deserialize)]
struct Toy {
    inner: Inner,
    offset_m: f64,
    mode: Mode,
    y_m: f64,
}

impl Default for Toy {
    fn default() -> Self {
        Toy {
            inner: Inner {
                gain_per_s: [1.0, 2.0, 3.0],
            },
            offset_m: 0.5,
            mode: Mode::Fast,
            y_m: 0.0,
        }
    }
}

static DECLARATIONS: [Declaration<Toy>; 4] = [
    decl!(10, parameter gain[3]: inner.gain_per_s, "1/s", "gain", above = 0.0, components = &["x", "y", "z"]),
    decl!(13, input offset: offset_m, "m", "offset", min = -1.0, below = 1.0),
    decl!(1, parameter mode: mode as enum Mode, "mode"),
    decl!(20, output y: y_m, "m", "result"),
];

impl Model for Toy {
    const MODEL_IDENTIFIER: &'static str = "Toy";
    const MODEL_NAME: &'static str = "Toy";
    const VERSION: &'static str = "0.0.0";
    const DESCRIPTION: &'static str = "";
    const DEFAULT_EXPERIMENT: Experiment = Experiment {
        start_time: 0.0,
        stop_time: 1.0,
        step_size: 0.1,
        tolerance: None,
    };
    fn declarations() -> &'static [Declaration<Self>] {
        &DECLARATIONS
    }
    fn exit_initialization(&mut self, _: f64, _: &mut Log) -> Result<(), ModelError> {
        Ok(())
    }
    fn do_step(&mut self, _: f64, _: f64, _: &mut Log) -> Result<StepEnd, ModelError> {
        Ok(StepEnd::Complete)
    }
}

#[test]
fn a_vector_is_one_declaration_with_element_accessors_and_its_field() {
    let gain = &DECLARATIONS[0];
    assert_eq!(gain.shape(), Shape::Vector(3));
    assert_eq!(gain.causality, Causality::Parameter);
    assert_eq!(gain.unit, Some("1/s"));
    assert_eq!(gain.components, ["x", "y", "z"]);
    let Kind::Real {
        get,
        set: Some(set),
        min,
        ..
    } = gain.kind
    else {
        panic!("a settable Real");
    };
    assert_eq!(min, Some(Limit::Exclusive(0.0)));
    let mut toy = Toy::default();
    set(&mut toy, 2, 7.5);
    assert_eq!(toy.inner.gain_per_s, [1.0, 2.0, 7.5]);
    assert_eq!(get(&toy, 1), 2.0);
    assert!(gain.has_field("gain_per_s") && gain.has_field("inner.gain_per_s"));
    assert!(!gain.has_field("per_s") && !gain.has_field("gain"));
}

#[test]
fn outputs_get_no_setter_and_bounds_open_or_closed_as_declared() {
    assert!(matches!(DECLARATIONS[3].kind, Kind::Real { set: None, .. }));
    let Kind::Real { min, max, .. } = DECLARATIONS[1].kind else {
        panic!("a Real");
    };
    let (min, max) = (min.unwrap(), max.unwrap());
    assert!(min.admits_above(-1.0) && !min.admits_above(-1.000001));
    assert!(max.admits_below(0.999) && !max.admits_below(1.0));
}

#[test]
fn an_enumeration_comes_from_its_rust_enum() {
    let ty = Mode::TYPE;
    assert_eq!(ty.listing(), "1 slow, 3 fast");
    assert_eq!((ty.min(), ty.max()), (Some(1), Some(3)));
    for mode in [Mode::Slow, Mode::Fast] {
        assert_eq!(Mode::from_value(mode.value()), Some(mode));
    }
    assert_eq!(Mode::from_value(2), None);
    let Kind::Enumeration {
        get,
        set: Some(set),
        ..
    } = DECLARATIONS[2].kind
    else {
        panic!("a settable enumeration");
    };
    let mut toy = Toy::default();
    assert_eq!(get(&toy), 3);
    set(&mut toy, 1);
    assert_eq!(toy.mode, Mode::Slow);
    // A raw i32 field holds the value as given (the layer has checked it is an item).
    let mut raw = 0i32;
    EnumValue::<Mode>::set_value(&mut raw, 3);
    assert_eq!(EnumValue::<Mode>::to_value(&raw), 3);
}

#[test]
fn the_toy_passes_the_checks_and_a_start_outside_its_bounds_does_not() {
    assert_eq!(check_declarations::<Toy>(), Ok(()));

    #[derive(Debug, Clone, Default, Serialize, Deserialize)]
    struct Bad {
        k: f64,
    }
    static BAD: [Declaration<Bad>; 1] = [decl!(0, parameter k: k, "1", "", above = 0.0)];
    impl Model for Bad {
        const MODEL_IDENTIFIER: &'static str = "Bad";
        const MODEL_NAME: &'static str = "Bad";
        const VERSION: &'static str = "0.0.0";
        const DESCRIPTION: &'static str = "";
        const DEFAULT_EXPERIMENT: Experiment = Toy::DEFAULT_EXPERIMENT;
        fn declarations() -> &'static [Declaration<Self>] {
            &BAD
        }
        fn exit_initialization(&mut self, _: f64, _: &mut Log) -> Result<(), ModelError> {
            Ok(())
        }
        fn do_step(&mut self, _: f64, _: f64, _: &mut Log) -> Result<StepEnd, ModelError> {
            Ok(StepEnd::Complete)
        }
    }
    // Default gives k = 0, which "> 0" excludes.
    let problems = check_declarations::<Bad>().unwrap_err();
    assert_eq!(problems.len(), 1, "{problems:?}");
    assert!(problems[0].starts_with("k: start 0"), "{problems:?}");
}

#[test]
fn a_model_error_names_the_field_and_element() {
    let e = ModelError::InvalidParameter {
        field: "inner.gain_per_s",
        index: Some(1),
        value: "-1".into(),
        reason: "must be > 0".into(),
    };
    assert_eq!(
        e.to_string(),
        "parameter inner.gain_per_s[1] = -1: must be > 0"
    );
}

#[test]
fn a_parameter_outside_its_declaration_is_refused_naming_field_value_unit_and_range() {
    use fmi_model::parameter::check_declared;
    assert_eq!(check_declared(&Toy::default()), Ok(()));
    let mut toy = Toy::default();
    toy.inner.gain_per_s[1] = 0.0;
    let e = check_declared(&toy).unwrap_err();
    assert_eq!((e.field, e.index), ("gain_per_s", Some(1)));
    assert_eq!(e.value, "0 1/s");
    assert_eq!(e.reason, "outside its declared range (0, inf) 1/s");
    toy.inner.gain_per_s[1] = f64::NAN;
    assert_eq!(check_declared(&toy).unwrap_err().value, "NaN 1/s");
    // An input is the master's to set at every step, not a parameter.
    let toy = Toy {
        offset_m: 5.0,
        ..Toy::default()
    };
    assert_eq!(check_declared(&toy), Ok(()));
}
