#![no_main]
//! FMI 3.0: (b) A random sequence of calls over the whole C ABI of one instance.
//! Written by `cargo xtask fuzz-crates` from [package.metadata.fmu].
#[path = "../../common/driver3.rs"]
mod driver3;

static FUNCTIONS: fmi_testkit::Fmi3Functions = fmi_testkit::fmi3_functions!(fmu_filter);

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    driver3::call_sequence::<fmu_filter::LanderFilter>(&FUNCTIONS, data);
});
