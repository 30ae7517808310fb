//! The paper's Section IV illustration: thrust axis 15 deg from vertical toward North, pitch
//! axis along East, guidance wants the thrust axis vertical.
// std's transcendental functions here are a reference independent of the libm the model uses.
#![allow(clippy::disallowed_methods)]
use crate::common;

use common::{paper_settings, RigidBody};
use fmu_gnc::attitude::{attitude_command, ControlLaw};
use lander_math::frames::{Body, Nue};
use nalgebra::{UnitQuaternion, Vector3};

const LIMIT_NM: f64 = 116.0;

fn tilted_north() -> RigidBody {
    // Rotating upright by -15 deg about East (body z) takes body y to [sin 15, cos 15, 0].
    let q = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), -15f64.to_radians());
    let body = RigidBody {
        q_body_to_nue: q,
        omega_body: Vector3::zeros(),
    };
    let t = body.thrust_axis_nue();
    assert!(t.x > 0.25 && t.z == 0.0, "thrust axis toward North: {t}");
    body
}

fn hover_up() -> Vector3<f64> {
    Vector3::new(0.0, 1.62, 0.0)
}

fn torque(law: ControlLaw, body: &RigidBody, phi_cmd_deg: f64) -> Vector3<f64> {
    attitude_command(
        &paper_settings(law),
        &body.q_body_to_nue,
        &Body(body.omega_body),
        &Nue(hover_up()),
        phi_cmd_deg.to_radians(),
    )
    .torque_body_nm
    .0
}

/// What the thrust axis did in a flight.
struct Flight {
    /// Thrust axis in NUE at the end.
    axis_nue: Vector3<f64>,
    /// East component of largest magnitude on the way (signed).
    east_extreme: f64,
    /// Largest tilt from vertical on the way, rad.
    tilt_max_rad: f64,
}

/// Fly `seconds` under `law` from the tilted start.
fn fly(law: ControlLaw, phi_cmd_deg: f64, seconds: f64) -> Flight {
    let mut body = tilted_north();
    let mut east_extreme: f64 = 0.0;
    let mut tilt_max_rad: f64 = 0.0;
    let dt = 0.01;
    for _ in 0..(seconds / dt).round() as usize {
        let tau = torque(law, &body, phi_cmd_deg);
        body.step(&tau, dt);
        let axis = body.thrust_axis_nue();
        if axis.z.abs() > east_extreme.abs() {
            east_extreme = axis.z;
        }
        tilt_max_rad = tilt_max_rad.max(axis.y.clamp(-1.0, 1.0).acos());
    }
    Flight {
        axis_nue: body.thrust_axis_nue(),
        east_extreme,
        tilt_max_rad,
    }
}

#[test]
fn case_1_phi_cmd_zero_both_laws_command_pure_pitch() {
    // GIVEN the tilted lander and phi_cmd = 0
    let body = tilted_north();
    for law in [ControlLaw::Coupled, ControlLaw::Decoupled] {
        // WHEN either law computes its torque
        let tau = torque(law, &body, 0.0);
        // THEN it is a pure pitch torque, in the sense that rights the thrust axis
        assert!(tau.x.abs() < 1e-9 && tau.y.abs() < 1e-9, "{law:?}: {tau}");
        assert!(tau.z > 0.5 * LIMIT_NM, "{law:?}: {tau}");
        // AND the thrust axis returns to vertical without leaving the North-Up plane
        let flight = fly(law, 0.0, 8.0);
        assert!(
            flight.east_extreme.abs() < 1e-12,
            "{law:?}: {}",
            flight.east_extreme
        );
        assert!(flight.axis_nue.y > 0.9999, "{law:?}: {}", flight.axis_nue);
        assert!(flight.tilt_max_rad <= 15f64.to_radians() + 1e-12);
    }
}

#[test]
fn case_2_phi_cmd_180_coupled_swings_sideways_decoupled_stays_in_plane() {
    // GIVEN the tilted lander and phi_cmd = 180 deg
    let body = tilted_north();
    // WHEN the coupled law computes its torque
    let coupled = torque(ControlLaw::Coupled, &body, 180.0);
    // THEN it has a large yaw (body x) component and no pitch: its eigen-axis is near roll
    assert!(coupled.x.abs() > 0.5 * LIMIT_NM, "coupled: {coupled}");
    assert!(coupled.z.abs() < 1e-9, "coupled: {coupled}");
    // WHEN the decoupled law computes its torque
    let decoupled = torque(ControlLaw::Decoupled, &body, 180.0);
    // THEN its lateral part is pure pitch, righting the thrust axis, plus a roll torque
    assert!(decoupled.x.abs() < 1e-9, "decoupled: {decoupled}");
    assert!(decoupled.z > 0.5 * LIMIT_NM, "decoupled: {decoupled}");
    assert!(decoupled.y.abs() > 0.5 * LIMIT_NM, "decoupled: {decoupled}");

    // AND in flight the coupled thrust axis swings far out of the North-Up plane and tilts
    // further than it started, before coming back (measured: ~19 deg East-West, ~20 deg tilt)
    let coupled = fly(ControlLaw::Coupled, 180.0, 10.0);
    assert!(
        coupled.east_extreme.abs() > 0.2,
        "coupled East-West {}",
        coupled.east_extreme
    );
    assert!(
        coupled.tilt_max_rad > 16f64.to_radians(),
        "coupled tilt {}",
        coupled.tilt_max_rad
    );
    // WHILE the decoupled one goes back toward vertical: it never tilts further, and its
    // East-West excursion is an order of magnitude smaller (~0.8 deg: while the body rolls,
    // the pitch rate it already has turns with it; the law then corrects that)
    let decoupled = fly(ControlLaw::Decoupled, 180.0, 10.0);
    assert!(decoupled.tilt_max_rad <= 15f64.to_radians() + 1e-9);
    assert!(decoupled.east_extreme.abs() < 0.1 * coupled.east_extreme.abs());
    assert!(
        decoupled.east_extreme.abs() < 0.02,
        "decoupled {}",
        decoupled.east_extreme
    );
    // AND both end upright
    assert!(coupled.axis_nue.y > 0.9999 && decoupled.axis_nue.y > 0.9999);
    // AND in the first 0.2 s, the decoupled thrust axis stays in the plane to 1e-4
    let start = fly(ControlLaw::Decoupled, 180.0, 0.2);
    assert!(start.east_extreme.abs() < 1e-4, "{}", start.east_extreme);
}

#[test]
fn the_sideways_swing_of_the_coupled_law_follows_the_short_way() {
    // 179 deg and 181 deg are the same mission demand to within 2 deg, but the coupled law's
    // short way goes round opposite sides: the thrust axis swings West for one, East for the
    // other (the paper's figure shows East under its own conventions). Exactly 180 deg is the
    // tie; cos(pi/2) = 6e-17 > 0 resolves it like 179 deg.
    let west = fly(ControlLaw::Coupled, 179.0, 1.0).east_extreme;
    let east = fly(ControlLaw::Coupled, 181.0, 1.0).east_extreme;
    let tie = fly(ControlLaw::Coupled, 180.0, 1.0).east_extreme;
    assert!(west < -0.1, "179 deg: {west}");
    assert!(east > 0.1, "181 deg: {east}");
    assert!(tie < -0.1, "180 deg: {tie}");
    // The decoupled law's first second stays near the plane whichever side the roll goes
    for phi in [179.0, 181.0] {
        let e = fly(ControlLaw::Decoupled, phi, 1.0).east_extreme;
        assert!(e.abs() < 0.01, "decoupled {phi} deg: {e}");
    }
}
