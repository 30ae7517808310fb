#![no_main]
//! (b) FMI 3.0: a random sequence of calls over the whole C ABI of one instance
//! (Co-Simulation with each choice of the master, or Model Exchange).
#[path = "../../common/driver3.rs"]
mod driver3;

static FUNCTIONS: fmi_testkit::Fmi3Functions = fmi_testkit::fmi3_functions!(fmu_gnc);

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    driver3::call_sequence::<fmu_gnc::LanderGnc>(&FUNCTIONS, data);
});
