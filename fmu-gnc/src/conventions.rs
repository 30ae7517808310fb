//! Frames, axes and the attitude quaternion: the one place where conventions are stated.
//!
//! * **NUE** local frame: axis 1 North, axis 2 Up, axis 3 East. Gravity is `[0, -g, 0]`.
//! * **Body** axes: 1 = yaw (x), 2 = roll (y) = the thrust axis, 3 = pitch (z). The engines
//!   push along body +y.
//! * **Attitude** `q_body_to_nue`: Hamilton product, scalar first in every public interface
//!   (`[q0, q1, q2, q3]`, `q0` scalar). It rotates body vectors into NUE,
//!   `v_nue = q ⊗ v_body ⊗ q*`; identity = upright (body x North, y Up, z East).
//! * The paper's direction cosine matrix `A` maps NUE components to body components (a frame
//!   rotation): `A = R(q)^T`, where `R(q)` is the active rotation matrix of `q`.
//! * Kinematics: `q' = ½ q ⊗ [0, omega_body]` (ERRATA 3), rates in body axes.
//!
//! Internally the crate uses nalgebra's [`UnitQuaternion`], which stores the scalar **last**
//! (`coords = [i, j, k, w]`) while its constructor `Quaternion::new(w, i, j, k)` takes it first.
//! Conversions to and from the scalar-first arrays happen only through the functions below,
//! on `lander_math::quaternion`'s bridge, shared with the other FMUs.
use nalgebra::{Matrix3, Quaternion, Unit, UnitQuaternion, Vector3};

/// The attitude type used throughout: body-to-NUE rotation.
pub type Attitude = UnitQuaternion<f64>;

/// The thrust axis in body coordinates (paper Sec. III, t_hat = [0, 1, 0]^T).
pub fn thrust_axis_body() -> Vector3<f64> {
    Vector3::y()
}

/// Below this norm an input quaternion carries no attitude (e.g. masters that zero every
/// input before the first exchange); the controller then commands safe outputs.
pub const MIN_QUATERNION_NORM: f64 = 1e-6;

/// Scalar-first components `[q0, q1, q2, q3]` to a unit quaternion, normalising.
/// `None` if the norm is below [`MIN_QUATERNION_NORM`] (no direction to normalise to).
pub fn attitude_from_scalar_first(q: [f64; 4]) -> Option<Attitude> {
    let raw = lander_math::quaternion::to_nalgebra(&q);
    let norm = raw.norm();
    if norm.is_finite() && norm >= MIN_QUATERNION_NORM {
        Some(UnitQuaternion::new_unchecked(raw / norm))
    } else {
        None
    }
}

/// A unit quaternion to scalar-first components `[q0, q1, q2, q3]`.
pub fn attitude_to_scalar_first(q: &Attitude) -> [f64; 4] {
    lander_math::quaternion::from_nalgebra(q)
}

/// `q` or `-q`, whichever has a non-negative scalar part: the same rotation, and the short
/// way (rotation angle in [0, pi]) when `q` is an error quaternion.
pub fn canonical(q: &Attitude) -> Attitude {
    if q.w < 0.0 {
        UnitQuaternion::new_unchecked(-q.into_inner())
    } else {
        *q
    }
}

/// The paper's DCM `A` (NUE to body, a frame rotation) of an attitude: `A = R(q)^T`.
pub fn dcm_nue_to_body(q_body_to_nue: &Attitude) -> Matrix3<f64> {
    q_body_to_nue.to_rotation_matrix().into_inner().transpose()
}

/// A rotation by `angle_rad` about the body y (thrust) axis, as an attitude quaternion
/// `[cos(angle/2), 0, sin(angle/2), 0]`.
pub fn rotation_about_thrust_axis(angle_rad: f64) -> Attitude {
    let (s, c) = libm::sincos(0.5 * angle_rad);
    UnitQuaternion::new_unchecked(Quaternion::new(c, 0.0, s, 0.0))
}

/// A rotation by `angle_rad` about unit axis `axis`, as an attitude quaternion
/// `[cos(angle/2), sin(angle/2) axis]`: nalgebra's `from_axis_angle` through libm, so that
/// every platform computes the same bits.
pub fn rotation_about(axis: &Unit<Vector3<f64>>, angle_rad: f64) -> Attitude {
    let (s, c) = libm::sincos(0.5 * angle_rad);
    UnitQuaternion::new_unchecked(Quaternion::from_parts(c, axis.into_inner() * s))
}

/// The rotation angle of `q` about unit axis `axis` from its swing-twist split, in (-pi, pi].
pub fn twist_angle(q: &Attitude, axis: &Unit<Vector3<f64>>) -> f64 {
    let projection = q.imag().dot(axis);
    wrap_angle(2.0 * libm::atan2(projection, q.w))
}

/// `x.round()` (half away from zero) inline, bit for bit: below 2^52 in magnitude `x`
/// truncates exactly through an i64 and its fraction is exact, a zero result takes the sign
/// of `x`; from there on (infinities and NaN too) every value is its own.
#[inline(always)]
fn round(x: f64) -> f64 {
    const INTEGRAL_FROM: f64 = 4_503_599_627_370_496.0;
    if x.abs() < INTEGRAL_FROM {
        let truncated = x as i64 as f64;
        let fraction = x - truncated;
        let rounded = if fraction >= 0.5 {
            truncated + 1.0
        } else if fraction <= -0.5 {
            truncated - 1.0
        } else {
            truncated
        };
        rounded.copysign(x)
    } else {
        x
    }
}

/// Wrap an angle to (-pi, pi].
pub fn wrap_angle(angle_rad: f64) -> f64 {
    use std::f64::consts::{PI, TAU};
    let wrapped = angle_rad - TAU * round(angle_rad / TAU);
    // `round` leaves [-pi, pi]; the half-open interval maps -pi to +pi.
    if wrapped <= -PI {
        wrapped + TAU
    } else if wrapped > PI {
        wrapped - TAU
    } else {
        wrapped
    }
}

/// Angle between two non-zero vectors in [0, pi], accurate near 0 and pi (atan2, not acos).
/// Returns 0 when either vector is zero.
pub fn angle_between(a: &Vector3<f64>, b: &Vector3<f64>) -> f64 {
    libm::atan2(a.cross(b).norm(), a.dot(b))
}

#[cfg(test)]
// std's functions here are a reference independent of the libm the model uses.
#[allow(clippy::disallowed_methods)]
mod tests {
    use super::*;
    use std::f64::consts::{FRAC_PI_2, PI};

    #[test]
    fn scalar_first_round_trip_keeps_component_order() {
        // GIVEN a quaternion whose components are all different
        let q_in = [0.5, -0.5, 0.5, 0.5];
        // WHEN it passes through nalgebra and back
        let q = attitude_from_scalar_first(q_in).unwrap();
        // THEN nalgebra sees the scalar as w and the order survives the round trip
        assert_eq!(q.w, 0.5);
        assert_eq!(q.coords[3], 0.5, "nalgebra stores w last");
        assert_eq!(attitude_to_scalar_first(&q), q_in);
    }

    #[test]
    fn input_quaternion_is_normalised_and_zero_norm_refused() {
        let q = attitude_from_scalar_first([2.0, 0.0, 0.0, 0.0]).unwrap();
        assert_eq!(attitude_to_scalar_first(&q), [1.0, 0.0, 0.0, 0.0]);
        assert!(attitude_from_scalar_first([0.0; 4]).is_none());
        assert!(attitude_from_scalar_first([1e-9, 0.0, 0.0, 0.0]).is_none());
    }

    #[test]
    fn quaternion_rotates_body_vectors_into_nue() {
        // GIVEN the attitude pitched +90 deg about body z (East)
        let q =
            attitude_from_scalar_first([(0.25 * PI).cos(), 0.0, 0.0, (0.25 * PI).sin()]).unwrap();
        // THEN the thrust axis (body y) points to -North, by the right-hand rule
        let thrust_nue = q * thrust_axis_body();
        assert!((thrust_nue - Vector3::new(-1.0, 0.0, 0.0)).norm() < 1e-15);
        // AND the paper's A maps that NUE direction back onto body y
        let a = dcm_nue_to_body(&q);
        assert!((a * thrust_nue - thrust_axis_body()).norm() < 1e-15);
    }

    #[test]
    fn rotation_about_thrust_axis_is_hamilton_active() {
        let q = rotation_about_thrust_axis(FRAC_PI_2);
        // +90 deg about y takes body z (East when upright) to North
        assert!((q * Vector3::z() - Vector3::x()).norm() < 1e-15);
        let axis = Vector3::y_axis();
        assert!((twist_angle(&q, &axis) - FRAC_PI_2).abs() < 1e-15);
    }

    #[test]
    fn canonical_picks_the_short_way() {
        let long_way = rotation_about_thrust_axis(1.5 * PI);
        let short = canonical(&long_way);
        assert!(short.w >= 0.0);
        assert!((short.angle() - 0.5 * PI).abs() < 1e-12);
        assert!(short.angle_to(&long_way) < 1e-12, "same rotation");
    }

    #[test]
    fn the_inline_round_is_std_round_bit_for_bit() {
        let mut values = vec![
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.5,
            -1.5,
            2.5,
            -2.5,
            0.49999999999999994,
            -0.49999999999999994,
            f64::from_bits(1),
            -f64::from_bits(1),
            4_503_599_627_370_495.5,
            -4_503_599_627_370_495.5,
            4_503_599_627_370_496.0,
            9.3e18,
            -9.3e18,
            f64::MAX,
            f64::MIN,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ];
        let mut state = 0x9e37_79b9_7f4a_7c15_u64;
        for _ in 0..200_000 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let x = f64::from_bits(state);
            values.extend([
                x,
                x.fract(),
                x * 1e-300,
                ((state >> 11) as f64 - 4e15) * 1e-12,
            ]);
        }
        for k in -100_000..=100_000 {
            values.extend([f64::from(k) * 0.5, f64::from(k) * 0.01, f64::from(k) * 0.3]);
        }
        for x in values {
            let (ours, std) = (round(x), x.round());
            if std.is_nan() {
                assert!(ours.is_nan(), "{x:e}");
            } else {
                assert_eq!(ours.to_bits(), std.to_bits(), "{x:e}");
            }
        }
    }

    #[test]
    fn wrap_angle_is_half_open() {
        assert_eq!(wrap_angle(PI), PI);
        assert_eq!(wrap_angle(-PI), PI);
        assert!((wrap_angle(3.0 * PI) - PI).abs() < 1e-12);
        assert!((wrap_angle(-0.5 * PI) + 0.5 * PI).abs() < 1e-15);
        assert!((wrap_angle(7.0) - (7.0 - 2.0 * PI)).abs() < 1e-12);
    }

    #[test]
    fn angle_between_is_accurate_at_both_ends() {
        let y = Vector3::y();
        let tiny = Vector3::new(1e-12, 1.0, 0.0);
        assert!((angle_between(&y, &tiny) - 1e-12).abs() < 1e-20);
        assert!((angle_between(&y, &-tiny) - (PI - 1e-12)).abs() < 1e-15);
    }
}
