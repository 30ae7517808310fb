//! Fixed-step classical Runge-Kutta (RK4) and the sub-step schedule of a communication step.
//!
//! RK4 with a fixed step is what the paper's 100 Hz simulator uses and it makes a run
//! bit-reproducible for a given step schedule; the global error is O(h^4).
use nalgebra::SVector;

/// A state that can be advanced along a derivative of the same shape.
pub trait OdeState: Sized {
    /// `self + h * derivative`.
    fn add_scaled(&self, h: f64, derivative: &Self) -> Self;
}

impl<const N: usize> OdeState for SVector<f64, N> {
    #[inline]
    fn add_scaled(&self, h: f64, derivative: &Self) -> Self {
        self + derivative * h
    }
}

/// One classical RK4 step of size `h` from `(t, x)` for `x' = f(t, x)`.
#[inline(always)]
pub fn rk4_step<S: OdeState>(f: impl Fn(f64, &S) -> S, t: f64, x: &S, h: f64) -> S {
    let half = 0.5 * h;
    // `x + h/6 k1 + h/3 k2 + h/3 k3 + h/6 k4`, summed left to right as each stage is known:
    // the same operations in the same order, with one stage held at a time instead of four.
    let k1 = f(t, x);
    let y = x.add_scaled(h / 6.0, &k1);
    let k2 = f(t + half, &x.add_scaled(half, &k1));
    let y = y.add_scaled(h / 3.0, &k2);
    let k3 = f(t + half, &x.add_scaled(half, &k2));
    let y = y.add_scaled(h / 3.0, &k3);
    let k4 = f(t + h, &x.add_scaled(h, &k3));
    y.add_scaled(h / 6.0, &k4)
}

/// [`rk4_step`] that also integrates `q` along the step: `f` returns the derivative and the
/// integrand at each stage, and the second element is `h/6 (q1 + 2 q2 + 2 q3 + q4)`, what RK4
/// gives for an added state `y' = q(t, x)` (the state's arithmetic is `rk4_step`'s, bit for bit).
#[inline(always)]
pub fn rk4_step_with_quadrature<S: OdeState, Q>(
    f: impl Fn(f64, &S) -> (S, Q),
    t: f64,
    x: &S,
    h: f64,
) -> (S, Q)
where
    Q: Copy + std::ops::Add<Output = Q> + std::ops::Mul<f64, Output = Q>,
{
    let half = 0.5 * h;
    // Summed as each stage is known, as in `rk4_step`.
    let (k1, q1) = f(t, x);
    let y = x.add_scaled(h / 6.0, &k1);
    let (k2, q2) = f(t + half, &x.add_scaled(half, &k1));
    let y = y.add_scaled(h / 3.0, &k2);
    let (k3, q3) = f(t + half, &x.add_scaled(half, &k2));
    let y = y.add_scaled(h / 3.0, &k3);
    let q23 = q2 + q3;
    let (k4, q4) = f(t + h, &x.add_scaled(h, &k3));
    let y = y.add_scaled(h / 6.0, &k4);
    (y, (q1 + q4) * (h / 6.0) + q23 * (h / 3.0))
}

/// A remainder shorter than this fraction of the sub-step is merged into the previous
/// sub-step instead of becoming a sub-step of its own: `h / h_sub` carries rounding
/// (0.1 / 0.01 = 10.000000000000002) and a 1e-18 s RK4 step would only add round-off.
const REMAINDER_MERGE_FRACTION: f64 = 1e-9;

/// The sub-step sizes covering a communication step `h > 0` with sub-steps of at most
/// `h_sub > 0`: full sub-steps, the last one shortened so that they sum to `h` (the last
/// end time is taken as `t + h` by the caller, not accumulated).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SubSteps {
    /// Number of sub-steps (>= 1).
    pub count: usize,
    /// Size of every sub-step but the last.
    pub size: f64,
    /// Size of the last sub-step (`<= size` up to the merge fraction).
    pub last: f64,
}

impl SubSteps {
    #[inline]
    pub fn new(h: f64, h_sub: f64) -> Self {
        // The common case (the communication step is one sub-step, up to the rounding of a
        // master's `(t + h) - t`): what the general rule below gives for it, without its
        // division and floor. For `h_sub <= h <= 2 h_sub` the difference is exact, and it is
        // the rule's remainder with one full sub-step.
        if h - h_sub <= REMAINDER_MERGE_FRACTION * h_sub {
            return Self {
                count: 1,
                size: h_sub,
                last: h,
            };
        }
        let ratio = h / h_sub;
        let full = (ratio + REMAINDER_MERGE_FRACTION).floor().max(0.0);
        let remainder = h - full * h_sub;
        if full >= 1.0 && remainder <= REMAINDER_MERGE_FRACTION * h_sub {
            let count = full as usize;
            Self {
                count,
                size: h_sub,
                last: h - (count - 1) as f64 * h_sub,
            }
        } else {
            Self {
                count: full as usize + 1,
                size: h_sub,
                last: remainder,
            }
        }
    }

    /// Start time offset (from the communication-step start) and size of sub-step `k`.
    #[inline]
    pub fn get(&self, k: usize) -> (f64, f64) {
        let offset = k as f64 * self.size;
        if k + 1 == self.count {
            (offset, self.last)
        } else {
            (offset, self.size)
        }
    }
}

#[cfg(test)]
// std's functions here are a reference independent of the libm the model uses.
#[allow(clippy::disallowed_methods)]
mod tests {
    use super::*;
    use nalgebra::Vector2;

    #[test]
    fn sub_steps_cover_the_step_exactly_with_a_shortened_last_one() {
        for (h, h_sub, count) in [
            (0.01, 0.01, 1),
            (0.1, 0.01, 10),
            (0.015, 0.01, 2),
            (0.004, 0.01, 1),
            (0.3, 0.1, 3),
            (1.0, 0.3, 4),
        ] {
            let s = SubSteps::new(h, h_sub);
            assert_eq!(s.count, count, "h = {h}, h_sub = {h_sub}");
            let total: f64 = (0..s.count).map(|k| s.get(k).1).sum();
            assert!(
                (total - h).abs() <= 4.0 * f64::EPSILON * h,
                "h = {h}: {total}"
            );
            assert!(s.last > 0.0 && s.last <= h_sub * (1.0 + 1e-9));
        }
    }

    #[test]
    fn the_one_sub_step_shortcut_agrees_with_the_general_rule() {
        // The general rule, written out without the shortcut.
        let general = |h: f64, h_sub: f64| {
            let full = (h / h_sub + REMAINDER_MERGE_FRACTION).floor().max(0.0);
            let remainder = h - full * h_sub;
            if full >= 1.0 && remainder <= REMAINDER_MERGE_FRACTION * h_sub {
                (full as usize, h - (full - 1.0) * h_sub)
            } else {
                (full as usize + 1, remainder)
            }
        };
        let h_sub: f64 = 0.01;
        let mut cases = vec![
            h_sub,
            0.004,
            1e-300,
            (17.2 + 0.01) - 17.2,
            (0.03 + 0.01) - 0.03,
        ];
        let mut h = h_sub;
        for _ in 0..64 {
            h = f64::from_bits(h.to_bits() + (1 << 20));
            cases.push(h);
            cases.push(f64::from_bits(
                h_sub.to_bits() - (h.to_bits() - h_sub.to_bits()),
            ));
        }
        for h in cases {
            let s = SubSteps::new(h, h_sub);
            let (count, last) = general(h, h_sub);
            assert_eq!(
                (s.count, s.last.to_bits()),
                (count, last.to_bits()),
                "h = {h:e}"
            );
        }
    }

    #[test]
    fn rk4_integrates_a_cubic_exactly() {
        // RK4 is exact for polynomials of degree <= 4 in t; x' = 3 t^2 gives x = t^3.
        let x = rk4_step(
            |t, _x: &Vector2<f64>| Vector2::new(3.0 * t * t, 0.0),
            1.0,
            &Vector2::new(1.0, 0.0),
            0.5,
        );
        assert!((x[0] - 1.5f64.powi(3)).abs() < 1e-14);
    }

    #[test]
    fn rk4_local_error_of_the_exponential_matches_the_taylor_remainder() {
        // exp(h) - RK4(h) = h^5/120 + O(h^6) for x' = x, x(0) = 1.
        let h = 0.05;
        let x = rk4_step(|_t, x: &Vector2<f64>| *x, 0.0, &Vector2::new(1.0, 0.0), h);
        let err = h.exp() - x[0];
        let predicted = h.powi(5) / 120.0;
        assert!((err / predicted - 1.0).abs() < 0.05, "{err} vs {predicted}");
    }
}
