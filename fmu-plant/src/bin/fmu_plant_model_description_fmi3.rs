//! Prints LanderPlant's FMI 3.0 modelDescription.xml (Co-Simulation and Model Exchange) to
//! stdout, or with `terminals-and-icons` its terminalsAndIcons.xml (packaged by `cargo xtask
//! fmus` as target/fmu/fmi3/LanderPlant.fmu).
fn main() {
    fmi3_export::describe::<fmu_plant::LanderPlant>(
        fmi3_export::model_description_xml_me::<fmu_plant::LanderPlant>,
    );
}
