//! The classical (coupled) quaternion PD law (paper Sec. IV, q_e and tau_cmd).
use super::gains::{pd_torque_body, AttitudeGains};
use super::profile::RollReference;
use crate::conventions::{canonical, Attitude};
use lander_math::frames::Body;

/// Paper Sec. IV, `q_e = q_ref^-1 ⊗ q` (ERRATA 4: this is the body-frame error; the printed
/// expansion with `+ q_refv x q_v` is the local-frame `q ⊗ q_ref^-1`) as an angle error
/// `2 q_ev` in body axes (ERRATA 9).
///
/// The short way is chosen here, on the error and not on the inputs: `q_e` is replaced by
/// `-q_e` when `q_e0 < 0`, so the commanded rotation is at most pi and the law gives the same
/// torque for `q` and `-q` (no unwinding).
pub fn coupled_angle_error_body(q_body_to_nue: &Attitude, q_ref: &Attitude) -> Body {
    let q_e = canonical(&(q_ref.inverse() * q_body_to_nue));
    Body(q_e.imag() * 2.0)
}

/// Paper Sec. IV, `tau = -Kp 2 q_ev - Kd (omega - omega_ref) + omega x I omega` (unsaturated;
/// `omega_ref = 0` but for a shaped manoeuvre), and the angle error it acted on.
pub fn coupled_torque_body(
    gains: &AttitudeGains,
    q_body_to_nue: &Attitude,
    omega_body: &Body,
    q_ref: &Attitude,
    reference: &RollReference,
) -> (Body, Body) {
    let error = coupled_angle_error_body(q_body_to_nue, q_ref);
    (pd_torque_body(gains, &error, omega_body, reference), error)
}

/// The law as [`ControlLaw`](super::ControlLaw) runs it.
#[inline(always)]
pub fn torque(inputs: &super::LawInputs) -> (Body, Body) {
    coupled_torque_body(
        &inputs.settings.gains,
        inputs.q_body_to_nue,
        inputs.omega_body,
        inputs.q_ref,
        inputs.roll,
    )
}
