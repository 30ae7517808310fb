#![no_main]
//! (a) A crafted FMU-state payload with a valid header and checksum, then gets and a step.
//! Written by `cargo xtask fuzz-crates` from [package.metadata.fmu].
#[path = "../../common/driver.rs"]
mod driver;

static FUNCTIONS: fmi_testkit::Fmi2Functions = fmi_testkit::fmi2_functions!(fmu_testmodel);

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    driver::restored_state::<fmu_testmodel::Oscillator>(&FUNCTIONS, data);
});
