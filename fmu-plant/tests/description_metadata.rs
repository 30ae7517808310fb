//! What a tool shows of the plant beyond its variables: who made it, under which terms, and
//! angles in degrees, in both FMI versions' model descriptions.
use model_description::ModelDescription;

const DEG_PER_RAD: f64 = 57.29577951308232;

#[test]
fn both_descriptions_name_author_copyright_license_and_show_angles_in_degrees() {
    let fmi2 = fmi2_export::model_description_xml_me::<fmu_plant::LanderPlant>();
    let fmi3 = fmi3_export::model_description_xml_me::<fmu_plant::LanderPlant>();
    for (version, xml) in [("FMI 2.0", &fmi2), ("FMI 3.0", &fmi3)] {
        for attribute in [
            r#"author="the lander-fmi contributors""#,
            r#"copyright="Copyright (c) 2026 the lander-fmi contributors""#,
            r#"license="MIT OR Apache-2.0""#,
            r#"version="0.1.0""#,
        ] {
            assert!(xml.contains(attribute), "{version}: no {attribute}");
        }
        for (unit, display) in [("rad", "deg"), ("rad/s", "deg/s")] {
            let element = format!(r#"<DisplayUnit name="{display}" factor="{DEG_PER_RAD}"/>"#);
            let at = xml
                .find(&format!(r#"<Unit name="{unit}">"#))
                .unwrap_or_else(|| panic!("{version}: no unit {unit}"));
            let end = at + xml[at..].find("</Unit>").unwrap();
            assert!(
                xml[at..end].contains(&element),
                "{version}: {unit} has no {element}"
            );
        }
    }
    // FMI 2.0: each angle variable defaults to its display unit, read back by our reader.
    let md = ModelDescription::from_xml(&fmi2).unwrap();
    let tilt = md
        .model_variables
        .variables
        .iter()
        .find(|v| {
            v.real
                .as_ref()
                .is_some_and(|r| r.unit.as_deref() == Some("rad"))
        })
        .expect("an angle variable");
    assert_eq!(
        tilt.real.as_ref().unwrap().display_unit.as_deref(),
        Some("deg"),
        "{}",
        tilt.name
    );
    // FMI 3.0: through the unit's declared type.
    assert!(fmi3.contains(r#"<Float64Type name="rad" unit="rad" displayUnit="deg"/>"#));
    // The factor is 180 / pi.
    assert_eq!(DEG_PER_RAD, 180.0 / std::f64::consts::PI);
}
