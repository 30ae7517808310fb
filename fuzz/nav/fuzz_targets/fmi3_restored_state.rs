#![no_main]
//! FMI 3.0: (a) A crafted FMU-state payload with a valid header and checksum, then gets and a step.
//! Written by `cargo xtask fuzz-crates` from [package.metadata.fmu].
#[path = "../../common/driver3.rs"]
mod driver3;

static FUNCTIONS: fmi_testkit::Fmi3Functions = fmi_testkit::fmi3_functions!(fmu_nav);

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    driver3::restored_state::<fmu_nav::LanderNav>(&FUNCTIONS, data);
});
