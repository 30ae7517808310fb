//! Prints the Oscillator's modelDescription.xml (used by `cargo xtask fmus`).
fn main() {
    print!(
        "{}",
        fmi2_export::model_description_xml::<fmu_testmodel::Oscillator>()
    );
}
