//! What only LanderFilter's refusals say, through both FMI versions' C functions: a sample
//! period within its bounds whose noise variance overflows. (Every value past a declared
//! bound, and every non-finite one: tests/conformance.rs.)
use fmi_testkit::{
    fmi2_functions, fmi3_functions, AtExit, Fmi2, Fmi2Functions, Fmi3, Fmi3Functions, Refusals,
};
use fmu_filter::LanderFilter;

static FUNCTIONS2: Fmi2Functions = fmi2_functions!(fmu_filter);
static FUNCTIONS3: Fmi3Functions = fmi3_functions!(fmu_filter);

const REFUSALS: Refusals = Refusals {
    in_the_set: &[],
    at_exit: &[
        // Within its bounds, but the white noise variance of one sample overflows.
        AtExit {
            sets: &[("imu_sample_period", 5e-324)],
            name: "imu_sample_period",
            says: "overflows",
        },
    ],
    step: 0.01,
};

#[test]
fn fmi2_refuses_rejected_parameters_by_name_and_stays_usable() {
    REFUSALS.check::<LanderFilter, Fmi2>(&FUNCTIONS2, &fmi2_export::guid::<LanderFilter>());
}

#[test]
fn fmi3_refuses_rejected_parameters_by_name_and_stays_usable() {
    let token = fmi3_export::instantiation_token::<LanderFilter>();
    REFUSALS.check::<LanderFilter, Fmi3>(&FUNCTIONS3, &token);
}
