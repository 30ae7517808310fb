//! Prints LanderNav's FMI 3.0 modelDescription.xml to stdout (packaged by `cargo xtask fmus`
//! as target/fmu/fmi3/LanderNav.fmu).
fn main() {
    print!(
        "{}",
        fmi3_export::model_description_xml::<fmu_nav::LanderNav>()
    );
}
