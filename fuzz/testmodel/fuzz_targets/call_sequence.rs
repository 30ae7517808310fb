#![no_main]
//! (b) A random sequence of calls over the whole C ABI of one instance.
//! Written by `cargo xtask fuzz-crates` from [package.metadata.fmu].
#[path = "../../common/driver.rs"]
mod driver;

static FUNCTIONS: fmi_testkit::Fmi2Functions = fmi_testkit::fmi2_functions!(fmu_testmodel);

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    driver::call_sequence::<fmu_testmodel::Oscillator>(&FUNCTIONS, data);
});
