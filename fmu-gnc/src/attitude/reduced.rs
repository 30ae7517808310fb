//! Reduced-attitude law (beyond the paper, for comparison): Brescianini, Hehn, D'Andrea,
//! "Nonlinear quadrocopter attitude control", ETH Zurich 2013, as in PX4's AttitudeControl.
//!
//! The thrust axis is brought onto its target by the shortest tilt first; the rotation about
//! the thrust axis is then added only as far as the weight `w` in [0, 1] allows: the target is
//! `q_red ⊗ q_y(w alpha)`, with `q_red` the current attitude tilted the short way onto the
//! reference thrust axis and `alpha` the remaining rotation about it. `w = 1` is the full
//! (coupled) attitude law, `w = 0` controls the thrust axis only.
use super::coupled::coupled_angle_error_body;
use super::gains::{pd_torque_body, AttitudeGains};
use super::profile::RollReference;
use crate::conventions::{
    canonical, rotation_about, rotation_about_thrust_axis, thrust_axis_body, Attitude,
};
use lander_math::frames::Body;
use nalgebra::{Unit, UnitQuaternion};

/// Beyond this tilt between current and reference thrust axes (rad) the shortest tilt has no
/// well-defined axis; the law then falls back to the full reference attitude, whose error
/// quaternion is well defined there (as PX4 does).
const ANTIPODAL_TILT_RAD: f64 = std::f64::consts::PI - 1e-4;

/// The weighted reduced target attitude for current attitude `q` and full reference `q_ref`.
pub fn reduced_reference(q_body_to_nue: &Attitude, q_ref: &Attitude, weight: f64) -> Attitude {
    let thrust_now_nue = q_body_to_nue * thrust_axis_body();
    let thrust_ref_nue = q_ref * thrust_axis_body();
    let axis = thrust_now_nue.cross(&thrust_ref_nue);
    let tilt_rad = libm::atan2(axis.norm(), thrust_now_nue.dot(&thrust_ref_nue));
    if tilt_rad > ANTIPODAL_TILT_RAD {
        return *q_ref;
    }
    // The tilt is a rotation in NUE applied to the current attitude (left product).
    let tilt_nue = match Unit::try_new(axis, 0.0) {
        Some(axis) => rotation_about(&axis, tilt_rad),
        None => UnitQuaternion::identity(),
    };
    let q_tilted = tilt_nue * q_body_to_nue;
    // What remains between the tilted attitude and the reference is a rotation about body y.
    let remaining = canonical(&(q_tilted.inverse() * q_ref));
    let alpha_rad = 2.0 * libm::atan2(remaining.j, remaining.w);
    q_tilted * rotation_about_thrust_axis(weight.clamp(0.0, 1.0) * alpha_rad)
}

/// Reduced-attitude PD torque (unsaturated) and the angle error it acted on.
pub fn reduced_torque_body(
    gains: &AttitudeGains,
    q_body_to_nue: &Attitude,
    omega_body: &Body,
    q_ref: &Attitude,
    weight: f64,
    reference: &RollReference,
) -> (Body, Body) {
    let target = reduced_reference(q_body_to_nue, q_ref, weight);
    let error = coupled_angle_error_body(q_body_to_nue, &target);
    (pd_torque_body(gains, &error, omega_body, reference), error)
}

/// The law as [`ControlLaw`](super::ControlLaw) runs it.
#[inline(always)]
pub fn torque(inputs: &super::LawInputs) -> (Body, Body) {
    reduced_torque_body(
        &inputs.settings.gains,
        inputs.q_body_to_nue,
        inputs.omega_body,
        inputs.q_ref,
        inputs.settings.reduced_yaw_weight,
        inputs.roll,
    )
}
