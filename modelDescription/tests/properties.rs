//! Property tests: whatever a model can put in a description comes back unchanged.
use model_description::*;
use proptest::prelude::*;

fn with_real_start(value: f64) -> ModelDescription {
    ModelDescription {
        fmi_version: "2.0".into(),
        model_name: "P".into(),
        guid: "{0}".into(),
        model_variables: ModelVariables {
            variables: vec![ScalarVariable {
                name: "x".into(),
                value_reference: 0,
                causality: Some(Causality::Parameter),
                variability: Some(Variability::Fixed),
                real: Some(RealVariable {
                    start: Some(value),
                    ..Default::default()
                }),
                ..Default::default()
            }],
        },
        ..Default::default()
    }
}

fn read_back(md: &ModelDescription) -> ModelDescription {
    let xml = md.to_xml().expect("writes");
    ModelDescription::from_xml(&xml).unwrap_or_else(|e| panic!("{e}\n{xml}"))
}

/// Characters XML 1.0 can carry in an attribute value (all but most C0 controls).
fn xml_char() -> impl Strategy<Value = char> {
    any::<char>().prop_filter("XML 1.0 Char", |c| {
        !matches!(*c, '\u{0}'..='\u{8}' | '\u{B}' | '\u{C}' | '\u{E}'..='\u{1F}' | '\u{FFFE}' | '\u{FFFF}')
    })
}

proptest! {
    #[test]
    fn every_double_round_trips_bit_exactly(bits in any::<u64>()) {
        let value = f64::from_bits(bits);
        let back = read_back(&with_real_start(value));
        let start = back.variable("x").unwrap().real.as_ref().unwrap().start.unwrap();
        if value.is_nan() {
            // XML has one NaN; the payload bits are not part of the value space.
            prop_assert!(start.is_nan());
        } else {
            prop_assert_eq!(start.to_bits(), bits);
        }
    }

    #[test]
    fn every_representable_string_round_trips(
        text in proptest::collection::vec(xml_char(), 0..40).prop_map(String::from_iter),
        start in proptest::collection::vec(xml_char(), 0..40).prop_map(String::from_iter),
    ) {
        let mut md = with_real_start(1.0);
        md.description = Some(text.clone());
        md.model_variables.variables.push(ScalarVariable {
            name: text.clone(),
            value_reference: 0,
            causality: Some(Causality::Parameter),
            variability: Some(Variability::Fixed),
            string: Some(StringVariable { declared_type: None, start: Some(start) }),
            ..Default::default()
        });
        prop_assert_eq!(read_back(&md), md);
    }
}
