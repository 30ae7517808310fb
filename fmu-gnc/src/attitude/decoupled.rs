//! The decoupled thrust-axis law (paper Sec. IV, the paper's contribution, ERRATA 5-7, 9).
use super::errors::ThrustAxisErrors;
use super::gains::{pd_torque_body, AttitudeGains};
use super::profile::RollReference;
use lander_math::frames::Body;

/// Paper Sec. IV, decoupled law: lateral torques (body x, z) from the errors relative to
/// `q_refL = q_guid ⊗ q_phib`, thrust-axis torque (body y) from `wrap(phi_b - phi_cmd)`, one set
/// of angle gains, `omega_ref = 0` (but for a shaped manoeuvre), gyroscopic feed-forward kept.
/// Unsaturated. The errors are [`thrust_axis_errors`](super::errors::thrust_axis_errors) of the
/// sample, computed once for the law and the diagnostics.
#[inline(always)]
pub fn decoupled_torque_body(
    gains: &AttitudeGains,
    errors: &ThrustAxisErrors,
    omega_body: &Body,
    reference: &RollReference,
) -> Body {
    pd_torque_body(gains, &errors.angle_error_body(), omega_body, reference)
}

/// The law as [`ControlLaw`](super::ControlLaw) runs it.
#[inline(always)]
pub fn torque(inputs: &super::LawInputs) -> (Body, Body) {
    (
        decoupled_torque_body(
            &inputs.settings.gains,
            inputs.split,
            inputs.omega_body,
            inputs.roll,
        ),
        inputs.split.angle_error_body(),
    )
}
