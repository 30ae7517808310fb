//! Prints LanderNav's FMI 3.0 modelDescription.xml to stdout, or with
//! `terminals-and-icons` its terminalsAndIcons.xml (packaged by `cargo xtask fmus`
//! as target/fmu/fmi3/LanderNav.fmu).
fn main() {
    fmi3_export::describe::<fmu_nav::LanderNav>(
        fmi3_export::model_description_xml::<fmu_nav::LanderNav>,
    );
}
