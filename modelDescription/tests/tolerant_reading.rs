//! What real files contain beyond the schema and must not stop a reader.
use model_description::{ModelDescription, StartValue};

const MINIMAL: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="2.0" modelName="M" guid="{0}">
  <CoSimulation modelIdentifier="M"/>
  <ModelVariables>
    <ScalarVariable name="u" valueReference="0" causality="input">
      <Real start="1.5"/>
    </ScalarVariable>
    <ScalarVariable name="y" valueReference="1" causality="output">
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

fn read_modified(from: &str, to: &str) -> ModelDescription {
    assert!(
        MINIMAL.contains(from),
        "test bug: {from:?} is not in the file"
    );
    let xml = MINIMAL.replacen(from, to, 1);
    ModelDescription::from_xml(&xml).unwrap_or_else(|e| panic!("{e}\n{xml}"))
}

fn assert_same_content(md: &ModelDescription) {
    let reference = ModelDescription::from_xml(MINIMAL).unwrap();
    assert_eq!(md.model_variables, reference.model_variables);
    assert_eq!(md.model_structure, reference.model_structure);
    assert_eq!(
        md.variable("u").unwrap().start(),
        Some(StartValue::Real(1.5))
    );
}

#[test]
fn a_stray_element_between_variables_does_not_split_the_list() {
    let md = read_modified(
        "</ScalarVariable>\n    <ScalarVariable name=\"y\"",
        "</ScalarVariable>\n    <ToolSpecific a=\"1\"><Nested/></ToolSpecific>\n    <ScalarVariable name=\"y\"",
    );
    assert_same_content(&md);
}

#[test]
fn unknown_root_children_and_attributes_are_skipped() {
    let md = read_modified(
        "<ModelVariables>",
        "<Extension version=\"9\"><ScalarVariable bogus=\"x\"/></Extension>\n  <ModelVariables>",
    );
    assert_same_content(&md);
    let md = read_modified(
        r#"<Real start="1.5"/>"#,
        r#"<Real start="1.5" relativeQuantity="false" unbounded="true" vendorFlag="3"/>"#,
    );
    assert_same_content(&md);
}

#[test]
fn byte_order_mark_and_namespaces_are_accepted() {
    let md = ModelDescription::from_xml(&format!("\u{feff}{MINIMAL}")).unwrap();
    assert_same_content(&md);
    // A DOCTYPE, even a bare one, is refused: tests/declarations.rs.
    let md = read_modified(
        "<fmiModelDescription ",
        "<fmiModelDescription xmlns:xsi=\"http://www.w3.org/2001/XMLSchema-instance\" \
         xsi:noNamespaceSchemaLocation=\"fmi2ModelDescription.xsd\" ",
    );
    assert_same_content(&md);
}

#[test]
fn character_references_are_decoded() {
    let md = read_modified(r#"modelName="M""#, r#"modelName="a&#x41;&amp;&lt;""#);
    assert_eq!(md.model_name, "aA&<");
}

#[test]
fn latin1_declared_files_are_decoded() {
    let xml = MINIMAL
        .replace("encoding=\"UTF-8\"", "encoding=\"ISO-8859-1\"")
        .replace("modelName=\"M\"", "modelName=\"W\u{e4}rme\"");
    // Re-encode as Latin-1: every character of this text is below U+0100.
    let latin1: Vec<u8> = xml
        .chars()
        .map(|c| u8::try_from(u32::from(c)).unwrap())
        .collect();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("modelDescription.xml");
    std::fs::write(&path, latin1).unwrap();
    let md = ModelDescription::from_file(&path).unwrap();
    assert_eq!(md.model_name, "W\u{e4}rme");
}

#[test]
fn whitespace_around_a_double_is_collapsed_as_xs_double_allows() {
    let md = read_modified(r#"start="1.5""#, r#"start=" 1.5 ""#);
    assert_same_content(&md);
}
