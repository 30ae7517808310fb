//! `validate` reports what the schema cannot express; each case breaks one rule in an
//! otherwise valid description and expects exactly that problem.
use model_description::*;

fn valid() -> ModelDescription {
    ModelDescription::from_xml(
        r#"<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="2.0" modelName="M" guid="{0}">
  <CoSimulation modelIdentifier="M"/>
  <UnitDefinitions>
    <Unit name="rad">
      <BaseUnit rad="1"/>
      <DisplayUnit name="deg" factor="57.29577951308232"/>
    </Unit>
  </UnitDefinitions>
  <TypeDefinitions>
    <SimpleType name="Mode">
      <Enumeration>
        <Item name="coupled" value="1"/>
        <Item name="decoupled" value="2"/>
      </Enumeration>
    </SimpleType>
    <SimpleType name="Angle">
      <Real unit="rad"/>
    </SimpleType>
  </TypeDefinitions>
  <ModelVariables>
    <ScalarVariable name="theta" valueReference="0" causality="output">
      <Real declaredType="Angle" displayUnit="deg"/>
    </ScalarVariable>
    <ScalarVariable name="der(theta)" valueReference="1">
      <Real unit="rad" derivative="1"/>
    </ScalarVariable>
    <ScalarVariable name="mode" valueReference="0" causality="parameter" variability="fixed">
      <Enumeration declaredType="Mode" start="2"/>
    </ScalarVariable>
    <ScalarVariable name="u" valueReference="2" causality="input">
      <Real start="0"/>
    </ScalarVariable>
  </ModelVariables>
  <ModelStructure>
    <Outputs>
      <Unknown index="1" dependencies="" dependenciesKind=""/>
    </Outputs>
    <Derivatives>
      <Unknown index="2" dependencies="1 4" dependenciesKind="dependent dependent"/>
    </Derivatives>
  </ModelStructure>
</fmiModelDescription>
"#,
    )
    .unwrap()
}

fn variable<'a>(md: &'a mut ModelDescription, name: &str) -> &'a mut ScalarVariable {
    md.model_variables
        .variables
        .iter_mut()
        .find(|v| v.name == name)
        .unwrap()
}

/// Applies `breakage` and expects exactly one problem containing `expected`.
fn assert_single_problem(breakage: impl FnOnce(&mut ModelDescription), expected: &str) {
    let mut md = valid();
    breakage(&mut md);
    let problems = md.validate().expect_err("accepted a broken description");
    assert_eq!(problems.len(), 1, "{problems:#?}");
    assert!(problems[0].contains(expected), "{problems:#?}");
}

#[test]
fn the_unbroken_description_is_valid() {
    assert_eq!(valid().validate(), Ok(()));
}

#[test]
fn fmi_version_must_be_2_0() {
    assert_single_problem(
        |md| md.fmi_version = "2.0.4".into(),
        "fmiVersion is \"2.0.4\"",
    );
}

#[test]
fn an_interface_element_is_required() {
    assert_single_problem(
        |md| md.co_simulation = None,
        "neither <ModelExchange> nor <CoSimulation>",
    );
}

#[test]
fn variable_names_are_unique() {
    assert_single_problem(
        |md| variable(md, "u").name = "mode".into(),
        "ScalarVariable 'mode' (index 4): the name is used by an earlier variable",
    );
}

#[test]
fn exactly_one_type_element() {
    assert_single_problem(
        |md| variable(md, "u").integer = Some(IntegerVariable::default()),
        "ScalarVariable 'u' (index 4): has 2 type elements",
    );
    assert_single_problem(
        |md| variable(md, "u").real = None,
        "ScalarVariable 'u' (index 4): has 0 type elements",
    );
}

#[test]
fn declared_types_exist_and_match_the_kind() {
    assert_single_problem(
        |md| {
            variable(md, "mode")
                .enumeration
                .as_mut()
                .unwrap()
                .declared_type = "Moed".into()
        },
        "declaredType \"Moed\" is not in TypeDefinitions",
    );
    assert_single_problem(
        |md| variable(md, "u").real.as_mut().unwrap().declared_type = Some("Mode".into()),
        "declaredType \"Mode\" is not a Real type",
    );
}

#[test]
fn units_and_display_units_are_defined() {
    assert_single_problem(
        |md| variable(md, "u").real.as_mut().unwrap().unit = Some("furlong".into()),
        "ScalarVariable 'u' (index 4): unit \"furlong\" is not in UnitDefinitions",
    );
    // The display unit is checked against the unit inherited from the declared type.
    assert_single_problem(
        |md| variable(md, "theta").real.as_mut().unwrap().display_unit = Some("grad".into()),
        "displayUnit \"grad\" is not a DisplayUnit of unit \"rad\"",
    );
    assert_single_problem(
        |md| {
            let angle = &mut md.type_definitions.as_mut().unwrap().simple_types[1];
            angle.real.as_mut().unwrap().unit = Some("deg".into());
            variable(md, "theta").real.as_mut().unwrap().display_unit = None;
        },
        "SimpleType 'Angle': unit \"deg\" is not in UnitDefinitions",
    );
}

#[test]
fn start_values_where_required_and_nowhere_forbidden() {
    assert_single_problem(
        |md| variable(md, "u").real.as_mut().unwrap().start = None,
        "ScalarVariable 'u' (index 4): has no start value",
    );
    assert_single_problem(
        |md| variable(md, "mode").enumeration.as_mut().unwrap().start = None,
        "ScalarVariable 'mode' (index 3): has no start value",
    );
    // An output defaults to initial="calculated", which forbids a start value.
    assert_single_problem(
        |md| variable(md, "theta").real.as_mut().unwrap().start = Some(0.0),
        "ScalarVariable 'theta' (index 1): has a start value",
    );
}

#[test]
fn derivative_points_at_a_real_variable() {
    assert_single_problem(
        |md| variable(md, "der(theta)").real.as_mut().unwrap().derivative = Some(3),
        "derivative=\"3\" is not the index of a Real variable",
    );
}

#[test]
fn model_structure_indices_are_in_range_and_outputs_complete() {
    assert_single_problem(
        |md| md.model_structure.derivatives.as_mut().unwrap().unknowns[0].dependencies = Some("1 5".into()),
        "ModelStructure > Derivatives > Unknown #1: dependency \"5\" is not the index of a variable",
    );
    assert_single_problem(
        |md| {
            md.model_structure.derivatives.as_mut().unwrap().unknowns[0].dependencies_kind =
                Some("dependent".into())
        },
        "1 dependenciesKind entries for 2 dependencies",
    );
    assert_single_problem(
        |md| md.model_structure.derivatives.as_mut().unwrap().unknowns[0].index = 4,
        "ModelStructure > Derivatives > Unknown #1: 'u' is not a derivative",
    );
    let problems = {
        let mut md = valid();
        md.model_structure.outputs.as_mut().unwrap().unknowns[0].index = 0;
        md.validate().unwrap_err()
    };
    assert_eq!(problems.len(), 2, "{problems:#?}");
    assert!(
        problems[0].contains("index 0 is not the index of a variable (1..=4)"),
        "{problems:#?}"
    );
    assert!(
        problems[1].contains("'theta' (index 1): an output missing from ModelStructure > Outputs"),
        "{problems:#?}"
    );
    assert_single_problem(
        |md| {
            // initial="exact" keeps its start value legal for an output.
            variable(md, "u").causality = Some(Causality::Output);
            variable(md, "u").initial = Some(Initial::Exact);
        },
        "ScalarVariable 'u' (index 4): an output missing from ModelStructure > Outputs",
    );
}

#[test]
fn every_problem_is_reported_not_just_the_first() {
    let mut md = valid();
    md.fmi_version = "3.0".into();
    variable(&mut md, "u").real.as_mut().unwrap().start = None;
    variable(&mut md, "u").real.as_mut().unwrap().unit = Some("furlong".into());
    assert_eq!(md.validate().unwrap_err().len(), 3);
}

#[test]
fn causality_and_variability_form_a_legal_pair() {
    // A parameter must be fixed or tunable; absent variability means continuous.
    assert_single_problem(
        |md| variable(md, "mode").variability = None,
        "ScalarVariable 'mode' (index 3): causality Parameter with variability Continuous is not a combination FMI 2.0 allows",
    );
    assert_single_problem(
        |md| variable(md, "u").variability = Some(Variability::Tunable),
        "causality Input with variability Tunable",
    );
}

#[test]
fn inputs_carry_no_initial_attribute() {
    assert_single_problem(
        |md| variable(md, "u").initial = Some(Initial::Exact),
        "ScalarVariable 'u' (index 4): an Input variable may not have an initial attribute",
    );
}
