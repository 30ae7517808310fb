//! Position-velocity (PV) guidance for hover (paper Sec. III, PV law).
use lander_math::frames::Nue;
use nalgebra::Vector3;
use std::f64::consts::TAU;

/// PV gains. Paper Sec. III states them as positive-definite; we use scalars from a
/// second-order design: `Kr = omega_g^2`, `Kv = 2 zeta_g omega_g`, `omega_g = 2 pi f_g`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PvGains {
    /// 1/s^2
    pub kr: f64,
    /// 1/s
    pub kv: f64,
}

impl PvGains {
    /// Gains placing the position-error poles at natural frequency `2 pi bandwidth_hz` with
    /// damping ratio `damping` (the paper's "Guidance Bandwidth" and "Guidance Damping").
    pub fn from_bandwidth(bandwidth_hz: f64, damping: f64) -> Self {
        let omega_g = TAU * bandwidth_hz;
        Self {
            kr: omega_g * omega_g,
            kv: 2.0 * damping * omega_g,
        }
    }
}

/// Paper Sec. III, PV law `a = g + Kr r_e + Kv v_e` with `r_e = r_ref - r`, `v_e = v_ref - v`.
///
/// Returns the **thrust** acceleration in NUE. ERRATA 8: the paper's `g` is the
/// gravity-cancelling vector `[0, +g, 0]`; writing it with the gravity vector `[0, -g, 0]` would
/// command the lander down. The net acceleration is then `Kr r_e + Kv v_e`.
///
/// Positions and velocities are NUE by type; a body-axis vector is refused at compile time:
///
/// ```
/// use fmu_gnc::guidance::pv::{pv_thrust_acceleration_nue, PvGains};
/// use lander_math::frames::Nue;
/// let gains = PvGains::from_bandwidth(0.06, 0.8);
/// let r_nue = Nue::new(0.0, 790.0, 0.0);
/// let v_nue = Nue::zeros();
/// let target = Nue::new(0.0, 800.0, 0.0);
/// pv_thrust_acceleration_nue(&gains, 1.62, &target, &Nue::zeros(), &r_nue, &v_nue);
/// ```
///
/// ```compile_fail,E0308
/// use fmu_gnc::guidance::pv::{pv_thrust_acceleration_nue, PvGains};
/// use lander_math::frames::{Body, Nue};
/// let gains = PvGains::from_bandwidth(0.06, 0.8);
/// let r_nue = Nue::new(0.0, 790.0, 0.0);
/// let v_body = Body::zeros(); // e.g. a velocimeter reading, not yet rotated into NUE
/// let target = Nue::new(0.0, 800.0, 0.0);
/// pv_thrust_acceleration_nue(&gains, 1.62, &target, &Nue::zeros(), &r_nue, &v_body);
/// ```
pub fn pv_thrust_acceleration_nue(
    gains: &PvGains,
    gravity_mps2: f64,
    r_ref_nue: &Nue,
    v_ref_nue: &Nue,
    r_nue: &Nue,
    v_nue: &Nue,
) -> Nue {
    let g_cancel_nue = Vector3::new(0.0, gravity_mps2, 0.0);
    Nue(g_cancel_nue + (r_ref_nue.0 - r_nue.0) * gains.kr + (v_ref_nue.0 - v_nue.0) * gains.kv)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Matrix2;

    #[test]
    fn closed_loop_poles_match_bandwidth_and_damping() {
        // GIVEN the paper's guidance bandwidth and damping
        let (f_hz, zeta) = (0.06, 0.8);
        let gains = PvGains::from_bandwidth(f_hz, zeta);
        // WHEN the PV law drives r'' = a_thrust + g_vec (error e = r - r_ref: e'' = -Kr e - Kv e')
        let a = Matrix2::new(0.0, 1.0, -gains.kr, -gains.kv);
        let poles = a.complex_eigenvalues();
        // THEN both poles have |s| = 2 pi f and -Re(s)/|s| = zeta
        for s in poles.iter() {
            let omega = s.norm();
            assert!((omega - TAU * f_hz).abs() < 1e-12, "|s| = {omega}");
            assert!(
                (-s.re / omega - zeta).abs() < 1e-12,
                "zeta = {}",
                -s.re / omega
            );
        }
    }

    #[test]
    fn on_target_at_rest_commands_exactly_gravity_cancellation() {
        let gains = PvGains::from_bandwidth(0.06, 0.8);
        let r = Nue::new(0.0, 800.0, 0.0);
        let a = pv_thrust_acceleration_nue(&gains, 1.62, &r, &Nue::zeros(), &r, &Nue::zeros());
        assert_eq!(a, Nue::new(0.0, 1.62, 0.0));
    }

    #[test]
    fn below_target_commands_more_than_gravity_up() {
        let gains = PvGains::from_bandwidth(0.06, 0.8);
        let r_ref = Nue::new(0.0, 800.0, 0.0);
        let r = Nue::new(0.0, 790.0, 0.0);
        let a = pv_thrust_acceleration_nue(&gains, 1.62, &r_ref, &Nue::zeros(), &r, &Nue::zeros());
        assert!(a.0.y > 1.62);
        // AND sinking makes it push harder still
        let a_sinking = pv_thrust_acceleration_nue(
            &gains,
            1.62,
            &r_ref,
            &Nue::zeros(),
            &r,
            &Nue::new(0.0, -1.0, 0.0),
        );
        assert!(a_sinking.0.y > a.0.y);
    }
}
