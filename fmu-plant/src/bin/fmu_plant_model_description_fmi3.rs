//! Prints LanderPlant's FMI 3.0 modelDescription.xml (Co-Simulation and Model Exchange) to
//! stdout (packaged by `cargo xtask fmus` as target/fmu/fmi3/LanderPlant.fmu).
fn main() {
    print!(
        "{}",
        fmi3_export::model_description_xml_me::<fmu_plant::LanderPlant>()
    );
}
