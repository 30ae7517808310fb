//! From guidance acceleration to engine thrust (paper Sec. III, `T = m ||a||`, with ERRATA 8).
use nalgebra::Vector3;

/// ERRATA 8: the thrust acceleration is the net (kinematic) acceleration minus gravity,
/// `a_T = a_net - g_vec` with `g_vec = [0, -g, 0]` in NUE.
pub fn thrust_acceleration_nue(a_net_nue: &Vector3<f64>, gravity_mps2: f64) -> Vector3<f64> {
    a_net_nue - Vector3::new(0.0, -gravity_mps2, 0.0)
}

/// Inverse of [`thrust_acceleration_nue`]: `a_net = a_T + g_vec`.
pub fn net_acceleration_nue(a_thrust_nue: &Vector3<f64>, gravity_mps2: f64) -> Vector3<f64> {
    a_thrust_nue + Vector3::new(0.0, -gravity_mps2, 0.0)
}

/// Paper Sec. III, `T = m ||a_T||_2`, saturated to `[thrust_min_n, thrust_max_n]`.
pub fn thrust_magnitude_n(
    mass_kg: f64,
    a_thrust_nue: &Vector3<f64>,
    thrust_min_n: f64,
    thrust_max_n: f64,
) -> f64 {
    (mass_kg * a_thrust_nue.norm()).clamp(thrust_min_n, thrust_max_n)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hovering_needs_thrust_equal_to_weight() {
        // GIVEN zero net acceleration on the Moon
        let a_t = thrust_acceleration_nue(&Vector3::zeros(), 1.62);
        // THEN the engines push up with m g
        assert_eq!(a_t, Vector3::new(0.0, 1.62, 0.0));
        assert!((thrust_magnitude_n(900.0, &a_t, 720.0, 1600.0) - 1458.0).abs() < 1e-9);
        assert_eq!(net_acceleration_nue(&a_t, 1.62), Vector3::zeros());
    }

    #[test]
    fn thrust_is_saturated_to_the_throttle_range() {
        let up = Vector3::new(0.0, 10.0, 0.0);
        assert_eq!(thrust_magnitude_n(900.0, &up, 720.0, 1600.0), 1600.0);
        assert_eq!(
            thrust_magnitude_n(900.0, &Vector3::zeros(), 720.0, 1600.0),
            720.0
        );
    }
}
