//! Attitude gains from bandwidth, damping and inertia (ERRATA "Modelling defaults").
use nalgebra::Vector3;
use std::f64::consts::TAU;

/// Diagonal PD gains and the inertia they were designed for, body axes (x yaw, y roll, z pitch).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AttitudeGains {
    /// N m / rad
    pub kp_nm_per_rad: Vector3<f64>,
    /// N m s / rad
    pub kd_nms_per_rad: Vector3<f64>,
    /// Principal moments of inertia, kg m^2 (also used by the gyroscopic feed-forward).
    pub inertia_kgm2: Vector3<f64>,
}

impl AttitudeGains {
    /// `Kp = I omega_c^2`, `Kd = 2 zeta_c omega_c I`, `omega_c = 2 pi f_c`, per axis.
    ///
    /// These act on **angle** errors: each axis then behaves as `I e'' + Kd e' + Kp e = 0`,
    /// natural frequency `omega_c`, damping `zeta_c`. The quaternion vector part is a half
    /// angle (`q_v = sin(theta/2) n ≈ theta/2 n`), so the laws feed `2 q_v`, not `q_v`
    /// (ERRATA 9); feeding `q_v` would halve the stiffness and lower the bandwidth by sqrt 2.
    pub fn from_bandwidth(bandwidth_hz: f64, damping: f64, inertia_kgm2: Vector3<f64>) -> Self {
        let omega_c = TAU * bandwidth_hz;
        Self {
            kp_nm_per_rad: inertia_kgm2 * (omega_c * omega_c),
            kd_nms_per_rad: inertia_kgm2 * (2.0 * damping * omega_c),
            inertia_kgm2,
        }
    }
}

/// Paper Sec. IV control law `tau = -Kp e - Kd omega_e + omega x I omega`, with `e` the angle
/// error in body axes (ERRATA 9) and `omega_ref = 0` (ERRATA defaults), so `omega_e = omega`.
pub fn pd_torque_body(
    gains: &AttitudeGains,
    angle_error_body: &Vector3<f64>,
    omega_body: &Vector3<f64>,
) -> Vector3<f64> {
    let inertia_omega = gains.inertia_kgm2.component_mul(omega_body);
    -gains.kp_nm_per_rad.component_mul(angle_error_body)
        - gains.kd_nms_per_rad.component_mul(omega_body)
        + omega_body.cross(&inertia_omega)
}

/// Per-axis saturation of a torque command to the RCS limits (each limit >= 0).
///
/// A NaN component can only come from overflowing terms (`inf - inf` at body rates beyond
/// ~1e150 rad/s); it is commanded as zero torque on that axis rather than passed on.
pub fn saturate_torque_body(torque_body: &Vector3<f64>, limit_body: &Vector3<f64>) -> Vector3<f64> {
    torque_body.zip_map(limit_body, |tau, limit| {
        if tau.is_nan() {
            0.0
        } else {
            tau.clamp(-limit, limit)
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Matrix2;

    #[test]
    fn each_axis_has_the_design_bandwidth_and_damping() {
        let inertia = Vector3::new(400.0, 300.0, 450.0);
        let gains = AttitudeGains::from_bandwidth(0.5, 0.8, inertia);
        for i in 0..3 {
            // I e'' = -Kp e - Kd e'  ->  companion matrix of s^2 + Kd/I s + Kp/I
            let a = Matrix2::new(
                0.0,
                1.0,
                -gains.kp_nm_per_rad[i] / inertia[i],
                -gains.kd_nms_per_rad[i] / inertia[i],
            );
            for s in a.complex_eigenvalues().iter() {
                assert!((s.norm() - TAU * 0.5).abs() < 1e-12);
                assert!((-s.re / s.norm() - 0.8).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn feed_forward_cancels_the_gyroscopic_term() {
        // GIVEN zero error and a spin: I w' = tau - w x I w must give w' = 0 for the Kd-free part
        let inertia = Vector3::new(400.0, 300.0, 450.0);
        let gains = AttitudeGains {
            kd_nms_per_rad: Vector3::zeros(),
            ..AttitudeGains::from_bandwidth(0.5, 0.8, inertia)
        };
        let w = Vector3::new(0.1, -0.2, 0.3);
        let tau = pd_torque_body(&gains, &Vector3::zeros(), &w);
        let w_dot = (tau - w.cross(&inertia.component_mul(&w))).component_div(&inertia);
        assert!(w_dot.norm() < 1e-15);
    }

    #[test]
    fn saturation_is_per_axis() {
        let limit = Vector3::new(116.0, 116.0, 50.0);
        let tau = saturate_torque_body(&Vector3::new(500.0, -20.0, -60.0), &limit);
        assert_eq!(tau, Vector3::new(116.0, -20.0, -50.0));
        let overflowed = Vector3::new(f64::INFINITY, f64::NAN, f64::NEG_INFINITY);
        assert_eq!(
            saturate_torque_body(&overflowed, &limit),
            Vector3::new(116.0, 0.0, -50.0)
        );
    }
}
