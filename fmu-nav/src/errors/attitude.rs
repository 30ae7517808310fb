//! The attitude error: a small rotation `theta` (rad, body axes; bias + random walk + white
//! noise, as for the other groups) applied on the body side,
//!
//! ```text
//! q_body_to_nue_est = q_body_to_nue ⊗ exp(theta / 2)
//! ```
//! so the estimated body axes are the true ones rotated by `theta`. The product of a unit
//! quaternion with a unit rotation stays unit (to rounding); the input's norm is kept, and
//! nothing is renormalised, so a degenerate input passes through as degenerate as it came.
use lander_math::quaternion::{from_nalgebra, to_nalgebra};
use nalgebra::{Quaternion, Unit, UnitQuaternion, Vector3};

/// `q` (scalar first, Hamilton) with the body-axis rotation `theta_body_rad` applied; `q`
/// itself, bit for bit, when the rotation is exactly zero.
pub fn rotate_body(q: [f64; 4], theta_body_rad: [f64; 3]) -> [f64; 4] {
    if theta_body_rad.iter().all(|&a| a == 0.0) {
        return q;
    }
    let error = from_scaled_axis(Vector3::from(theta_body_rad));
    let rotated = to_nalgebra(&q) * error;
    from_nalgebra(&rotated)
}

/// The body-axis rotation (rad) that takes `truth` to `estimate` (unit quaternions, scalar
/// first), the inverse of [`rotate_body`]: for checking the error statistics.
pub fn body_error(truth: [f64; 4], estimate: [f64; 4]) -> [f64; 3] {
    let unit = |q: [f64; 4]| UnitQuaternion::from_quaternion(to_nalgebra(&q));
    let error = unit(truth).inverse() * unit(estimate);
    scaled_axis(&error).into()
}

/// `exp(theta / 2)`: nalgebra's `UnitQuaternion::from_scaled_axis`, step for step (the same
/// identity below machine epsilon), with libm's sine and cosine so that every platform gives
/// the same bits.
fn from_scaled_axis(theta: Vector3<f64>) -> Quaternion<f64> {
    let half = theta / 2.0;
    let nn = half.norm_squared();
    if nn <= f64::EPSILON * f64::EPSILON {
        return Quaternion::identity();
    }
    let n = nn.sqrt();
    let (s, c) = libm::sincos(n);
    Quaternion::from_parts(c, half * (s / n))
}

/// The rotation vector (axis times angle in [0, pi]) of a unit quaternion: nalgebra's
/// `scaled_axis`, step for step, with libm's atan2.
fn scaled_axis(q: &UnitQuaternion<f64>) -> Vector3<f64> {
    let v = if q.w >= 0.0 { q.imag() } else { -q.imag() };
    match Unit::try_new(v, 0.0) {
        Some(axis) => axis.into_inner() * (2.0 * libm::atan2(q.imag().norm(), q.w.abs())),
        None => Vector3::zeros(),
    }
}

#[cfg(test)]
// std's functions here are a reference independent of the libm the model uses.
#[allow(clippy::disallowed_methods)]
mod tests {
    use super::*;

    const TILTED: [f64; 4] = [0.9914448613738104, 0.0, 0.0, -0.13052619222005157];

    #[test]
    fn a_zero_rotation_returns_the_input_bit_for_bit() {
        for q in [TILTED, [-0.0, 0.0, 0.0, 0.0], [2.0, -0.0, 1e-300, 0.5]] {
            let out = rotate_body(q, [0.0, -0.0, 0.0]);
            assert_eq!(out.map(f64::to_bits), q.map(f64::to_bits));
        }
    }

    #[test]
    fn a_rotation_about_a_body_axis_composes_on_the_body_side() {
        // GIVEN the upright attitude and 0.1 rad about body y
        let q = rotate_body([1.0, 0.0, 0.0, 0.0], [0.0, 0.1, 0.0]);
        // THEN the result is the rotation of 0.1 rad about y, and the error reads back
        let expected = [(0.05f64).cos(), 0.0, (0.05f64).sin(), 0.0];
        for (a, b) in q.iter().zip(expected) {
            assert!((a - b).abs() < 1e-16, "{q:?}");
        }
        // AND on a tilted attitude the error is recovered in body axes
        let theta = [0.01, -0.02, 0.003];
        let back = body_error(TILTED, rotate_body(TILTED, theta));
        for (a, b) in back.iter().zip(theta) {
            assert!((a - b).abs() < 1e-15, "{back:?}");
        }
    }

    #[test]
    fn the_estimate_stays_unit() {
        let q = rotate_body(TILTED, [0.3, -1.0, 2.0]);
        let norm = q.iter().map(|c| c * c).sum::<f64>().sqrt();
        assert!((norm - 1.0).abs() < 4.0 * f64::EPSILON, "{norm}");
    }
}
