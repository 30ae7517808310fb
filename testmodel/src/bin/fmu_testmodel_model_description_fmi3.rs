//! Prints the Oscillator's FMI 3.0 modelDescription.xml (Co-Simulation and Model Exchange)
//! to stdout, or with `terminals-and-icons` its terminalsAndIcons.xml (packaged by
//! `cargo xtask fmus` as target/fmu/fmi3/Oscillator.fmu).
fn main() {
    fmi3_export::describe::<fmu_testmodel::Oscillator>(
        fmi3_export::model_description_xml_me::<fmu_testmodel::Oscillator>,
    );
}
