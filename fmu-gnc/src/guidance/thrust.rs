//! From guidance acceleration to engine thrust (paper Sec. III, `T = m ||a||`, with ERRATA 8).
use lander_math::frames::Nue;
use nalgebra::Vector3;

/// ERRATA 8: the thrust acceleration is the net (kinematic) acceleration minus gravity,
/// `a_T = a_net - g_vec` with `g_vec = [0, -g, 0]` in NUE.
pub fn thrust_acceleration_nue(a_net_nue: &Nue, gravity_mps2: f64) -> Nue {
    *a_net_nue - Nue::new(0.0, -gravity_mps2, 0.0)
}

/// Inverse of [`thrust_acceleration_nue`]: `a_net = a_T + g_vec`.
pub fn net_acceleration_nue(a_thrust_nue: &Nue, gravity_mps2: f64) -> Nue {
    *a_thrust_nue + Nue::new(0.0, -gravity_mps2, 0.0)
}

/// Paper Sec. III, `T = m ||a_T||_2`, saturated to `[thrust_min_n, thrust_max_n]`.
pub fn thrust_magnitude_n(
    mass_kg: f64,
    a_thrust_nue: &Nue,
    thrust_min_n: f64,
    thrust_max_n: f64,
) -> f64 {
    // Not `f64::clamp`: it panics when min > max, and parameters set in initialization mode
    // may be so until fmi2ExitInitializationMode refuses them, while a get in that mode
    // already evaluates this (found by the API fuzzer: fmi2GetReal answered fmi2Fatal).
    (mass_kg * a_thrust_nue.norm())
        .min(thrust_max_n)
        .max(thrust_min_n)
}

/// Beyond the paper: the thrust acceleration the engines can actually deliver, closest to the
/// command with priority to the vertical (Up) component, so that a lateral demand never costs
/// altitude. Above `thrust_max_n / m` the Up component is kept (itself capped at the maximum)
/// and the horizontal part shortened to fit; below `thrust_min_n / m` the vector is lengthened
/// along its own direction (straight up when it has none).
///
/// Guidance stores this *achievable* command and the descent polynomial restarts from it
/// (`a0`), which is the anti-windup: re-solving from an acceleration the engines could not
/// give would make the command grow while the state falls behind it.
pub fn achievable_thrust_acceleration_nue(
    a_thrust_nue: &Nue,
    mass_kg: f64,
    thrust_min_n: f64,
    thrust_max_n: f64,
) -> Nue {
    if mass_kg.is_nan() || mass_kg <= 0.0 {
        return *a_thrust_nue;
    }
    let (a_min, a_max) = (thrust_min_n / mass_kg, thrust_max_n / mass_kg);
    // A mass so small (1e-308 kg) that the limits overflow: no acceleration is out of reach,
    // and shaping against infinite limits would output inf (found by the API fuzzer).
    if !(a_min.is_finite() && a_max.is_finite()) {
        return *a_thrust_nue;
    }
    let norm = a_thrust_nue.norm();
    if norm > a_max {
        let a = &a_thrust_nue.0;
        // max/min rather than clamp: never panics on a negative a_max from a restored state.
        let up = a.y.max(-a_max).min(a_max);
        let horizontal = Vector3::new(a.x, 0.0, a.z);
        let room = (a_max * a_max - up * up).max(0.0).sqrt();
        let h_norm = horizontal.norm();
        let scale = if h_norm > room { room / h_norm } else { 1.0 };
        Nue::new(horizontal.x * scale, up, horizontal.z * scale)
    } else if norm < a_min {
        if norm > 0.0 {
            *a_thrust_nue * (a_min / norm)
        } else {
            Nue::new(0.0, a_min, 0.0)
        }
    } else {
        *a_thrust_nue
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_vanishing_mass_leaves_the_command_finite() {
        // GIVEN a mass whose thrust limits overflow to infinity
        let a = Nue::new(0.1, 1.0, -0.2);
        for mass_kg in [1e-308, 5e-324] {
            // WHEN the command is shaped THEN it stays the (finite) command
            let shaped = achievable_thrust_acceleration_nue(&a, mass_kg, 720.0, 1600.0);
            assert_eq!(shaped, a);
        }
    }

    #[test]
    fn saturation_with_crossed_limits_does_not_panic() {
        // GIVEN thrust_min > thrust_max, as a master may set them before the validation
        let a = Nue::new(0.0, 1.62, 0.0);
        // WHEN the thrust is saturated THEN it is a finite value, not a panic
        let thrust_n = thrust_magnitude_n(900.0, &a, 720.0, 489.0);
        assert!(thrust_n.is_finite());
        // AND with ordered limits it is the usual saturation
        assert_eq!(thrust_magnitude_n(900.0, &a, 720.0, 1600.0), 900.0 * 1.62);
        assert_eq!(
            thrust_magnitude_n(900.0, &(a * 10.0), 720.0, 1600.0),
            1600.0
        );
        assert_eq!(thrust_magnitude_n(900.0, &(a * 0.1), 720.0, 1600.0), 720.0);
    }

    #[test]
    fn an_achievable_command_is_left_alone() {
        let a = Nue::new(0.3, 1.62, -0.2);
        assert_eq!(
            achievable_thrust_acceleration_nue(&a, 900.0, 720.0, 1600.0),
            a
        );
    }

    #[test]
    fn above_the_maximum_the_vertical_is_kept_and_the_horizontal_shortened() {
        // GIVEN a hover (1.62 up) with a 2 m/s^2 lateral demand: 2.58 m/s^2 > 1600/900
        let a = Nue::new(1.2, 1.62, -1.6);
        let limited = achievable_thrust_acceleration_nue(&a, 900.0, 720.0, 1600.0);
        // THEN the Up component is untouched, the magnitude is the maximum, the direction of
        // the horizontal part unchanged
        assert_eq!(limited.0.y, 1.62);
        assert!((limited.norm() - 1600.0 / 900.0).abs() < 1e-12);
        assert!((limited.0.x / limited.0.z - a.0.x / a.0.z).abs() < 1e-12);
    }

    #[test]
    fn a_vertical_demand_beyond_the_maximum_becomes_full_thrust_straight_up() {
        let limited =
            achievable_thrust_acceleration_nue(&Nue::new(0.5, 5.0, 0.0), 900.0, 720.0, 1600.0);
        assert_eq!(limited, Nue::new(0.0, 1600.0 / 900.0, 0.0));
    }

    #[test]
    fn below_the_minimum_the_vector_is_lengthened_along_itself() {
        let a = Nue::new(0.1, 0.2, 0.0);
        let limited = achievable_thrust_acceleration_nue(&a, 900.0, 720.0, 1600.0);
        assert!((limited.norm() - 0.8).abs() < 1e-12);
        assert!((limited.0.normalize() - a.0.normalize()).norm() < 1e-12);
        assert_eq!(
            achievable_thrust_acceleration_nue(&Nue::zeros(), 900.0, 720.0, 1600.0),
            Nue::new(0.0, 0.8, 0.0)
        );
    }

    #[test]
    fn hovering_needs_thrust_equal_to_weight() {
        // GIVEN zero net acceleration on the Moon
        let a_t = thrust_acceleration_nue(&Nue::zeros(), 1.62);
        // THEN the engines push up with m g
        assert_eq!(a_t, Nue::new(0.0, 1.62, 0.0));
        assert!((thrust_magnitude_n(900.0, &a_t, 720.0, 1600.0) - 1458.0).abs() < 1e-9);
        assert_eq!(net_acceleration_nue(&a_t, 1.62), Nue::zeros());
    }

    #[test]
    fn thrust_is_saturated_to_the_throttle_range() {
        let up = Nue::new(0.0, 10.0, 0.0);
        assert_eq!(thrust_magnitude_n(900.0, &up, 720.0, 1600.0), 1600.0);
        assert_eq!(
            thrust_magnitude_n(900.0, &Nue::zeros(), 720.0, 1600.0),
            720.0
        );
    }
}
