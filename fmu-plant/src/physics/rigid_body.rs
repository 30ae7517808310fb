//! Rotational dynamics of a rigid body whose body axes are its principal axes.
//!
//! Euler's equations `I w' + w x I w = tau` and the quaternion kinematics
//! `q' = ½ q ⊗ [0, w]` (ERRATA item 3: the paper's printed Omega matrix is not skew-symmetric;
//! this product form is). The landing-site frame is treated as inertial for the rotation: the
//! Moon turns at 2.7e-6 rad/s, five orders of magnitude below the rates the RCS commands.
use super::frames::{body_to_nue, Body, Nue};
use nalgebra::{Quaternion, Vector3};

/// Principal moments of inertia `[Ixx, Iyy, Izz]` in kg m^2 (body axes = principal axes).
pub type PrincipalInertia = Vector3<f64>;

/// Body angular acceleration in rad/s^2 from Euler's equations.
///
/// Rate and torque are body axes by type; a torque still in NUE does not compile:
///
/// ```compile_fail,E0308
/// use fmu_plant::physics::frames::{Body, Nue};
/// use fmu_plant::physics::rigid_body::omega_dot_body;
/// let inertia = nalgebra::Vector3::new(400.0, 300.0, 450.0);
/// let torque_nue = Nue::new(0.0, 0.0, 116.0); // not yet rotated into body axes
/// omega_dot_body(&inertia, &Body::zeros(), &torque_nue);
/// ```
#[inline]
pub fn omega_dot_body(inertia: &PrincipalInertia, omega_body: &Body, torque_body: &Body) -> Body {
    let (omega_body, torque_body) = (&omega_body.0, &torque_body.0);
    let angular_momentum_body = inertia.component_mul(omega_body);
    Body((torque_body - omega_body.cross(&angular_momentum_body)).component_div(inertia))
}

/// `q' = ½ q ⊗ [0, omega_body]` for `q` = body to NUE.
#[inline]
pub fn quaternion_rate(q_body_to_nue: &Quaternion<f64>, omega_body: &Body) -> Quaternion<f64> {
    (q_body_to_nue * Quaternion::from_imag(omega_body.0)) * 0.5
}

/// Angular momentum in NUE (constant when no torque acts).
pub fn angular_momentum_nue(
    inertia: &PrincipalInertia,
    q_body_to_nue: &Quaternion<f64>,
    omega_body: &Body,
) -> Nue {
    let momentum_body = Body(inertia.component_mul(&omega_body.0));
    body_to_nue(q_body_to_nue, &momentum_body)
}

/// Rotational kinetic energy ½ wᵀ I w in J.
pub fn rotational_energy(inertia: &PrincipalInertia, omega_body: &Body) -> f64 {
    0.5 * omega_body.0.dot(&inertia.component_mul(&omega_body.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quaternion_rate_is_tangent_to_the_unit_sphere() {
        // d|q|^2/dt = 2 q . q' must vanish for any rate: the form preserves the norm.
        let q = Quaternion::new(0.8, 0.2, -0.4, 0.4).normalize();
        let w = Body::new(0.3, -2.0, 1.1);
        let qdot = quaternion_rate(&q, &w);
        assert!(q.coords.dot(&qdot.coords).abs() < 1e-15);
    }

    #[test]
    fn quaternion_rate_matches_the_corrected_omega_matrix_of_errata_item_3() {
        // Independent form: scalar-first q' = ½ Ω(w) q with the skew-symmetric 4x4 matrix
        // (the paper's printed matrix, reordered to scalar first, with row 4 corrected).
        let (q0, q1, q2, q3) = (0.7, 0.1, -0.5, 0.5);
        let q = Quaternion::new(q0, q1, q2, q3);
        let (wx, wy, wz) = (0.4, -0.2, 0.9);
        let omega = nalgebra::Matrix4::new(
            0.0, -wx, -wy, -wz, //
            wx, 0.0, wz, -wy, //
            wy, -wz, 0.0, wx, //
            wz, wy, -wx, 0.0,
        );
        let expected = omega * nalgebra::Vector4::new(q0, q1, q2, q3) * 0.5;
        assert_eq!(omega.transpose(), -omega, "skew-symmetric");
        let got = quaternion_rate(&q, &Body::new(wx, wy, wz));
        let got = nalgebra::Vector4::new(got.w, got.i, got.j, got.k);
        assert!((got - expected).norm() < 1e-15);
    }

    #[test]
    fn gyroscopic_term_vanishes_for_spin_about_a_principal_axis() {
        let inertia = Vector3::new(400.0, 300.0, 450.0);
        let wdot = omega_dot_body(&inertia, &Body::new(0.0, 3.0, 0.0), &Body::zeros());
        assert_eq!(wdot, Body::zeros());
    }

    #[test]
    fn euler_equations_reproduce_the_hand_computed_gyroscopic_coupling() {
        // Ixx wx' = (Iyy - Izz) wy wz; with w = (0, 1, 2): (300 - 450) * 2 / 400 = -0.75.
        let inertia = Vector3::new(400.0, 300.0, 450.0);
        let wdot = omega_dot_body(&inertia, &Body::new(0.0, 1.0, 2.0), &Body::zeros()).0;
        assert!((wdot.x + 0.75).abs() < 1e-15);
        assert_eq!(wdot.y, 0.0);
        assert_eq!(wdot.z, 0.0);
    }
}
