//! Files with a DTD are refused before parsing, by the FMI 2.0 and 3.0 readers alike: no
//! entity is expanded, not even once.
use model_description::fmi3::{fmi_version_of, Fmi3ModelDescription};
use model_description::{Error, ModelDescription};

/// Ten entities, each ten references to the previous: 10^9 copies of "lol" once expanded.
fn entity_bomb(root: &str, version: &str) -> String {
    let mut text = format!("<?xml version=\"1.0\"?>\n<!DOCTYPE {root} [\n<!ENTITY lol0 \"lol\">\n");
    for level in 1..10 {
        let previous = format!("&lol{};", level - 1).repeat(10);
        text.push_str(&format!("<!ENTITY lol{level} \"{previous}\">\n"));
    }
    text.push_str(&format!(
        "]>\n<{root} fmiVersion=\"{version}\" modelName=\"&lol9;\" guid=\"g\" \
         instantiationToken=\"t\"><ModelVariables/></{root}>\n"
    ));
    text
}

const ONE_ENTITY: &str = r#"<?xml version="1.0"?>
<!DOCTYPE fmiModelDescription [<!ENTITY name "Expanded">]>
<fmiModelDescription fmiVersion="2.0" modelName="&name;" guid="{g}">
  <CoSimulation modelIdentifier="m"/>
  <ModelVariables/>
  <ModelStructure/>
</fmiModelDescription>
"#;

fn assert_refused(result: Result<impl std::fmt::Debug, Error>, line: u64) {
    match result {
        Err(Error::Declaration { line: at, keyword }) => {
            assert_eq!((at, keyword.as_str()), (line, "DOCTYPE"));
        }
        other => panic!("expected the DTD refused, got {other:?}"),
    }
}

#[test]
fn an_entity_bomb_is_refused_unparsed_by_both_readers() {
    let start = std::time::Instant::now();
    assert_refused(
        ModelDescription::from_xml(&entity_bomb("fmiModelDescription", "2.0")),
        2,
    );
    assert_refused(
        Fmi3ModelDescription::from_xml(&entity_bomb("fmiModelDescription", "3.0")),
        2,
    );
    assert_eq!(
        fmi_version_of(entity_bomb("fmiModelDescription", "3.0").as_bytes()),
        None
    );
    assert!(start.elapsed().as_secs() < 2, "{:?}", start.elapsed());
}

#[test]
fn a_single_entity_is_not_expanded_but_refused() {
    assert_refused(ModelDescription::from_xml(ONE_ENTITY), 2);
    let text = ONE_ENTITY
        .replace("2.0", "3.0")
        .replace("guid", "instantiationToken");
    assert_refused(Fmi3ModelDescription::from_xml(&text), 2);
}

#[test]
fn the_refusal_says_what_and_where() {
    let error = ModelDescription::from_xml(ONE_ENTITY)
        .unwrap_err()
        .to_string();
    assert!(error.starts_with("line 2: <!DOCTYPE ...>"), "{error}");
    assert!(error.contains("entity"), "{error}");
}

#[test]
fn even_a_bare_doctype_is_refused() {
    let text = ONE_ENTITY
        .replace(" [<!ENTITY name \"Expanded\">]", "")
        .replace("&name;", "M");
    assert_refused(ModelDescription::from_xml(&text), 2);
}
