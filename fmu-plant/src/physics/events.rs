//! State events inside a sub-step: where a smooth event function crosses zero.
//!
//! The event function is evaluated on the RK4 re-integration from the sub-step start with a
//! shorter step (the "dense output" of a fixed-step RK4), so the located state is exactly the
//! state the integrator would produce, and it is smooth in the step length.
//!
//! # Termination
//! The search ends for every finite input. Its resolution is [`crossing_tolerance_s`]: the
//! absolute [`CROSSING_TIME_TOLERANCE_S`] at everyday times, but never finer than
//! [`CROSSING_TIME_RELATIVE_TOLERANCE`] times the simulation time or the window length, since
//! beyond 2^16 s adjacent doubles are farther apart than 1e-11 s and a finer bracket cannot
//! exist. A bracket whose midpoint rounds onto one of its ends also ends the search, and
//! [`MAX_ITERATIONS`] bounds it whatever the arithmetic does.

/// Time resolution of the crossing at everyday times, s. Far below any physical time scale of
/// the plant, still 1e3 above the round-off of a simulation time of ~200 s.
pub const CROSSING_TIME_TOLERANCE_S: f64 = 1e-11;

/// Resolution of the crossing relative to the time (and to the window), where the absolute
/// tolerance is below what doubles can resolve: 8 ulps.
pub const CROSSING_TIME_RELATIVE_TOLERANCE: f64 = 8.0 * f64::EPSILON;

/// Iterations after which the search falls back to bisection only. Illinois converges
/// superlinearly; the cap keeps a pathological function from looping.
const MAX_ILLINOIS_ITERATIONS: usize = 40;

/// Hard bound on the iterations: bisection exhausts the doubles of any bracket in fewer
/// than 2100 halvings, so this is only reached if the arithmetic misbehaves.
pub const MAX_ITERATIONS: usize = 4096;

/// The finest time resolution that makes sense at simulation time `t_s` (see the module
/// documentation). An infinite `t_s` gives an infinite tolerance, which ends any loop
/// comparing against it at once; a NaN `t_s` gives the absolute tolerance.
#[inline]
pub fn crossing_tolerance_s(t_s: f64) -> f64 {
    CROSSING_TIME_TOLERANCE_S.max(CROSSING_TIME_RELATIVE_TOLERANCE * t_s.abs())
}

/// Finds `tau` in `(0, h]` where `g` crosses from positive to non-positive, given
/// `g_start = g(0) > 0` and `g_end = g(h) <= 0`; `t_s` is the simulation time of the window's
/// start (it sets the resolution, see [`crossing_tolerance_s`]). Returns the right end of the
/// final bracket, so that `g(tau) <= 0`: the event has happened at the returned time (it is
/// not missed by a rounding and then found again at the start of the next step), and
/// `tau - tau_true` is at most the tolerance. Regula falsi with the Illinois modification,
/// bisection as a fallback.
pub fn find_crossing(
    mut g: impl FnMut(f64) -> f64,
    g_start: f64,
    g_end: f64,
    h: f64,
    t_s: f64,
) -> f64 {
    debug_assert!(g_start > 0.0 && g_end <= 0.0 && h > 0.0);
    let tolerance = crossing_tolerance_s(t_s).max(CROSSING_TIME_RELATIVE_TOLERANCE * h);
    let (mut a, mut fa) = (0.0, g_start);
    let (mut b, mut fb) = (h, g_end);
    // Which end was retained last: +1 = a, -1 = b; used by the Illinois halving.
    let mut side = 0i8;
    let mut iterations = 0;
    while b - a > tolerance && iterations < MAX_ITERATIONS {
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
        if !(c > a && c < b) {
            // No double lies strictly inside: the bracket is as fine as it can be.
            break;
        }
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
// std's functions here are a reference independent of the libm the model uses.
#[allow(clippy::disallowed_methods)]
mod tests {
    use super::*;

    #[test]
    fn finds_the_root_of_a_parabola_to_the_tolerance_from_the_right() {
        // Falling body: h(t) = 3 - 0.81 t^2 over a 5 s window; root at sqrt(3 / 0.81).
        let g = |t: f64| 3.0 - 0.81 * t * t;
        let tau = find_crossing(g, g(0.0), g(5.0), 5.0, 0.0);
        let exact = (3.0f64 / 0.81).sqrt();
        assert!(
            tau >= exact - 1e-15 && tau - exact <= CROSSING_TIME_TOLERANCE_S,
            "{tau} vs {exact}"
        );
        assert!(g(tau) <= 0.0);
    }

    #[test]
    fn a_root_at_the_end_of_the_window_is_returned_as_the_end() {
        let tau = find_crossing(|t| 1.0 - t, 1.0, 0.0, 1.0, 0.0);
        assert!((tau - 1.0).abs() <= CROSSING_TIME_TOLERANCE_S);
    }

    #[test]
    fn a_function_flat_near_the_root_still_converges() {
        // (1 - t)^5 is so flat at its root that plain regula falsi stalls on one side.
        let g = |t: f64| (0.3 - t).powi(5);
        let tau = find_crossing(g, g(0.0), g(1.0), 1.0, 0.0);
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
        let tau = find_crossing(g, 0.7, -0.3, 1.0, 0.0);
        assert!(tau.is_finite() && tau > 0.0 && tau <= 1.0);
    }

    /// Runs `f` on a thread and fails if it has not finished within `limit_s`: a hang would
    /// otherwise never report.
    fn within<T: Send + 'static>(limit_s: u64, f: impl FnOnce() -> T + Send + 'static) -> T {
        let (tx, rx) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            let _ = tx.send(f());
        });
        rx.recv_timeout(std::time::Duration::from_secs(limit_s))
            .expect("the crossing search did not end (watchdog)")
    }

    #[test]
    fn the_tolerance_is_absolute_at_everyday_times_and_relative_beyond() {
        assert_eq!(crossing_tolerance_s(200.0), CROSSING_TIME_TOLERANCE_S);
        let t = 2f64.powi(40);
        assert_eq!(
            crossing_tolerance_s(t),
            CROSSING_TIME_RELATIVE_TOLERANCE * t
        );
        assert_eq!(crossing_tolerance_s(f64::INFINITY), f64::INFINITY);
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(512))]
        /// An event function computed the way the plant computes it, from absolute times:
        /// `(t + root) - (t + s)` is a staircase once `t` is large, the worst case for a
        /// search that wants a bracket finer than the spacing of the doubles.
        #[test]
        fn the_search_ends_at_every_time_magnitude_and_window_length(
            log_t in -3.0f64..300.0,
            log_h in -12.0f64..300.0,
            fraction in 0.0f64..1.0,
        ) {
            let (t, h) = (10f64.powf(log_t), 10f64.powf(log_h));
            let root = (fraction * h).max(f64::MIN_POSITIVE);
            let g = move |s: f64| (t + root) - (t + s);
            let (g0, g1) = (g(0.0), g(h));
            proptest::prop_assume!(g0 > 0.0 && g1 <= 0.0);
            let tau = within(10, move || find_crossing(g, g0, g1, h, t));
            // The crossing is inside the window, on its far side, within the resolution.
            proptest::prop_assert!(tau > 0.0 && tau <= h, "tau = {tau}");
            proptest::prop_assert!(g(tau) <= 0.0);
            let resolution = crossing_tolerance_s(t).max(CROSSING_TIME_RELATIVE_TOLERANCE * h);
            proptest::prop_assert!(
                tau - root <= resolution + 2.0 * f64::EPSILON * t,
                "tau = {tau}, root = {root}, resolution = {resolution}"
            );
        }
    }

    #[test]
    fn a_window_wider_than_the_absolute_tolerance_can_resolve_still_ends() {
        // A 1e10 s window: the doubles near its end are 2e-6 apart, far above 1e-11.
        let g = |s: f64| 0.7e10 - s;
        let tau = within(10, move || find_crossing(g, g(0.0), g(1e10), 1e10, 0.0));
        assert!((tau - 0.7e10).abs() <= CROSSING_TIME_RELATIVE_TOLERANCE * 1e10);
    }
}
