//! State events inside a sub-step: where a smooth event function crosses zero.
//!
//! The event function is evaluated on the RK4 re-integration from the sub-step start with a
//! shorter step (the "dense output" of a fixed-step RK4), so the located state is exactly the
//! state the integrator would produce, and it is smooth in the step length.

/// Time resolution of the crossing, s. Far below any physical time scale of the plant,
/// still 1e3 above the round-off of a simulation time of ~200 s.
pub const CROSSING_TIME_TOLERANCE_S: f64 = 1e-11;

/// Iterations after which the search falls back to bisection only. Illinois converges
/// superlinearly; the cap keeps a pathological function from looping.
const MAX_ILLINOIS_ITERATIONS: usize = 40;

/// Finds `tau` in `(0, h]` where `g` crosses from positive to non-positive, given
/// `g_start = g(0) > 0` and `g_end = g(h) <= 0`. Returns the right end of the final bracket, so
/// that `g(tau) <= 0`: the event has happened at the returned time (it is not missed by a
/// rounding and then found again at the start of the next step), and `tau - tau_true` is at most
/// the tolerance. Regula falsi with the Illinois modification, bisection as a fallback.
pub fn find_crossing(mut g: impl FnMut(f64) -> f64, g_start: f64, g_end: f64, h: f64) -> f64 {
    debug_assert!(g_start > 0.0 && g_end <= 0.0 && h > 0.0);
    let (mut a, mut fa) = (0.0, g_start);
    let (mut b, mut fb) = (h, g_end);
    // Which end was retained last: +1 = a, -1 = b; used by the Illinois halving.
    let mut side = 0i8;
    let mut iterations = 0;
    while b - a > CROSSING_TIME_TOLERANCE_S {
        iterations += 1;
        let secant = if iterations <= MAX_ILLINOIS_ITERATIONS && fa.is_finite() && fb.is_finite() {
            (a * fb - b * fa) / (fb - fa)
        } else {
            f64::NAN
        };
        // Stay strictly inside the bracket, else bisect.
        let c = if secant > a && secant < b {
            secant
        } else {
            0.5 * (a + b)
        };
        let fc = g(c);
        if fc > 0.0 {
            a = c;
            fa = fc;
            if side == 1 {
                fb *= 0.5;
            }
            side = 1;
        } else {
            b = c;
            fb = fc;
            if side == -1 {
                fa *= 0.5;
            }
            side = -1;
        }
        if fb == 0.0 {
            break;
        }
    }
    b
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_the_root_of_a_parabola_to_the_tolerance_from_the_right() {
        // Falling body: h(t) = 3 - 0.81 t^2 over a 5 s window; root at sqrt(3 / 0.81).
        let g = |t: f64| 3.0 - 0.81 * t * t;
        let tau = find_crossing(g, g(0.0), g(5.0), 5.0);
        let exact = (3.0f64 / 0.81).sqrt();
        assert!(
            tau >= exact - 1e-15 && tau - exact <= CROSSING_TIME_TOLERANCE_S,
            "{tau} vs {exact}"
        );
        assert!(g(tau) <= 0.0);
    }

    #[test]
    fn a_root_at_the_end_of_the_window_is_returned_as_the_end() {
        let tau = find_crossing(|t| 1.0 - t, 1.0, 0.0, 1.0);
        assert!((tau - 1.0).abs() <= CROSSING_TIME_TOLERANCE_S);
    }

    #[test]
    fn a_function_flat_near_the_root_still_converges() {
        // (1 - t)^5 is so flat at its root that plain regula falsi stalls on one side.
        let g = |t: f64| (0.3 - t).powi(5);
        let tau = find_crossing(g, g(0.0), g(1.0), 1.0);
        assert!((tau - 0.3).abs() < 1e-3, "{tau}");
        assert!(g(tau) <= 0.0);
    }

    #[test]
    fn a_non_finite_value_inside_the_window_falls_back_to_bisection() {
        let g = |t: f64| {
            if (0.49..0.51).contains(&t) {
                f64::NAN
            } else {
                0.7 - t
            }
        };
        let tau = find_crossing(g, 0.7, -0.3, 1.0);
        assert!(tau.is_finite() && tau > 0.0 && tau <= 1.0);
    }
}
