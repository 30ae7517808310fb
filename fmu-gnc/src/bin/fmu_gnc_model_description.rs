//! Prints LanderGnc's modelDescription.xml (generated from the variable table) to stdout.
//! `fmu-gnc/modelDescription.xml` is this output, checked in; a test fails on drift.
fn main() {
    print!(
        "{}",
        fmi2_export::model_description_xml::<fmu_gnc::LanderGnc>()
    );
}
