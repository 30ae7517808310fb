//! Attitude gains from bandwidth, damping and inertia (ERRATA "Modelling defaults").
use super::profile::RollReference;
use lander_math::frames::Body;
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
    /// Angular deceleration the law may count on to stop a rotation, rad/s^2, per axis;
    /// infinite = no shaping (the paper's PD). See [`braking_limited_error`].
    pub braking_radps2: Vector3<f64>,
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
            braking_radps2: Vector3::repeat(f64::INFINITY),
        }
    }

    /// Enables braking-limited error shaping: the law may count on `margin` of the torque
    /// limit to stop a rotation (`margin` in (0, 1]; 0 leaves the paper's pure PD).
    pub fn with_braking(mut self, torque_limit_body_nm: &Vector3<f64>, margin: f64) -> Self {
        if margin > 0.0 {
            self.braking_radps2 = (torque_limit_body_nm * margin).component_div(&self.inertia_kgm2);
        }
        self
    }
}

/// Beyond the paper (the square-root controller of ArduPilot's attitude library, for the same
/// reason): the PD law `-Kp e - Kd omega` is `-Kd (omega - omega_cmd)` with the rate demand
/// `omega_cmd = -(Kp / Kd) e`. With the paper's gains (0.5 Hz) and RCS (116 N m) a 15 deg error
/// asks for ten times the torque limit; the saturated loop then builds up a rate it cannot
/// brake in the remaining angle and overshoots by about as much again. Shaping the angle error
/// so that `|omega_cmd| <= sqrt(2 a_brake |e|)`, the rate from which `a_brake` stops the
/// rotation exactly at the target, removes that overshoot:
/// `e' = sign(e) min(|e|, (Kd / Kp) sqrt(2 a_brake |e|))`.
/// Below `|e| = 2 a_brake (Kd / Kp)^2` (4 deg on the pitch axis with the defaults and a margin of
/// 0.5) `e' = e`: small errors see exactly the paper's law, and so does every law for which
/// `braking_radps2` is infinite.
pub fn braking_limited_error(
    angle_error_rad: f64,
    kp_nm_per_rad: f64,
    kd_nms_per_rad: f64,
    braking_radps2: f64,
) -> f64 {
    if !(braking_radps2.is_finite() && kp_nm_per_rad > 0.0) {
        return angle_error_rad;
    }
    let limit =
        kd_nms_per_rad / kp_nm_per_rad * (2.0 * braking_radps2 * angle_error_rad.abs()).sqrt();
    if limit.is_nan() {
        angle_error_rad
    } else {
        // max/min rather than clamp: a restored state may carry gains of either sign.
        angle_error_rad.max(-limit).min(limit)
    }
}

/// Paper Sec. IV control law `tau = -Kp e - Kd omega_e + omega x I omega`, with `e` the angle
/// error in body axes (ERRATA 9) and `omega_e = omega - omega_ref`; the paper's `omega_ref` is
/// 0 (ERRATA defaults), a shaped manoeuvre feeds its rate and, as `I alpha_ref`, its
/// acceleration forward (`reference`). `e` is braking-limited per axis when the gains ask for
/// it ([`braking_limited_error`]).
#[inline(always)]
pub fn pd_torque_body(
    gains: &AttitudeGains,
    angle_error_body: &Body,
    omega_body: &Body,
    reference: &RollReference,
) -> Body {
    let (angle_error_body, omega_body) = (&angle_error_body.0, &omega_body.0);
    let inertia_omega = gains.inertia_kgm2.component_mul(omega_body);
    let shaped = Vector3::from_fn(|i, _| {
        braking_limited_error(
            angle_error_body[i],
            gains.kp_nm_per_rad[i],
            gains.kd_nms_per_rad[i],
            gains.braking_radps2[i],
        )
    });
    let omega_error = omega_body - reference.omega_body().0;
    let torque = -gains.kp_nm_per_rad.component_mul(&shaped)
        - gains.kd_nms_per_rad.component_mul(&omega_error)
        + omega_body.cross(&inertia_omega);
    // Skipped at rest, where adding +0 could turn a -0 torque into +0: the paper's law stays
    // bit for bit what it was.
    Body(if reference.accel_radps2 == 0.0 {
        torque
    } else {
        torque + gains.inertia_kgm2.component_mul(&reference.alpha_body().0)
    })
}

/// Per-axis saturation of a torque command to the RCS limits (each limit >= 0).
///
/// A NaN component can only come from overflowing terms (`inf - inf` at body rates beyond
/// ~1e150 rad/s); it is commanded as zero torque on that axis rather than passed on.
pub fn saturate_torque_body(torque_body: &Body, limit_body: &Vector3<f64>) -> Body {
    Body(torque_body.0.zip_map(limit_body, |tau, limit| {
        if tau.is_nan() {
            0.0
        } else {
            // `tau.max(-limit).min(limit)` as compares (never a panic on a negative limit
            // from a restored state, as `clamp` would): a NaN limit leaves the value as it
            // is, as max and min do, and a tie keeps the value, as they do here (`maxsd` and
            // `minsd` with the value second), so one instruction each rather than their
            // NaN-aware lowering.
            let at_least = if -limit > tau { -limit } else { tau };
            if limit < at_least {
                limit
            } else {
                at_least
            }
        }
    }))
}

#[cfg(test)]
// std's functions here are a reference independent of the libm the model uses.
#[allow(clippy::disallowed_methods)]
mod tests {
    use super::*;
    use nalgebra::Matrix2;

    #[test]
    fn small_errors_see_the_paper_law_large_ones_a_brakeable_rate_demand() {
        // GIVEN the pitch axis with the default gains and half the 116 N m limit for braking
        let gains = AttitudeGains::from_bandwidth(0.5, 0.8, Vector3::new(400.0, 300.0, 450.0))
            .with_braking(&Vector3::repeat(116.0), 0.5);
        let (kp, kd, a) = (
            gains.kp_nm_per_rad.z,
            gains.kd_nms_per_rad.z,
            gains.braking_radps2.z,
        );
        assert!((a - 58.0 / 450.0).abs() < 1e-15);
        let linear_up_to = 2.0 * a * (kd / kp).powi(2);
        // THEN below the corner the error is untouched (the paper's PD)
        for e in [0.0, 1e-6, -0.5 * linear_up_to, 0.999 * linear_up_to] {
            assert_eq!(braking_limited_error(e, kp, kd, a), e);
        }
        // AND above it the implied rate demand is exactly the braking rate sqrt(2 a |e|)
        for e in [0.1, -0.26, 1.0, -3.0] {
            let shaped = braking_limited_error(e, kp, kd, a);
            let rate_demand = kp / kd * shaped.abs();
            assert!(
                (rate_demand - (2.0 * a * e.abs()).sqrt()).abs() < 1e-12,
                "e {e}"
            );
            assert_eq!(shaped.signum(), e.signum());
            assert!(shaped.abs() < e.abs());
        }
        // AND without braking (the default gains) nothing is shaped
        let plain = AttitudeGains::from_bandwidth(0.5, 0.8, Vector3::repeat(450.0));
        assert_eq!(
            braking_limited_error(1.0, kp, kd, plain.braking_radps2.z),
            1.0
        );
        // AND a margin of 0 keeps the paper's law
        let off = plain.with_braking(&Vector3::repeat(116.0), 0.0);
        assert!(off.braking_radps2.iter().all(|b| b.is_infinite()));
    }

    #[test]
    fn shaping_never_makes_a_nan_from_finite_input() {
        for e in [f64::MAX, -f64::MAX, f64::MIN_POSITIVE, 0.0, -0.0] {
            assert!(!braking_limited_error(e, 1e4, 2e3, 0.1).is_nan());
            assert!(!braking_limited_error(e, 0.0, 2e3, 0.1).is_nan());
        }
    }

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
        let tau = pd_torque_body(&gains, &Body::zeros(), &Body(w), &RollReference::default()).0;
        let w_dot = (tau - w.cross(&inertia.component_mul(&w))).component_div(&inertia);
        assert!(w_dot.norm() < 1e-15);
    }

    #[test]
    fn saturation_is_per_axis() {
        let limit = Vector3::new(116.0, 116.0, 50.0);
        let tau = saturate_torque_body(&Body::new(500.0, -20.0, -60.0), &limit);
        assert_eq!(tau, Body::new(116.0, -20.0, -50.0));
        let overflowed = Body::new(f64::INFINITY, f64::NAN, f64::NEG_INFINITY);
        assert_eq!(
            saturate_torque_body(&overflowed, &limit),
            Body::new(116.0, 0.0, -50.0)
        );
    }
}
