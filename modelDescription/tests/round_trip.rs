//! Writing then reading gives back the same description, and the written text has the
//! properties a reviewer of the checked-in XML relies on.
use model_description::*;

/// A description that uses every element and every attribute kind this crate writes.
fn rich() -> ModelDescription {
    let real = |name: &str, vr, causality, unit: &str, start| ScalarVariable {
        name: name.into(),
        value_reference: vr,
        causality: Some(causality),
        real: Some(RealVariable {
            unit: Some(unit.into()),
            start,
            ..Default::default()
        }),
        ..Default::default()
    };
    ModelDescription {
        fmi_version: "2.0".into(),
        model_name: "Lander <test> & \"quotes\" 'too'".into(),
        guid: "{8c4e810f-3df3-4a00-8276-176fa3c9f000}".into(),
        description: Some("line one\nline two\ttabbed".into()),
        author: Some("md".into()),
        version: Some("0.1.0".into()),
        copyright: Some("(c) nobody".into()),
        license: Some("MIT OR Apache-2.0".into()),
        generation_tool: Some("lander-fmi".into()),
        generation_date_and_time: Some("2024-01-01T00:00:00Z".into()),
        variable_naming_convention: Some("structured".into()),
        number_of_event_indicators: Some(0),
        model_exchange: None,
        co_simulation: Some(CoSimulation {
            model_identifier: "Lander".into(),
            needs_execution_tool: Some(false),
            can_handle_variable_communication_step_size: Some(true),
            can_interpolate_inputs: Some(false),
            max_output_derivative_order: Some(0),
            can_run_asynchronuously: Some(false),
            can_be_instantiated_only_once_per_process: Some(false),
            can_not_use_memory_management_functions: Some(true),
            can_get_and_set_fmu_state: Some(true),
            can_serialize_fmu_state: Some(true),
            provides_directional_derivative: Some(false),
        }),
        unit_definitions: Some(UnitDefinitions {
            units: vec![
                Unit {
                    name: "m/s2".into(),
                    base_unit: Some(BaseUnit {
                        m: Some(1),
                        s: Some(-2),
                        ..Default::default()
                    }),
                    display_units: vec![],
                },
                Unit {
                    name: "rad".into(),
                    base_unit: Some(BaseUnit {
                        rad: Some(1),
                        factor: Some(1.0),
                        offset: Some(0.0),
                        ..Default::default()
                    }),
                    display_units: vec![DisplayUnit {
                        name: "deg".into(),
                        factor: Some(57.295_779_513_082_32),
                        offset: None,
                    }],
                },
                Unit {
                    name: "degC".into(),
                    base_unit: Some(BaseUnit {
                        k: Some(1),
                        offset: Some(273.15),
                        ..Default::default()
                    }),
                    display_units: vec![],
                },
            ],
        }),
        type_definitions: Some(TypeDefinitions {
            simple_types: vec![
                SimpleType {
                    name: "Mode".into(),
                    description: Some("guidance mode".into()),
                    enumeration: Some(EnumerationType {
                        quantity: None,
                        items: vec![
                            EnumerationItem {
                                name: "coupled".into(),
                                value: 1,
                                description: Some("paper eq. 12".into()),
                            },
                            EnumerationItem {
                                name: "decoupled".into(),
                                value: 2,
                                description: None,
                            },
                        ],
                    }),
                    ..Default::default()
                },
                SimpleType {
                    name: "Angle".into(),
                    real: Some(RealType {
                        quantity: Some("Angle".into()),
                        unit: Some("rad".into()),
                        min: Some(-std::f64::consts::PI),
                        max: Some(std::f64::consts::PI),
                    }),
                    ..Default::default()
                },
                SimpleType {
                    name: "Count".into(),
                    integer: Some(IntegerType {
                        quantity: None,
                        min: Some(i32::MIN),
                        max: Some(i32::MAX),
                    }),
                    ..Default::default()
                },
                SimpleType {
                    name: "Flag".into(),
                    boolean: Some(Empty {}),
                    ..Default::default()
                },
                SimpleType {
                    name: "Label".into(),
                    string: Some(Empty {}),
                    ..Default::default()
                },
            ],
        }),
        log_categories: Some(LogCategories {
            categories: vec![
                Category {
                    name: "logStatusError".into(),
                    description: Some("errors".into()),
                },
                Category {
                    name: "logCalls".into(),
                    description: None,
                },
            ],
        }),
        default_experiment: Some(DefaultExperiment {
            start_time: Some(0.0),
            stop_time: Some(120.0),
            tolerance: Some(1e-9),
            step_size: Some(0.01),
        }),
        model_variables: ModelVariables {
            variables: vec![
                real("r_nue[1]", 1, Causality::Output, "m", Some(1737.4e3)),
                real("g_moon", 2, Causality::Parameter, "m/s2", Some(1.62)),
                ScalarVariable {
                    name: "tiny".into(),
                    value_reference: 3,
                    description: Some("smallest subnormal".into()),
                    causality: Some(Causality::Local),
                    variability: Some(Variability::Continuous),
                    initial: Some(Initial::Calculated),
                    can_handle_multiple_set_per_time_instant: None,
                    real: Some(RealVariable {
                        declared_type: Some("Angle".into()),
                        quantity: Some("Angle".into()),
                        unit: Some("rad".into()),
                        display_unit: Some("deg".into()),
                        min: Some(f64::NEG_INFINITY),
                        max: Some(f64::INFINITY),
                        nominal: Some(5e-324),
                        start: Some(-0.0),
                        derivative: Some(1),
                    }),
                    ..Default::default()
                },
                ScalarVariable {
                    name: "step_count".into(),
                    value_reference: 1,
                    causality: Some(Causality::Output),
                    variability: Some(Variability::Discrete),
                    integer: Some(IntegerVariable {
                        declared_type: Some("Count".into()),
                        quantity: None,
                        min: Some(-1),
                        max: Some(i32::MAX),
                        start: Some(i32::MIN),
                    }),
                    ..Default::default()
                },
                ScalarVariable {
                    name: "enabled".into(),
                    value_reference: 1,
                    causality: Some(Causality::Parameter),
                    variability: Some(Variability::Fixed),
                    initial: Some(Initial::Exact),
                    can_handle_multiple_set_per_time_instant: Some(true),
                    boolean: Some(BooleanVariable {
                        declared_type: Some("Flag".into()),
                        start: Some(true),
                    }),
                    ..Default::default()
                },
                ScalarVariable {
                    name: "label".into(),
                    value_reference: 1,
                    causality: Some(Causality::Parameter),
                    variability: Some(Variability::Tunable),
                    string: Some(StringVariable {
                        declared_type: Some("Label".into()),
                        start: Some("a <b> & 'c' \"d\"\nnext".into()),
                    }),
                    ..Default::default()
                },
                ScalarVariable {
                    name: "mode".into(),
                    value_reference: 2,
                    causality: Some(Causality::Parameter),
                    variability: Some(Variability::Fixed),
                    enumeration: Some(EnumerationVariable {
                        declared_type: "Mode".into(),
                        quantity: Some("Mode".into()),
                        min: Some(1),
                        max: Some(2),
                        start: Some(2),
                    }),
                    ..Default::default()
                },
                ScalarVariable {
                    name: "time".into(),
                    value_reference: 0,
                    causality: Some(Causality::Independent),
                    real: Some(RealVariable::default()),
                    ..Default::default()
                },
            ],
        },
        model_structure: ModelStructure {
            outputs: Some(UnknownList {
                unknowns: vec![
                    Unknown {
                        index: 1,
                        dependencies: Some(String::new()),
                        dependencies_kind: Some(String::new()),
                    },
                    Unknown {
                        index: 4,
                        dependencies: None,
                        dependencies_kind: None,
                    },
                ],
            }),
            derivatives: Some(UnknownList {
                unknowns: vec![Unknown {
                    index: 3,
                    dependencies: Some("1 2".into()),
                    dependencies_kind: Some("dependent fixed".into()),
                }],
            }),
            initial_unknowns: Some(UnknownList {
                unknowns: vec![Unknown {
                    index: 1,
                    dependencies: Some("2".into()),
                    dependencies_kind: None,
                }],
            }),
        },
    }
}

fn bits_of_reals(md: &ModelDescription) -> Vec<Option<[Option<u64>; 4]>> {
    let bits = |v: Option<f64>| v.map(f64::to_bits);
    md.model_variables
        .variables
        .iter()
        .map(|v| {
            v.real
                .as_ref()
                .map(|r| [bits(r.start), bits(r.min), bits(r.max), bits(r.nominal)])
        })
        .collect()
}

#[test]
fn write_then_read_gives_an_equal_description() {
    let original = rich();
    let xml = original.to_xml().expect("writes");
    let back = ModelDescription::from_xml(&xml).unwrap_or_else(|e| panic!("{e}\n{xml}"));
    assert_eq!(back, original, "\n{xml}");
    // PartialEq on f64 cannot tell -0.0 from 0.0: compare bits too.
    assert_eq!(bits_of_reals(&back), bits_of_reals(&original));
}

#[test]
fn writing_is_deterministic_and_stable_under_a_second_round_trip() {
    let first = rich().to_xml().unwrap();
    let second = ModelDescription::from_xml(&first)
        .unwrap()
        .to_xml()
        .unwrap();
    assert_eq!(first, second);
}

#[test]
fn written_text_starts_with_the_utf8_declaration_and_is_one_element_per_line() {
    let xml = rich().to_xml().unwrap();
    let mut lines = xml.lines();
    assert_eq!(
        lines.next(),
        Some(r#"<?xml version="1.0" encoding="UTF-8"?>"#)
    );
    assert!(xml.ends_with("</fmiModelDescription>\n"));
    for line in lines {
        let trimmed = line.trim_start();
        let indent = line.len() - trimmed.len();
        assert!(
            trimmed.starts_with('<'),
            "not one element per line: {line:?}"
        );
        assert_eq!(indent % 2, 0, "indent is not in steps of two: {line:?}");
        assert_eq!(
            trimmed.matches('<').count(),
            1,
            "two elements on one line: {line:?}"
        );
    }
    assert!(xml.contains("\n  <CoSimulation "));
    assert!(xml.contains("\n    <ScalarVariable name=\"g_moon\""));
}

#[test]
fn attribute_values_are_escaped() {
    let xml = rich().to_xml().unwrap();
    assert!(
        xml.contains(r#"modelName="Lander &lt;test&gt; &amp; &quot;quotes&quot; &apos;too&apos;""#),
        "{xml}"
    );
    // A raw line break would be normalised to a space by any reader.
    assert!(xml.contains("line one&#xA;line two"), "{xml}");
}

#[test]
fn booleans_and_special_doubles_use_their_xsd_spelling() {
    let xml = rich().to_xml().unwrap();
    assert!(xml.contains(r#"canGetAndSetFMUstate="true""#));
    assert!(xml.contains(r#"canBeInstantiatedOnlyOncePerProcess="false""#));
    assert!(xml.contains(r#"min="-INF" max="INF""#), "{xml}");
    assert!(xml.contains(r#"nominal="5e-324""#), "{xml}");
    assert!(xml.contains(r#"start="1737400""#), "{xml}");
    assert!(xml.contains(r#"tolerance="1e-9""#), "{xml}");
}

#[test]
fn absent_optionals_write_no_attribute_and_empty_types_write_an_empty_element() {
    let xml = rich().to_xml().unwrap();
    assert!(xml.contains(
        "<ScalarVariable name=\"time\" valueReference=\"0\" causality=\"independent\">\n      <Real/>"
    ), "{xml}");
    assert!(
        xml.contains("<SimpleType name=\"Flag\">\n      <Boolean/>"),
        "{xml}"
    );
}

#[test]
fn a_tab_survives_the_round_trip_as_a_character_reference() {
    let xml = rich().to_xml().unwrap();
    assert!(xml.contains("line two&#x9;tabbed"), "{xml}");
    assert!(!xml.contains('\t'));
}

#[test]
fn control_characters_xml_cannot_hold_are_refused_with_the_line() {
    let mut md = rich();
    md.model_variables.variables[1].description = Some("bell\u{7}".into());
    let error = md.to_xml().unwrap_err();
    assert!(matches!(error, Error::Write(_)), "{error:?}");
    let message = error.to_string();
    assert!(message.contains("g_moon"), "{message}");
    assert!(message.contains("\\u{7}"), "{message}");
}
