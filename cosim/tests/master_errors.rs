//! The master refuses a broken system before anything runs, naming every problem, and ends a
//! run the FMU refuses with the FMU's own log in the error.
use cosim::master::{MasterError, Simulation};
use cosim::system::{Connection, ParamValue};

use crate::common::{fmu_dir, lander_loop};

#[test]
fn unknown_names_and_type_mismatches_are_all_reported_before_the_run() {
    // GIVEN the lander loop with a misspelt source, a misspelt parameter and an Integer
    // output wired to a Real input
    let mut system = lander_loop();
    system.connections.push(Connection {
        from: "plant.r_neu".into(),
        to: "gnc.r_nue".into(),
    });
    system.connections.push(Connection {
        from: "gnc.guidance_phase".into(),
        to: "plant.thrust_cmd".into(),
    });
    system.set_parameter("gnc", "phi_cmdd", ParamValue::Real(1.0));
    // WHEN it is resolved against the FMUs
    let error = match Simulation::new(system, &fmu_dir()) {
        Err(error @ MasterError::Resolve { .. }) => error.to_string(),
        Err(other) => panic!("wrong error: {other}"),
        Ok(_) => panic!("a broken system was accepted"),
    };
    // THEN one error names all three problems
    assert!(
        error.contains("'plant.r_neu'") && error.contains("r_neu"),
        "{error}"
    );
    assert!(
        error.contains("gnc.guidance_phase") && error.contains("plant.thrust_cmd"),
        "{error}"
    );
    assert!(error.contains("type mismatch"), "{error}");
    assert!(error.contains("phi_cmdd"), "{error}");
}

#[test]
fn a_refused_parameter_ends_the_run_with_the_fmu_log() {
    // GIVEN a thrust range the GNC must refuse at initialization (each bound is within its
    // declared range; together they are not)
    let mut system = lander_loop();
    system.set_parameter("gnc", "thrust_min", ParamValue::Real(2000.0));
    let mut simulation = Simulation::new(system, &fmu_dir()).unwrap();
    // WHEN the run starts
    let error = simulation
        .run(&mut cosim::master::Trajectory::default())
        .unwrap_err();
    // THEN the error chain carries the FMU's log line naming the parameter
    let text = format!("{:#}", anyhow::Error::from(error));
    assert!(text.contains("fmi2ExitInitializationMode"), "{text}");
    assert!(text.contains("thrust_max"), "{text}");
}

#[test]
fn an_output_and_values_outside_their_declared_range_are_refused_before_the_run() {
    // GIVEN the lander loop asking to set the plant's output `altitude`, the control law 7
    // (declared 1 to the last law) and phi_cmd 20 rad (declared within +-4 pi)
    let mut system = lander_loop();
    system.set_parameter("plant", "altitude", ParamValue::Real(5.0));
    system.set_parameter("gnc", "control_law", ParamValue::Integer(7));
    system.set_parameter("gnc", "phi_cmd", ParamValue::Real(20.0));
    // WHEN it is resolved against the FMUs, before any FMU is instantiated
    let error = match Simulation::new(system, &fmu_dir()) {
        Err(error @ MasterError::Resolve { .. }) => error.to_string(),
        Err(other) => panic!("wrong error: {other}"),
        Ok(_) => panic!("the system was accepted"),
    };
    // THEN one error names each value and what the FMU declares
    assert!(
        error.contains("'altitude' is an output with initial=\"calculated\""),
        "{error}"
    );
    assert!(
        error.contains("'control_law' = 7 is above its declared max"),
        "{error}"
    );
    assert!(
        error.contains("'phi_cmd' = 20 is above its declared max"),
        "{error}"
    );
}

#[test]
fn a_vector_set_whole_names_its_elements_and_suggestions_are_only_settable_variables() {
    let mut system = lander_loop();
    system.set_parameter("plant", "r0_nue", ParamValue::Real(100.0));
    system.set_parameter("plant", "altitde", ParamValue::Real(3.0));
    let error = match Simulation::new(system, &fmu_dir()) {
        Err(error @ MasterError::Resolve { .. }) => error.to_string(),
        Err(other) => panic!("wrong error: {other}"),
        Ok(_) => panic!("the system was accepted"),
    };
    assert!(
        error.contains("'r0_nue' is a vector of 3: set its elements, e.g. plant.r0_nue[1]"),
        "{error}"
    );
    // `altitude` is an output: not a suggestion for a value to set.
    assert!(
        error.contains("'altitde'") && !error.contains("did you mean 'altitude'"),
        "{error}"
    );
}
