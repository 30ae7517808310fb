//! LanderGnc through its FMI 3.0 C functions, on the test kit's FMI 3.0 driver:
//! Co-Simulation works with array inputs and outputs (Model Exchange, which it does not
//! offer, refused with the reason: tests/conformance.rs).

use fmi_testkit::fmi3_ffi::*;
use fmi_testkit::{fmi3_functions, CoSimulationOptions, Fmi3Functions, Fmi3Instance};

static FUNCTIONS: Fmi3Functions = fmi3_functions!(fmu_gnc);

fn token() -> String {
    fmi3_export::instantiation_token::<fmu_gnc::LanderGnc>()
}

#[test]
fn co_simulation_steps_and_reads_the_thrust_command() {
    let gnc =
        Fmi3Instance::co_simulation(&FUNCTIONS, "gnc", &token(), CoSimulationOptions::default())
            .unwrap_or_else(|log| panic!("{log:?}"));
    assert_eq!(gnc.enter_initialization_mode(0.0, None), fmi3OK);
    assert_eq!(gnc.exit_initialization_mode(), fmi3OK);
    let step = gnc.do_step(0.0, 0.01);
    assert_eq!(step.status, fmi3OK);
    assert_eq!(step.last_successful_time, 0.01);
    let (status, n) = gnc.number_of_continuous_states();
    assert_eq!(status, fmi3OK);
    assert_eq!(
        n, 0,
        "a Co-Simulation-only model has no continuous states to offer"
    );
}
