//! Files that cannot be read: each error must name the line, the element and, where there
//! is one, the attribute, so the file can be fixed from the message alone.
use model_description::{Error, ModelDescription};

/// A small valid file; the tests break one thing in it at a time.
const VALID: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="2.0" modelName="M" guid="{0}">
  <CoSimulation modelIdentifier="M"/>
  <TypeDefinitions>
    <SimpleType name="Mode">
      <Enumeration>
        <Item name="off" value="0"/>
      </Enumeration>
    </SimpleType>
  </TypeDefinitions>
  <ModelVariables>
    <ScalarVariable name="u" valueReference="0" causality="input">
      <Real start="0"/>
    </ScalarVariable>
    <ScalarVariable name="x" valueReference="1" causality="output">
      <Real/>
    </ScalarVariable>
  </ModelVariables>
  <ModelStructure>
    <Outputs>
      <Unknown index="2"/>
    </Outputs>
  </ModelStructure>
</fmiModelDescription>
"#;

fn broken(from: &str, to: &str) -> Error {
    assert!(
        VALID.contains(from),
        "test bug: {from:?} is not in the valid file"
    );
    let xml = VALID.replacen(from, to, 1);
    match ModelDescription::from_xml(&xml) {
        Ok(_) => panic!("accepted a broken file:\n{xml}"),
        Err(e) => e,
    }
}

/// Asserts an `Error::Invalid` and returns its message.
fn assert_invalid(error: Error, line: u64, element: &str, attribute: Option<&str>) -> String {
    let message = error.to_string();
    match error {
        Error::Invalid {
            line: l,
            element: e,
            attribute: a,
            ..
        } => {
            assert_eq!(
                (l, e.as_str(), a.as_deref()),
                (line, element, attribute),
                "{message}"
            );
        }
        other => panic!("expected Error::Invalid, got {other:?}"),
    }
    message
}

#[test]
fn the_unbroken_file_reads() {
    let md = ModelDescription::from_xml(VALID).unwrap();
    assert_eq!(md.model_variables.variables.len(), 2);
    assert_eq!(md.validate(), Ok(()));
}

#[test]
fn missing_value_reference_names_the_variable_and_attribute() {
    let error = broken(
        r#"name="x" valueReference="1" causality"#,
        r#"name="x" causality"#,
    );
    let message = assert_invalid(
        error,
        15,
        "ScalarVariable 'x' (index 2)",
        Some("valueReference"),
    );
    assert_eq!(
        message,
        "line 15: ScalarVariable 'x' (index 2): attribute valueReference: required but missing"
    );
}

#[test]
fn non_numeric_value_reference_quotes_the_value() {
    let error = broken(r#"valueReference="1""#, r#"valueReference="1a""#);
    let message = assert_invalid(
        error,
        15,
        "ScalarVariable 'x' (index 2)",
        Some("valueReference"),
    );
    assert!(
        message.contains("\"1a\" is not an unsigned integer"),
        "{message}"
    );
    assert!(message.contains("invalid digit"), "{message}");
}

#[test]
fn negative_value_reference_is_refused() {
    let error = broken(r#"valueReference="0""#, r#"valueReference="-1""#);
    assert_invalid(
        error,
        12,
        "ScalarVariable 'u' (index 1)",
        Some("valueReference"),
    );
}

#[test]
fn wrong_root_element_is_named() {
    let error = broken("<fmiModelDescription ", "<fmiModelDescriptionX ");
    assert!(
        matches!(&error, Error::WrongRoot { found } if found == "fmiModelDescriptionX"),
        "{error:?}"
    );
    assert_eq!(
        error.to_string(),
        "root element is <fmiModelDescriptionX>, expected <fmiModelDescription>"
    );
}

#[test]
fn an_fmi3_style_or_unrelated_document_is_a_wrong_root() {
    let error = ModelDescription::from_xml("<html><body/></html>").unwrap_err();
    assert!(matches!(error, Error::WrongRoot { .. }), "{error:?}");
}

#[test]
fn truncated_file_names_the_open_element() {
    let cut = VALID.find("<Real/>").unwrap();
    let error = ModelDescription::from_xml(&VALID[..cut]).unwrap_err();
    let message = error.to_string();
    match error {
        Error::Malformed { inside, .. } => {
            assert_eq!(
                inside.as_deref(),
                Some("ScalarVariable 'x' (index 2)"),
                "{message}"
            );
        }
        other => panic!("expected Error::Malformed, got {other:?}"),
    }
    assert!(message.contains("not well-formed XML"), "{message}");
}

#[test]
fn mismatched_tags_give_line_and_column() {
    let error = broken("</Outputs>", "</Output>");
    match error {
        Error::Malformed {
            line, ref inside, ..
        } => {
            assert_eq!(line, 22, "{error}");
            assert_eq!(
                inside.as_deref(),
                Some("ModelStructure > Outputs"),
                "{error}"
            );
        }
        other => panic!("expected Error::Malformed, got {other:?}"),
    }
}

#[test]
fn empty_input_is_malformed_not_a_panic() {
    let error = ModelDescription::from_xml("").unwrap_err();
    assert!(
        matches!(error, Error::Malformed { inside: None, .. }),
        "{error:?}"
    );
}

#[test]
fn unknown_causality_lists_the_legal_ones() {
    let error = broken(r#"causality="output""#, r#"causality="outptu""#);
    let message = assert_invalid(error, 15, "ScalarVariable 'x' (index 2)", Some("causality"));
    assert!(message.contains("\"outptu\" is not one of parameter, calculatedParameter, input, output, local, independent"), "{message}");
}

#[test]
fn non_numeric_real_start_names_the_type_element() {
    let error = broken(r#"<Real start="0"/>"#, r#"<Real start="zero"/>"#);
    let message = assert_invalid(
        error,
        13,
        "ScalarVariable 'u' (index 1) > Real",
        Some("start"),
    );
    assert!(message.contains("\"zero\" is not a number"), "{message}");
}

#[test]
fn a_boolean_attribute_outside_xs_boolean_is_refused() {
    let error = broken(
        r#"<CoSimulation modelIdentifier="M"/>"#,
        r#"<CoSimulation modelIdentifier="M" canGetAndSetFMUstate="yes"/>"#,
    );
    assert_invalid(error, 3, "CoSimulation", Some("canGetAndSetFMUstate"));
}

#[test]
fn a_variable_without_a_type_element_is_refused() {
    let error = broken("      <Real/>\n", "");
    let message = assert_invalid(error, 15, "ScalarVariable 'x' (index 2)", None);
    assert!(message.contains("has no type element"), "{message}");
}

#[test]
fn a_variable_with_two_type_elements_is_refused() {
    let error = broken("<Real/>", "<Real/><Integer/>");
    let message = assert_invalid(error, 15, "ScalarVariable 'x' (index 2)", None);
    assert!(
        message.contains("2 type elements (<Real>, <Integer>)"),
        "{message}"
    );
}

#[test]
fn a_bad_model_structure_index_names_the_list_and_position() {
    let error = broken(r#"<Unknown index="2"/>"#, r#"<Unknown index="two"/>"#);
    assert_invalid(
        error,
        21,
        "ModelStructure > Outputs > Unknown #1",
        Some("index"),
    );
}

#[test]
fn a_bad_dependency_is_quoted() {
    let error = broken(
        r#"<Unknown index="2"/>"#,
        r#"<Unknown index="2" dependencies="1 x"/>"#,
    );
    let message = assert_invalid(
        error,
        21,
        "ModelStructure > Outputs > Unknown #1",
        Some("dependencies"),
    );
    assert!(message.contains("\"x\" in \"1 x\""), "{message}");
}

#[test]
fn an_enumeration_item_without_value_names_its_type() {
    let error = broken(r#"<Item name="off" value="0"/>"#, r#"<Item name="off"/>"#);
    assert_invalid(
        error,
        7,
        "SimpleType 'Mode' > Enumeration > Item 'off'",
        Some("value"),
    );
}

#[test]
fn a_missing_root_attribute_is_named() {
    let error = broken(r#" guid="{0}""#, "");
    assert_invalid(error, 2, "fmiModelDescription", Some("guid"));
}

#[test]
fn a_second_co_simulation_element_is_refused() {
    let error = broken(
        r#"<CoSimulation modelIdentifier="M"/>"#,
        "<CoSimulation modelIdentifier=\"M\"/>\n  <CoSimulation modelIdentifier=\"N\"/>",
    );
    let message = assert_invalid(error, 4, "CoSimulation", None);
    assert!(message.contains("more than once"), "{message}");
}

#[test]
fn a_missing_file_names_the_path() {
    let error = ModelDescription::from_file("/nonexistent/modelDescription.xml").unwrap_err();
    assert!(matches!(error, Error::Io { .. }), "{error:?}");
    assert!(
        error
            .to_string()
            .contains("/nonexistent/modelDescription.xml"),
        "{error}"
    );
}

#[test]
fn a_second_outputs_list_is_refused() {
    let error = broken("</Outputs>", "</Outputs>\n    <Outputs/>");
    assert_invalid(error, 23, "ModelStructure > Outputs", None);
}

#[test]
fn fmi_1_and_fmi_3_files_are_refused_by_version_first() {
    for version in ["1.0", "3.0"] {
        let error = broken(r#"fmiVersion="2.0""#, &format!(r#"fmiVersion="{version}""#));
        let message = assert_invalid(error, 2, "fmiModelDescription", Some("fmiVersion"));
        assert!(message.contains("is not FMI 2.0"), "{message}");
    }
}
