//! Prints LanderFilter's modelDescription.xml to stdout (checked in as
//! `fmu-filter/modelDescription.xml`; a test fails on drift).
fn main() {
    print!(
        "{}",
        fmi2_export::model_description_xml::<fmu_filter::LanderFilter>()
    );
}
