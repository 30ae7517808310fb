//! The table is valid and the XML reads back into the same description (that the checked-in
//! modelDescription.xml is what the code generates: tests/conformance.rs).
use fmi2_export::{check_table, model_description, model_description_xml};
use fmu_testmodel::Oscillator;
use model_description::{Causality, ModelDescription};

#[test]
fn the_table_passes_check_table() {
    check_table::<Oscillator>().unwrap();
}

#[test]
fn the_xml_reads_back_and_validates() {
    let written = model_description::<Oscillator>();
    let read = ModelDescription::from_xml(&model_description_xml::<Oscillator>()).unwrap();
    assert_eq!(read, written);
    read.validate().unwrap();
}

/// ModelStructure by hand: outputs x (6), v (7), step_count (10), no direct feedthrough;
/// initial unknowns are those outputs plus the calculated parameter omega_n (8).
#[test]
fn model_structure_lists_outputs_and_initial_unknowns() {
    let md = model_description::<Oscillator>();
    let index_of = |name: &str| {
        md.model_variables
            .variables
            .iter()
            .position(|v| v.name == name)
            .unwrap() as u32
            + 1
    };
    let outputs = md.model_structure.outputs.unwrap().unknowns;
    let expected: Vec<u32> = ["x", "v", "step_count"]
        .iter()
        .map(|n| index_of(n))
        .collect();
    assert_eq!(
        outputs.iter().map(|u| u.index).collect::<Vec<_>>(),
        expected
    );
    assert!(outputs
        .iter()
        .all(|u| u.dependencies.as_deref() == Some("")));
    let initial: Vec<u32> = md
        .model_structure
        .initial_unknowns
        .unwrap()
        .unknowns
        .iter()
        .map(|u| u.index)
        .collect();
    assert_eq!(
        initial,
        vec![
            index_of("x"),
            index_of("v"),
            index_of("omega_n"),
            index_of("step_count")
        ]
    );
    for i in &initial {
        let var = &md.model_variables.variables[*i as usize - 1];
        assert!(matches!(
            var.causality,
            Some(Causality::Output | Causality::CalculatedParameter)
        ));
    }
}

/// FMI 3.0 wants value references unique across types and an event indicator and state
/// derivatives that name declared variables: the description builds without a problem.
#[test]
fn the_fmi3_description_is_valid() {
    assert_eq!(
        fmi3_export::variables::check::<Oscillator>(),
        Vec::<String>::new()
    );
    let xml = fmi3_export::model_description_xml_me::<Oscillator>();
    assert!(xml.contains("<ModelExchange modelIdentifier=\"Oscillator\""));
    assert!(xml.contains("<EventIndicator valueReference=\"11\"/>"));
    assert!(xml.contains("<ContinuousStateDerivative valueReference=\"9\"/>"));
}
