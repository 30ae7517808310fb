//! Rejected parameters through both FMI versions' C functions: each refused by name with its
//! value in the log, the instance left usable.
use fmi_testkit::{
    fmi2_functions, fmi3_functions, Fmi2, Fmi2Functions, Fmi3, Fmi3Functions, Refusals,
};
use fmu_nav::LanderNav;

static FUNCTIONS2: Fmi2Functions = fmi2_functions!(fmu_nav);
static FUNCTIONS3: Fmi3Functions = fmi3_functions!(fmu_nav);

const REFUSALS: Refusals = Refusals {
    in_the_set: &[
        ("r_nue_noise_sigma", -1.0, "-1"),
        ("v_nue_random_walk", f64::NAN, "NaN"),
        ("attitude_noise_sigma", -0.01, "-0.01"),
        ("omega_body_noise_sigma", f64::NEG_INFINITY, "-inf"),
    ],
    at_exit: &[],
    step: 0.01,
};

#[test]
fn fmi2_refuses_rejected_parameters_by_name_and_stays_usable() {
    REFUSALS.check::<LanderNav, Fmi2>(&FUNCTIONS2, &fmi2_export::guid::<LanderNav>());
}

#[test]
fn fmi3_refuses_rejected_parameters_by_name_and_stays_usable() {
    let token = fmi3_export::instantiation_token::<LanderNav>();
    REFUSALS.check::<LanderNav, Fmi3>(&FUNCTIONS3, &token);
}
