//! The faults a scenario throws mid-flight (docs/plant-actuators.md, "Faults"), set through
//! the C API after initialization as a master's event sets them: each does what it says.
use crate::common::Plant;
use fmi_testkit::fmi2::*;

const G: f64 = 1.62;

/// A plant that keeps its mass (isp huge), initialized, with the RCS model given.
fn plant(rcs_model: i32) -> Plant {
    let fmu = Plant::new();
    fmu.enter_init();
    fmu.set("isp", 1e15);
    fmu.set_integer("rcs_model", rcs_model);
    assert_eq!(fmu.exit_init(), fmi2OK, "{:?}", fmu.messages());
    fmu
}

fn steps(fmu: &Plant, from: usize, to: usize, h: f64) {
    for k in from..to {
        assert_eq!(fmu.step(k as f64 * h, h), fmi2OK, "{:?}", fmu.messages());
    }
}

#[test]
fn an_engine_health_set_mid_flight_scales_the_delivered_thrust_from_then_on() {
    // GIVEN 1400 N commanded for 1 s: all of it delivered
    let fmu = plant(1);
    fmu.set("thrust_cmd", 1400.0);
    steps(&fmu, 0, 100, 0.01);
    assert_eq!(fmu.get("thrust_actual"), 1400.0);
    let v0 = fmu.get("v_nue[2]");
    // WHEN one of two engines is lost (health 0.5) at t = 1 s
    fmu.set("engine_health", 0.5);
    // THEN 700 N is delivered, below the two-engine minimum of 720 N the command still gets
    assert_eq!(fmu.get("thrust_actual"), 700.0);
    steps(&fmu, 100, 200, 0.01);
    assert_eq!(fmu.get("thrust_actual"), 700.0);
    // AND the vertical acceleration over the next second is 700 / 900 - g
    let dv = fmu.get("v_nue[2]") - v0;
    assert!((dv - (700.0 / 900.0 - G)).abs() < 1e-9, "{dv}");
    // AND the minimum command is halved as well: one engine at its own minimum
    fmu.set("thrust_cmd", 720.0);
    assert_eq!(fmu.get("thrust_actual"), 360.0);
}

#[test]
fn a_thruster_stuck_off_gives_no_force_while_commanded() {
    // GIVEN the thruster model, thruster 1 (+y force at x = 1 m: +58 N m about z) commanded
    let fmu = plant(2);
    fmu.set("rcs_duty[1]", 1.0);
    assert_eq!(fmu.get("rcs_force_body[2]"), 58.0);
    // WHEN its valve sticks closed
    fmu.set_integer("rcs_stuck_thruster", 1);
    fmu.set_integer("rcs_stuck_mode", 1);
    // THEN it gives no force and no torque, commanded over a whole second
    assert_eq!(fmu.get("rcs_force_body[2]"), 0.0);
    steps(&fmu, 0, 100, 0.01);
    assert_eq!(fmu.get("omega_body[3]"), 0.0);
    assert_eq!(fmu.get("torque_actual_body[3]"), 0.0);
}

#[test]
fn a_thruster_stuck_on_gives_full_force_while_not_commanded() {
    // GIVEN the thruster model, no thruster commanded
    let fmu = plant(2);
    let izz = fmu.get("inertia_body[3]");
    // WHEN thruster 2 (-y force at x = -1 m: +58 N m about z) sticks open
    fmu.set_integer("rcs_stuck_thruster", 2);
    fmu.set_integer("rcs_stuck_mode", 2);
    // THEN it pushes with its full 58 N, and spins the lander up about z at 58 / Izz
    assert_eq!(fmu.get("rcs_force_body[2]"), -58.0);
    steps(&fmu, 0, 100, 0.01);
    let omega = fmu.get("omega_body[3]");
    assert!(
        (omega - 58.0 / izz).abs() < 1e-12,
        "{omega} vs {}",
        58.0 / izz
    );
    // AND mended (thruster 0: none), it stops pushing
    fmu.set_integer("rcs_stuck_thruster", 0);
    steps(&fmu, 100, 200, 0.01);
    assert!((fmu.get("omega_body[3]") - omega).abs() < 1e-12);
}

#[test]
fn a_stuck_thruster_in_the_torque_model_is_refused_naming_the_model() {
    let fmu = plant(1);
    fmu.set_integer("rcs_stuck_thruster", 3);
    assert_eq!(fmu.step(0.0, 0.01), fmi2Error);
    let messages = fmu.messages().join("\n");
    assert!(
        messages.contains("rcs_stuck_thruster = 3") && messages.contains("rcs_model = 2"),
        "{messages}"
    );
}

#[test]
fn an_engine_health_outside_0_1_is_refused() {
    let fmu = plant(1);
    assert_eq!(
        fmu.set_real(crate::common::vr("engine_health"), 1.5),
        fmi2Error
    );
}
