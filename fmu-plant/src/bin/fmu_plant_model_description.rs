//! Prints LanderPlant's modelDescription.xml to stdout (checked in as
//! `fmu-plant/modelDescription.xml`; a test fails on drift).
fn main() {
    print!(
        "{}",
        fmi2_export::model_description_xml_me::<fmu_plant::LanderPlant>()
    );
}
