//! The master for any system, not only the lander's: algebraic loops and values set on
//! connected inputs refused, parameter types and names checked before the run, each problem
//! named with a suggestion.
use cosim::master::{MasterError, Simulation};
use cosim::system::{Connection, InstanceDesc, ParamValue, SystemDescription};

use crate::common::{fmu_dir, lander_loop};

/// The problems `Simulation::new` reports, as one text.
fn refused(system: SystemDescription) -> String {
    match Simulation::new(system, &fmu_dir()) {
        Err(error @ MasterError::Resolve { .. }) => error.to_string(),
        Err(other) => panic!("wrong error: {other}"),
        Ok(_) => panic!("a broken system was accepted"),
    }
}

#[test]
fn missing_fmus_are_all_named_with_where_they_were_looked_for() {
    let empty = tempfile::tempdir().unwrap();
    let error = match Simulation::new(lander_loop(), empty.path()) {
        Err(error) => error.to_string(),
        Ok(_) => panic!("ran without FMUs"),
    };
    for expected in [
        "instance 'gnc'",
        "instance 'plant'",
        "LanderGnc.fmu",
        "--fmu-dir",
        "LANDER_FMU_DIR",
    ] {
        assert!(error.contains(expected), "{expected}: {error}");
    }
}

#[test]
fn a_gnc_wired_to_itself_is_an_algebraic_loop_named_in_the_error() {
    // GIVEN one GNC whose thrust command feeds its own mass input (every GNC output depends
    // on every input in its ModelStructure)
    let mut system = lander_loop();
    system.instances.retain(|i| i.name == "gnc");
    system.connections = vec![Connection {
        from: "gnc.thrust_cmd".into(),
        to: "gnc.mass".into(),
    }];
    // WHEN it is resolved THEN it is refused, naming the cycle
    let error = refused(system);
    assert!(
        error.contains("algebraic loop: gnc.thrust_cmd -> gnc.mass ~> gnc.thrust_cmd"),
        "{error}"
    );
}

#[test]
fn a_declared_feedthrough_loop_is_accepted_under_jacobi_ordering_where_every_link_is_delayed() {
    // GIVEN the loop through the plant's delivered thrust that Gauss-Seidel refuses
    let mut system = lander_loop();
    for c in &mut system.connections {
        if c.to == "gnc.mass" {
            c.from = "plant.thrust_actual".into();
        }
    }
    let mut gauss_seidel = system.clone();
    gauss_seidel.ordering = cosim::system::Ordering::GaussSeidel;
    assert!(refused(gauss_seidel).contains("algebraic loop"));
    // WHEN it is resolved for Jacobi ordering THEN it is accepted and flies its first second
    system.ordering = cosim::system::Ordering::Jacobi;
    system.stop_time = 1.0;
    let mut simulation = Simulation::new(system, &fmu_dir()).unwrap();
    let mut trajectory = cosim::master::Trajectory::default();
    simulation.run(&mut trajectory).unwrap();
    assert_eq!(trajectory.len(), 101);
}

#[test]
fn a_loop_through_the_plants_feedthrough_output_is_refused_and_the_paper_loop_is_not() {
    // GIVEN the lander loop with the GNC's mass taken from the plant's delivered thrust, an
    // output that depends on the thrust command
    let mut system = lander_loop();
    for c in &mut system.connections {
        if c.to == "gnc.mass" {
            c.from = "plant.thrust_actual".into();
        }
    }
    let error = refused(system);
    assert!(error.contains("algebraic loop"), "{error}");
    assert!(
        error.contains("plant.thrust_actual -> gnc.mass")
            && error.contains("gnc.thrust_cmd -> plant.thrust_cmd"),
        "{error}"
    );
    // The paper loop itself runs: the plant's navigation outputs depend on no input.
    Simulation::new(lander_loop(), &fmu_dir()).unwrap_or_else(|e| panic!("{e}"));
}

#[test]
fn a_value_set_on_a_connected_input_is_refused() {
    // GIVEN the lander loop, where gnc.mass comes from plant.mass
    let mut simulation = Simulation::new(lander_loop(), &fmu_dir()).unwrap();
    // WHEN a value is set on it THEN it is refused, naming the connection
    let error = simulation
        .set_parameter("gnc", "mass", ParamValue::Real(900.0))
        .unwrap_err()
        .to_string();
    assert!(error.contains("connected from 'plant.mass'"), "{error}");
    // and so is the same value in the scenario, before anything runs
    let mut system = lander_loop();
    system.set_parameter("gnc", "mass", ParamValue::Real(900.0));
    assert!(refused(system).contains("connected from 'plant.mass'"));
    // while an unconnected parameter is accepted
    simulation
        .set_parameter("gnc", "phi_cmd", ParamValue::Real(0.5))
        .unwrap();
}

#[test]
fn parameter_types_and_names_are_checked_before_the_run_all_at_once() {
    let mut system = lander_loop();
    system.set_parameter("gnc", "control_law", ParamValue::Real(1.5));
    system.set_parameter("gnc", "phi_cmd", ParamValue::Boolean(true));
    system.set_parameter("plant", "m0", ParamValue::String("heavy".into()));
    system.set_parameter("gnc", "control_bandwith", ParamValue::Real(0.5));
    let error = refused(system);
    assert!(
        error.contains("'control_law'") && error.contains("the Real 1.5"),
        "{error}"
    );
    assert!(
        error.contains("'phi_cmd' is Real") && error.contains("the Boolean true"),
        "{error}"
    );
    assert!(
        error.contains("'m0'") && error.contains("\"heavy\""),
        "{error}"
    );
    assert!(
        error.contains("(did you mean 'control_bandwidth'?)"),
        "{error}"
    );
}

#[test]
fn an_unknown_instance_in_a_connection_gets_a_suggestion() {
    let mut system = lander_loop();
    system.instances.push(InstanceDesc {
        name: "plant2".into(),
        fmu: "LanderPlant.fmu".into(),
        parameters: vec![],
        connectors: None,
        model_exchange: None,
        interface_named: false,
    });
    system.connections.push(Connection {
        from: "plant2.mass".into(),
        to: "gcn.mass".into(),
    });
    // validate() already refuses the unknown instance; the master says the same with a hint.
    let error = refused(system);
    assert!(error.contains("did you mean 'gnc'"), "{error}");
}
