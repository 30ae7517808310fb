//! The conventions of the plant, stated once (they match `docs/interface.md` and fmu-gnc).
//!
//! * **NUE**: the local frame of the landing site, axis 1 North, axis 2 Up, axis 3 East,
//!   origin at the landing site on the surface. It is fixed to the Moon.
//! * **Body**: axis 1 = yaw (x), axis 2 = roll (y) = the thrust axis, axis 3 = pitch (z).
//!   The main engine pushes along +y body.
//! * **Attitude**: a Hamilton quaternion, *scalar first* in every public array,
//!   `q_body_to_nue = [q0, q1, q2, q3]`, rotating body vectors into NUE:
//!   `v_nue = q ⊗ v_body ⊗ q*`. Identity = upright (body x North, y Up, z East).
//! * **Kinematics**: `q' = ½ q ⊗ [0, omega_body]`, `omega_body` in body axes.
//!
//! A scalar-first array meets a nalgebra quaternion (which stores w last) only through
//! `lander_math::quaternion::{to_nalgebra, from_nalgebra}`, shared with the other FMUs.
pub use lander_math::frames::{Body, Nue};
use nalgebra::{Quaternion, UnitQuaternion, Vector3};

/// Thrust axis in body coordinates.
pub fn thrust_axis_body() -> Body {
    Body(Vector3::y())
}

/// Local vertical (Up) in NUE coordinates.
pub fn up_nue() -> Nue {
    Nue(Vector3::y())
}

/// The plant's outputs as a scalar-first array (the shared bridge, under the name the speed
/// bench uses).
pub use lander_math::quaternion::from_nalgebra as quaternion_to_scalar_first;

/// Rotates a body vector into NUE with the attitude `q_body_to_nue` (unit or not: the
/// rotation of the normalised quaternion is used).
#[inline]
pub fn body_to_nue(q_body_to_nue: &Quaternion<f64>, v_body: &Body) -> Nue {
    Nue(UnitQuaternion::from_quaternion(*q_body_to_nue) * v_body.0)
}

/// Angle between the thrust axis and the local vertical, in [0, pi] rad.
pub fn tilt_from_vertical(q_body_to_nue: &Quaternion<f64>) -> f64 {
    let thrust_nue = body_to_nue(q_body_to_nue, &thrust_axis_body());
    libm::acos(thrust_nue.dot(&up_nue()).clamp(-1.0, 1.0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use lander_math::quaternion::to_nalgebra;
    use std::f64::consts::FRAC_PI_2;

    #[test]
    fn positive_rotation_about_pitch_tips_the_thrust_axis_from_up_towards_north() {
        // GIVEN a +90 deg rotation about body z (pitch, = East when upright), scalar first
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let q = to_nalgebra(&[h, 0.0, 0.0, h]);
        // WHEN the thrust axis (body +y) is rotated into NUE
        let t = body_to_nue(&q, &thrust_axis_body());
        // THEN z x y = -x: the thrust axis points South (-North), a right-handed rotation.
        assert!((t - Nue::new(-1.0, 0.0, 0.0)).0.norm() < 1e-15);
        assert!((tilt_from_vertical(&q) - FRAC_PI_2).abs() < 1e-15);
    }

    #[test]
    fn body_to_nue_matches_the_explicit_sandwich_product() {
        let q = to_nalgebra(&[0.9, 0.1, -0.3, 0.2]).normalize();
        let v = Vector3::new(0.3, -1.2, 2.0);
        let sandwich = q * Quaternion::from_imag(v) * q.conjugate();
        assert!((body_to_nue(&q, &Body(v)).0 - sandwich.imag()).norm() < 1e-14);
    }
}
