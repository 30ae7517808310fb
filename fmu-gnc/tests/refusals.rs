//! What only LanderGnc's refusals say, through both FMI versions' C functions: the angle
//! likely meant in degrees, and limits each within its bounds that the pair is not. (Every
//! value past a declared bound: tests/conformance.rs.)
use fmi_testkit::{
    fmi2_functions, fmi3_functions, AtExit, Fmi2, Fmi2Functions, Fmi3, Fmi3Functions, Refusals,
};
use fmu_gnc::LanderGnc;

static FUNCTIONS2: Fmi2Functions = fmi2_functions!(fmu_gnc);
static FUNCTIONS3: Fmi3Functions = fmi3_functions!(fmu_gnc);

const REFUSALS: Refusals = Refusals {
    in_the_set: &[
        // The unit named, and the value in the display unit it was likely meant in
        (
            "phi_cmd",
            150.0,
            "value 150 rad is outside [-4π, 4π] rad; did you mean 150 deg = 2.618 rad?",
        ),
        (
            "phi_cmd",
            13.0,
            "value 13 rad is outside [-4π, 4π] rad; did you mean 13 deg = 0.2269 rad?",
        ),
    ],
    at_exit: &[
        // Each within its bounds, the pair not: the lowest thrust above the highest.
        AtExit {
            sets: &[("thrust_min", 5000.0), ("thrust_max", 1000.0)],
            name: "thrust_max",
            says: "1000: must be >= thrust_min",
        },
    ],
    step: 0.01,
};

#[test]
fn fmi2_refuses_rejected_parameters_by_name_and_stays_usable() {
    REFUSALS.check::<LanderGnc, Fmi2>(&FUNCTIONS2, &fmi2_export::guid::<LanderGnc>());
}

#[test]
fn fmi3_refuses_rejected_parameters_by_name_and_stays_usable() {
    let token = fmi3_export::instantiation_token::<LanderGnc>();
    REFUSALS.check::<LanderGnc, Fmi3>(&FUNCTIONS3, &token);
}
