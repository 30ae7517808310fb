//! The thrust-axis split of the attitude error (paper Sec. IV control errors, ERRATA 5, 7, 9):
//! one pure function, consumed by the decoupled law and by every law's diagnostics.
use super::phi_b::phi_b;
use super::reference::q_phi;
use crate::conventions::{angle_between, canonical, thrust_axis_body, wrap_angle, Attitude};
use lander_math::frames::Body;
use nalgebra::Vector3;

/// Control errors about the body axes, all angles in rad (ERRATA 9).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ThrustAxisErrors {
    /// Rotation about the thrust axis (body y): `wrap(phi_b - phi_cmd)` in (-pi, pi].
    pub roll_rad: f64,
    /// Lateral error about body x: `2 q_ex` of `q_refL^-1 ⊗ q`.
    pub yaw_rad: f64,
    /// Lateral error about body z: `2 q_ez` of `q_refL^-1 ⊗ q`.
    pub pitch_rad: f64,
    /// Angle between the body thrust axis and the guidance direction, in [0, pi].
    pub tilt_rad: f64,
    /// The achieved 1-3-2 rotation about the thrust axis.
    pub phi_b_rad: f64,
}

impl ThrustAxisErrors {
    /// The three errors as a body-axis vector `[yaw (x), roll (y), pitch (z)]`.
    pub fn angle_error_body(&self) -> Body {
        Body::new(self.yaw_rad, self.roll_rad, self.pitch_rad)
    }
}

/// Angle between the body thrust axis and the thrust direction of the guidance attitude
/// `q_guid`; unchanged by any rotation of `q` about the thrust axis.
#[inline(always)]
pub fn tilt_angle(q_body_to_nue: &Attitude, q_guid: &Attitude) -> f64 {
    angle_between(
        &(q_body_to_nue * thrust_axis_body()),
        &(q_guid * thrust_axis_body()),
    )
}

/// Paper Sec. IV, decoupled errors: `q_refL = q_guid ⊗ q_phib` (ERRATA 6 for `q_phib`),
/// `q_e = q_refL^-1 ⊗ q` taken the short way (`q_e0 >= 0`), yaw and pitch errors
/// `2 q_ex`, `2 q_ez`, roll error `wrap(phi_b - phi_cmd)` (ERRATA 5, 9).
///
/// Because `q_refL` carries the attitude's own 1-3-2 angle about the thrust axis, `q_e` has no
/// share of the roll command: the lateral errors only move the thrust axis toward guidance
/// and are exactly zero when it is on target, whatever the roll (ERRATA 7).
#[inline(always)]
pub fn thrust_axis_errors(
    q_body_to_nue: &Attitude,
    q_guid: &Attitude,
    phi_cmd_rad: f64,
) -> ThrustAxisErrors {
    thrust_axis_errors_toward(
        q_body_to_nue,
        q_guid,
        &(q_guid * thrust_axis_body()),
        phi_cmd_rad,
    )
}

/// [`thrust_axis_errors`] with the guidance thrust direction `q_guid t` (NUE) given, as a
/// caller that keeps it between samples has it.
#[inline(always)]
pub fn thrust_axis_errors_toward(
    q_body_to_nue: &Attitude,
    q_guid: &Attitude,
    guidance_thrust_axis_nue: &Vector3<f64>,
    phi_cmd_rad: f64,
) -> ThrustAxisErrors {
    let phi_b_rad = phi_b(q_body_to_nue);
    let q_ref_lateral = q_guid * q_phi(phi_b_rad);
    let q_e = canonical(&(q_ref_lateral.inverse() * q_body_to_nue));
    ThrustAxisErrors {
        roll_rad: wrap_angle(phi_b_rad - phi_cmd_rad),
        yaw_rad: 2.0 * q_e.i,
        pitch_rad: 2.0 * q_e.k,
        tilt_rad: angle_between(&thrust_axis_nue(q_body_to_nue), guidance_thrust_axis_nue),
        phi_b_rad,
    }
}

/// Body +y rotated into NUE by `q`: `q * thrust_axis_body()` as nalgebra computes it
/// (`t = 2 u x y`, then `t w + u x t + y`), without the products by the zero and unit
/// components of `y`: `t = (-2 z, 0, 2 x)` exactly, and each remaining term is the same
/// rounded product or sum. Only the sign of a zero component can differ, which an angle
/// between unit vectors never sees (the norm of their cross product squares it, and
/// their dot product is a zero of either sign only when that norm is 1).
#[inline(always)]
pub fn thrust_axis_nue(q: &Attitude) -> Vector3<f64> {
    let (w, x, y, z) = (q.w, q.i, q.j, q.k);
    let (t0, t2) = (-z * 2.0, x * 2.0);
    Vector3::new(t0 * w + y * t2, (z * t0 - x * t2) + 1.0, t2 * w + -(y * t0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Quaternion, UnitQuaternion};

    #[test]
    fn the_thrust_axis_is_nalgebras_rotation_of_body_y_to_the_sign_of_a_zero() {
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        let mut attitudes = vec![
            UnitQuaternion::identity(),
            UnitQuaternion::new_unchecked(Quaternion::new(0.0, 0.0, 0.0, 1.0)),
            UnitQuaternion::new_unchecked(Quaternion::new(-0.0, 1.0, -0.0, 0.0)),
        ];
        for k in 0..50_000 {
            let mut q = [next(), next(), next(), next()];
            if k % 5 == 0 {
                q[k % 4] = 0.0;
            }
            if k % 7 == 0 {
                q[(k + 1) % 4] = -0.0;
            }
            let raw = Quaternion::new(q[0], q[1], q[2], q[3]);
            attitudes.push(UnitQuaternion::new_unchecked(raw / raw.norm()));
        }
        let mut directions = vec![
            Vector3::y(),
            -Vector3::y(),
            Vector3::x(),
            Vector3::new(0.0, -0.0, 1.0),
        ];
        for _ in 0..8 {
            directions.push(Vector3::new(next(), next(), next()).normalize());
        }
        for q in attitudes {
            let full = q * thrust_axis_body();
            let ours = thrust_axis_nue(&q);
            // == equates the zeros of either sign, and nothing else
            assert_eq!(ours, full, "{q:?}");
            for b in &directions {
                assert_eq!(
                    angle_between(&ours, b).to_bits(),
                    angle_between(&full, b).to_bits(),
                    "{q:?} {b:?}"
                );
            }
        }
    }
}
