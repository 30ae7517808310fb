//! Rejected parameters through both FMI versions' C functions: each refused by name with its
//! value in the log, the instance left usable.
use fmi_testkit::{
    fmi2_functions, fmi3_functions, AtExit, Fmi2, Fmi2Functions, Fmi3, Fmi3Functions, Refusals,
};
use fmu_filter::LanderFilter;

static FUNCTIONS2: Fmi2Functions = fmi2_functions!(fmu_filter);
static FUNCTIONS3: Fmi3Functions = fmi3_functions!(fmu_filter);

const REFUSALS: Refusals = Refusals {
    in_the_set: &[
        ("gyro_scale_factor_sigma", 0.2, "0.2"),
        ("accel_misalignment_sigma", -1e-3, "-0.001"),
        ("accel_scale_factor_sigma", f64::NAN, "NaN"),
        ("altimeter_noise_sigma", 0.0, "0"),
        ("chi2_gate", 0.0, "0"),
        ("attitude0_sigma", f64::INFINITY, "inf"),
    ],
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
