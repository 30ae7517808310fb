//! The achieved rotation about the thrust axis, phi_b (paper Sec. IV, phi_b formula, ERRATA 5).
use crate::conventions::Attitude;

/// Paper Sec. IV, phi_b formula, as corrected by ERRATA 5: the third angle of the intrinsic
/// 1-3-2 (x, then new z, then new y) sequence `R(q) = R_x(a) R_z(b) R_y(phi_b)`, i.e. the
/// rotation about the thrust axis,
/// `phi_b = atan2(2 (q1 q3 + q0 q2), q0^2 + q1^2 - q2^2 - q3^2) = atan2(A31, A11)`,
/// scalar first. The paper's printed formula mixes index sets and uses atan.
///
/// Quadratic in `q`, so `q` and `-q` give the same angle. Result in (-pi, pi]. At gimbal
/// lock (`b = ±pi/2`: thrust axis horizontal along North) both arguments vanish and the
/// result is some finite angle, never NaN.
pub fn phi_b(q_body_to_nue: &Attitude) -> f64 {
    let (q0, q1, q2, q3) = (
        q_body_to_nue.w,
        q_body_to_nue.i,
        q_body_to_nue.j,
        q_body_to_nue.k,
    );
    let a31 = 2.0 * (q1 * q3 + q0 * q2);
    let a11 = q0 * q0 + q1 * q1 - q2 * q2 - q3 * q3;
    let angle = libm::atan2(a31, a11);
    // atan2 returns [-pi, pi]; the controller's convention is the half-open (-pi, pi].
    if angle == -std::f64::consts::PI {
        std::f64::consts::PI
    } else {
        angle
    }
}

#[cfg(test)]
// std's functions here are a reference independent of the libm the model uses.
#[allow(clippy::disallowed_methods)]
mod tests {
    use super::*;
    use crate::attitude::reference::q_phi;
    use crate::conventions::{dcm_nue_to_body, twist_angle};
    use nalgebra::{Rotation3, UnitQuaternion, Vector3};
    use std::f64::consts::FRAC_PI_2;

    /// Independent 1-3-2 extraction from the rotation matrix: with R = R_x(a) R_z(b) R_y(c),
    /// the first row of R is untouched by R_x and reads [cb cc, -sb, cb sc], so
    /// c = atan2(R13, R11).
    fn third_angle_from_rotation_matrix(r: &Rotation3<f64>) -> f64 {
        let m = r.matrix();
        m[(0, 2)].atan2(m[(0, 0)])
    }

    #[test]
    fn phi_b_agrees_with_an_independent_1_3_2_extraction() {
        let steps = [-3.1, -2.0, -0.9, -0.2, 0.0, 0.3, 1.1, 2.4, 3.1];
        for &a in &steps {
            for &b in &[-1.4, -0.7, 0.0, 0.5, 1.3] {
                for &c in &steps {
                    // GIVEN R built from the 1-3-2 angles by matrix products (not quaternions)
                    let r = Rotation3::from_axis_angle(&Vector3::x_axis(), a)
                        * Rotation3::from_axis_angle(&Vector3::z_axis(), b)
                        * Rotation3::from_axis_angle(&Vector3::y_axis(), c);
                    let q = UnitQuaternion::from_rotation_matrix(&r);
                    // THEN phi_b of its quaternion is the third angle, read from the matrix
                    assert!(
                        (phi_b(&q) - c).abs() < 1e-12,
                        "a {a} b {b} c {c}: {}",
                        phi_b(&q)
                    );
                    assert!((third_angle_from_rotation_matrix(&r) - c).abs() < 1e-12);
                    // AND equals atan2(A31, A11) of the paper's DCM A = R^T
                    let dcm = dcm_nue_to_body(&q);
                    assert!((phi_b(&q) - dcm[(2, 0)].atan2(dcm[(0, 0)])).abs() < 1e-12);
                    // AND does not care about the quaternion's sign
                    let neg = UnitQuaternion::new_unchecked(-q.into_inner());
                    assert_eq!(phi_b(&neg), phi_b(&q));
                }
            }
        }
    }

    #[test]
    fn phi_b_of_q_phi_is_phi() {
        for phi in [-3.0, -1.0, 0.0, 0.5, 2.9, std::f64::consts::PI] {
            assert!((phi_b(&q_phi(phi)) - phi).abs() < 1e-14, "ERRATA 6");
        }
    }

    #[test]
    fn errata_7_phi_b_is_not_the_swing_twist_angle_when_tilted() {
        // GIVEN the thrust axis tilted toward North-East (no twist in the swing-twist sense)
        let tilt =
            crate::attitude::reference::q_guid(&lander_math::frames::Nue::new(0.5, 1.0, 0.5));
        // THEN the swing-twist angle about y is zero but the 1-3-2 angle is not
        assert!(twist_angle(&tilt, &Vector3::y_axis()).abs() < 1e-15);
        let offset = phi_b(&tilt);
        assert!(
            offset.abs() > 0.05,
            "1-3-2 angle of a diagonal tilt: {offset}"
        );
        // AND the difference is a constant rotation about y: adding a twist shifts both alike
        for twist in [-2.0, 0.4, 1.7] {
            let q = tilt * q_phi(twist);
            let diff = crate::conventions::wrap_angle(phi_b(&q) - twist);
            assert!((diff - offset).abs() < 1e-12);
        }
    }

    #[test]
    fn phi_b_is_finite_at_gimbal_lock() {
        let lock = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), FRAC_PI_2);
        assert!(phi_b(&lock).is_finite());
    }
}
