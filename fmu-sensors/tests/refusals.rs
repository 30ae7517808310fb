//! Rejected parameters through both FMI versions' C functions: each refused by name with its
//! value in the log, the instance left usable. (The parameters the model
//! rejects only in combination are vectors: `tests/robustness`' FMI 2.0 suite sets them.)
use fmi_testkit::{
    fmi2_functions, fmi3_functions, Fmi2, Fmi2Functions, Fmi3, Fmi3Functions, Refusals,
};
use fmu_sensors::LanderSensors;

static FUNCTIONS2: Fmi2Functions = fmi2_functions!(fmu_sensors);
static FUNCTIONS3: Fmi3Functions = fmi3_functions!(fmu_sensors);

const REFUSALS: Refusals = Refusals {
    in_the_set: &[
        ("accel_scale_factor_sigma", 0.06, "0.06"),
        ("gyro_misalignment_sigma", -1e-3, "-0.001"),
        ("accel_bias_sigma", -1.0, "-1"),
        ("imu_sample_period", 0.0, "0"),
        ("altimeter_dropout_probability", 1.5, "1.5"),
        ("velocimeter_max_range", f64::NAN, "NaN"),
    ],
    at_exit: &[],
    step: 0.01,
};

#[test]
fn fmi2_refuses_rejected_parameters_by_name_and_stays_usable() {
    REFUSALS.check::<LanderSensors, Fmi2>(&FUNCTIONS2, &fmi2_export::guid::<LanderSensors>());
}

#[test]
fn fmi3_refuses_rejected_parameters_by_name_and_stays_usable() {
    let token = fmi3_export::instantiation_token::<LanderSensors>();
    REFUSALS.check::<LanderSensors, Fmi3>(&FUNCTIONS3, &token);
}
