//! Prints LanderSensors' modelDescription.xml to stdout (checked in as
//! `fmu-sensors/modelDescription.xml`; a test fails on drift).
fn main() {
    print!(
        "{}",
        fmi2_export::model_description_xml::<fmu_sensors::LanderSensors>()
    );
}
