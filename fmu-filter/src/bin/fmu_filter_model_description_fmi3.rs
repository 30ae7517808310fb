//! Prints LanderFilter's FMI 3.0 modelDescription.xml to stdout (checked in as
//! `fmu-filter/modelDescription.fmi3.xml`; packaged by `cargo xtask fmus` as
//! target/fmu/fmi3/LanderFilter.fmu).
fn main() {
    print!(
        "{}",
        fmi3_export::model_description_xml::<fmu_filter::LanderFilter>()
    );
}
