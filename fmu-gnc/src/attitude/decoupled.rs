//! The decoupled thrust-axis law (paper Sec. IV, the paper's contribution, ERRATA 5-7, 9).
use super::errors::{thrust_axis_errors, ThrustAxisErrors};
use super::gains::{pd_torque_body, AttitudeGains};
use crate::conventions::Attitude;
use nalgebra::Vector3;

/// Paper Sec. IV, decoupled law: lateral torques (body x, z) from the errors relative to
/// `q_refL = q_guid ⊗ q_phib`, thrust-axis torque (body y) from `wrap(phi_b - phi_cmd)`, one set
/// of angle gains, `omega_ref = 0`, gyroscopic feed-forward kept. Unsaturated.
pub fn decoupled_torque_body(
    gains: &AttitudeGains,
    q_body_to_nue: &Attitude,
    omega_body: &Vector3<f64>,
    q_guid: &Attitude,
    phi_cmd_rad: f64,
) -> (Vector3<f64>, ThrustAxisErrors) {
    let errors = thrust_axis_errors(q_body_to_nue, q_guid, phi_cmd_rad);
    let torque = pd_torque_body(gains, &errors.angle_error_body(), omega_body);
    (torque, errors)
}
