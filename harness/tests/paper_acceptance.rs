//! Acceptance: the paper's claim, flown through the C ABI of the packaged FMUs.
//!
//! Thresholds come from the physics, not from the measured values:
//! - Decoupled law, paper scenario. The only lateral disturbance is the initial 15 deg tilt,
//!   which the attitude loop (omega_c = 2 pi 0.5 rad/s, zeta = 0.8) removes within about
//!   2 zeta / omega_c ~ 0.5 s, with the roll manoeuvre kept off the lateral axes. Over that
//!   time the thrust's horizontal component (g tan 15 deg = 0.43 m/s^2) builds at most
//!   ~0.4 m/s, which the hover guidance (omega_g = 2 pi 0.06 rad/s) turns into a peak excursion
//!   of order v / omega_g ~ 1 m. We allow 5 m.
//! - Coupled law: the shortest-path error quaternion swings the thrust axis sideways by an angle
//!   comparable to the tilt itself while the 150 deg roll is under way, for seconds, and the
//!   long-horizon descent guidance then carries that velocity error over the 130 s descent. We
//!   require at least 10x the decoupled deviation: an order of magnitude, the paper's claim.
//! - From an upright start (or with phi_cmd = 0 from the tilted start) the roll demand never
//!   produces a lateral error in either law (a pure roll, resp. a pure pitch manoeuvre), so the
//!   positions must agree to rounding; in practice they are bit-identical.
use crate::common;

use cosim::supervise::Runner;
use cosim::system::ParamValue;
use lander::laws::{Law, Laws};
use lander::paper::{fly, Flight};
use lander::scenarios;

fn simulation(scenario: &str, phi_cmd_deg: Option<f64>) -> Runner {
    let mut system = scenarios::load(scenario).unwrap();
    if let Some(deg) = phi_cmd_deg {
        system.set_parameter("gnc", "phi_cmd", ParamValue::Real(deg.to_radians()));
    }
    Runner::new(system, &common::fmu_dir()).unwrap()
}

fn max_position_difference(a: &Flight, b: &Flight) -> f64 {
    assert_eq!(a.trajectory.len(), b.trajectory.len());
    (1..=3)
        .map(|i| {
            let name = format!("plant.r_nue[{i}]");
            let (x, y) = (
                a.trajectory.column(&name).unwrap(),
                b.trajectory.column(&name).unwrap(),
            );
            x.iter()
                .zip(&y)
                .map(|(p, q)| (p - q).abs())
                .fold(0.0, f64::max)
        })
        .fold(0.0, f64::max)
}

fn wrap(angle: f64) -> f64 {
    let wrapped = angle.rem_euclid(std::f64::consts::TAU);
    if wrapped > std::f64::consts::PI {
        wrapped - std::f64::consts::TAU
    } else {
        wrapped
    }
}

#[test]
fn paper_scenario_coupled_law_drifts_off_the_vertical_decoupled_does_not() {
    // GIVEN the paper scenario: tilted start, phi_cmd = 150 deg at t = 0
    let mut sim = simulation("paper", None);
    // WHEN each law flies it
    let coupled = fly(&mut sim, Law::COUPLED).unwrap();
    let decoupled = fly(&mut sim, Law::DECOUPLED).unwrap();
    let (c, d) = (&coupled.metrics, &decoupled.metrics);
    println!(
        "max horizontal deviation: coupled {:.3} m, decoupled {:.3} m",
        c.max_horizontal_deviation_m, d.max_horizontal_deviation_m
    );
    // THEN the decoupled law stays on the vertical, the coupled one drifts an order of magnitude more
    assert!(d.max_horizontal_deviation_m < 5.0, "decoupled {d:?}");
    assert!(
        c.max_horizontal_deviation_m > 10.0 * d.max_horizontal_deviation_m,
        "coupled {c:?} vs decoupled {d:?}"
    );
    // AND both still finish the mission: hovering at 150 m, rolled to phi_cmd
    for m in [c, d] {
        assert!(m.terminal_position_error_m < 1.0, "{m:?}");
        assert!(m.terminal_velocity_error_mps < 0.1, "{m:?}");
        assert!(
            wrap(m.final_phi_b_rad - 150f64.to_radians()).abs() < 1e-3,
            "{m:?}"
        );
    }
}

#[test]
fn with_no_roll_demand_the_laws_fly_the_same_trajectory() {
    // GIVEN the tilted start and phi_cmd = 0: re-erecting the thrust axis is a pure pitch
    let mut sim = simulation("paper", Some(0.0));
    let coupled = fly(&mut sim, Law::COUPLED).unwrap();
    let decoupled = fly(&mut sim, Law::DECOUPLED).unwrap();
    // THEN the positions agree to rounding
    let difference = max_position_difference(&coupled, &decoupled);
    assert!(difference < 1e-9, "max position difference {difference} m");
}

#[test]
fn from_an_upright_start_the_laws_agree_for_every_roll_demand() {
    for phi_cmd_deg in [0.0, 30.0, 90.0, 150.0, 180.0] {
        // GIVEN an upright start and phi_cmd applied at the start of the descent
        let mut sim = simulation("upright", Some(phi_cmd_deg));
        let coupled = fly(&mut sim, Law::COUPLED).unwrap();
        let decoupled = fly(&mut sim, Law::DECOUPLED).unwrap();
        // THEN the trajectories agree to rounding (the roll is about the thrust axis only)
        let difference = max_position_difference(&coupled, &decoupled);
        assert!(difference < 1e-9, "phi_cmd {phi_cmd_deg}: {difference} m");
        // AND both end rolled to phi_cmd
        for flight in [&coupled, &decoupled] {
            let error = wrap(flight.metrics.final_phi_b_rad - phi_cmd_deg.to_radians());
            assert!(
                error.abs() < 1e-3,
                "phi_cmd {phi_cmd_deg}, {:?}: final phi_b error {error} rad",
                flight.law
            );
        }
    }
}

#[test]
fn braking_limited_shaping_keeps_a_dispersed_start_near_the_vertical() {
    // GIVEN the tilted start 1 m North of the target vertical, no roll demand. With the paper's
    // pure PD the saturated RCS (116 N m against ~1,100 N m asked) overshoots the tilt and the
    // descent starts with metres per second of drift (~50 m excursion). With the rate demand
    // shaped so it can be braked in time, the attitude follows guidance without overshoot and
    // the excursion stays of the order of the offset itself: we allow 5 m.
    let mut system = scenarios::load("paper").unwrap();
    system.set_parameter("gnc", "phi_cmd", ParamValue::Real(0.0));
    system.set_parameter("plant", "r0_nue[1]", ParamValue::Real(1.0));
    system.set_parameter("gnc", "rate_shaping_margin", ParamValue::Real(0.5));
    let mut sim = Runner::new(system.clone(), &common::fmu_dir()).unwrap();
    for law in Laws::of_runner(&sim, "gnc").unwrap().all() {
        let flight = fly(&mut sim, law).unwrap();
        assert!(
            flight.metrics.max_horizontal_deviation_m < 5.0,
            "{law:?}: {:?}",
            flight.metrics
        );
    }
    // AND without the shaping (the paper's law, the default) the same start drifts far more,
    // so the test above measures the shaping, not an easy case
    system.set_parameter("gnc", "rate_shaping_margin", ParamValue::Real(0.0));
    let mut paper_law = Runner::new(system, &common::fmu_dir()).unwrap();
    let flight = fly(&mut paper_law, Law::DECOUPLED).unwrap();
    assert!(
        flight.metrics.max_horizontal_deviation_m > 20.0,
        "{:?}",
        flight.metrics
    );
}
