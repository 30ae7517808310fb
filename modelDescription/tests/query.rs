//! The master-side convenience API, against the FMI 2.0 text where it encodes a rule.
use model_description::*;

fn variable(causality: Option<Causality>, variability: Option<Variability>) -> ScalarVariable {
    ScalarVariable {
        name: "v".into(),
        causality,
        variability,
        real: Some(RealVariable::default()),
        ..Default::default()
    }
}

#[test]
fn absent_causality_and_variability_take_the_standard_defaults() {
    let v = variable(None, None);
    assert_eq!(v.causality_or_default(), Causality::Local);
    assert_eq!(v.variability_or_default(), Variability::Continuous);
}

/// FMI 2.0.4 §2.2.7, table of default `initial` values: rows are variability, columns
/// causality; (A) and (B) default to exact, (C) to calculated, (D), (E) and the cells the
/// standard forbids have no initial. Written out from the standard's table, cell by cell.
#[test]
fn initial_defaults_follow_the_standard_table() {
    use Causality::*;
    use Variability::*;
    let exact = Some(Initial::Exact);
    let calculated = Some(Initial::Calculated);
    #[rustfmt::skip]
    let table = [
        // variability, [parameter, calculatedParameter, input, output, local, independent]
        (Constant,   [None,  None,       None, exact,      exact,      None]),
        (Fixed,      [exact, calculated, None, None,       calculated, None]),
        (Tunable,    [exact, calculated, None, None,       calculated, None]),
        (Discrete,   [None,  None,       None, calculated, calculated, None]),
        (Continuous, [None,  None,       None, calculated, calculated, None]),
    ];
    let causalities = [
        Parameter,
        CalculatedParameter,
        Input,
        Output,
        Local,
        Independent,
    ];
    for (variability, row) in table {
        for (causality, expected) in causalities.into_iter().zip(row) {
            let v = variable(Some(causality), Some(variability));
            assert_eq!(
                v.initial_or_default(),
                expected,
                "{causality:?} {variability:?}"
            );
        }
    }
}

#[test]
fn an_explicit_initial_wins_over_the_default() {
    let mut v = variable(Some(Causality::Output), None);
    v.initial = Some(Initial::Approx);
    assert_eq!(v.initial_or_default(), Some(Initial::Approx));
}

#[test]
fn kind_and_start_follow_the_type_element() {
    let mut v = ScalarVariable::default();
    assert_eq!(v.kind(), None);
    assert_eq!(v.start(), None);
    v.boolean = Some(BooleanVariable {
        declared_type: Some("Flag".into()),
        start: Some(true),
    });
    assert_eq!(v.kind(), Some(VariableKind::Boolean));
    assert_eq!(v.start(), Some(StartValue::Boolean(true)));
    assert_eq!(v.declared_type(), Some("Flag"));
}

#[test]
fn enumerations_are_accessed_as_integers() {
    assert_eq!(
        VariableKind::Enumeration.accessed_as(),
        VariableKind::Integer
    );
    for kind in [
        VariableKind::Real,
        VariableKind::Integer,
        VariableKind::Boolean,
        VariableKind::String,
    ] {
        assert_eq!(kind.accessed_as(), kind);
    }
}

#[test]
fn model_structure_indices_are_one_based() {
    let md = ModelDescription {
        model_variables: ModelVariables {
            variables: vec![
                ScalarVariable {
                    name: "a".into(),
                    ..variable(None, None)
                },
                ScalarVariable {
                    name: "b".into(),
                    ..variable(None, None)
                },
            ],
        },
        ..Default::default()
    };
    assert!(md.variable_at(0).is_none());
    assert_eq!(md.variable_at(1).unwrap().name, "a");
    assert_eq!(md.variable_at(2).unwrap().name, "b");
    assert!(md.variable_at(3).is_none());
    assert!(md.variable_at(u32::MAX).is_none());
    assert_eq!(md.index_of("b"), Some(2));
    assert_eq!(md.index_of("c"), None);
    assert!(md.variable("c").is_none());
    assert_eq!(md.co_simulation_identifier(), None);
}

#[test]
fn a_variables_own_unit_wins_over_its_declared_types() {
    let md = ModelDescription {
        type_definitions: Some(TypeDefinitions {
            simple_types: vec![SimpleType {
                name: "Angle".into(),
                real: Some(RealType {
                    unit: Some("rad".into()),
                    ..Default::default()
                }),
                ..Default::default()
            }],
        }),
        ..Default::default()
    };
    let mut v = variable(None, None);
    assert_eq!(md.unit_of(&v), None);
    v.real.as_mut().unwrap().declared_type = Some("Angle".into());
    assert_eq!(md.unit_of(&v), Some("rad"));
    v.real.as_mut().unwrap().unit = Some("deg".into());
    assert_eq!(md.unit_of(&v), Some("deg"));
}
