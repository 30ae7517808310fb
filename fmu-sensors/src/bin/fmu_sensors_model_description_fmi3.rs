//! Prints LanderSensors' FMI 3.0 modelDescription.xml to stdout (checked in as
//! `fmu-sensors/modelDescription.fmi3.xml`), or with `terminals-and-icons` its
//! terminalsAndIcons.xml; both packaged by `cargo xtask fmus` in
//! target/fmu/fmi3/LanderSensors.fmu.
fn main() {
    fmi3_export::describe::<fmu_sensors::LanderSensors>(
        fmi3_export::model_description_xml::<fmu_sensors::LanderSensors>,
    );
}
