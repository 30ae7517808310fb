//! What both methods share about step sizes: the first one, the smallest one, where a step
//! toward t_stop lands, and how often a step may be retried.

use crate::eval::Eval;
use crate::norm::scaled_rms;
use crate::{SolverError, Tolerances};

/// Attempts (error-test or Newton failures) at one step before giving up. Each failure at
/// least halves the step (BDF) or cuts it to 0.9 or less (Tsitouras), so this is reached only
/// when the step would have to shrink by far more than any discontinuity needs.
pub(crate) const MAX_ATTEMPTS: u32 = 60;

/// A step this much longer than the one proposed is taken to land on t_stop exactly, rather
/// than leaving a sliver of a step before it.
const STRETCH: f64 = 1.01;

/// Steps shorter than this at `t` change `t` by only a few units in the last place: the
/// solver could no longer tell where it is.
pub(crate) fn min_step(t: f64) -> f64 {
    10.0 * (t.abs().next_up() - t.abs())
}

/// The step from `t` toward `t_stop` for a proposed size `h`: `(h, t_new, lands)`. A step that
/// lands has `t_new` equal to `t_stop` bit for bit (not `t + h`, which may round past it).
/// The returned h is always t_new - t as the floats have it, so that the method integrates
/// over the interval the time actually advances by, also where t is large and t + h rounds.
pub(crate) fn toward(t: f64, h: f64, t_stop: f64) -> (f64, f64, bool) {
    let remaining = t_stop - t;
    if h * STRETCH >= remaining {
        (remaining, t_stop, true)
    } else {
        let t_new = t + h;
        (t_new - t, t_new, false)
    }
}

/// Hairer, Norsett & Wanner's starting step (Solving ODEs I, II.4): the step for which an
/// explicit Euler step would change f by about 1% in the error norm, refined by one probe
/// evaluation of f. `order` is that of the method's error estimate. Nothing beyond
/// t0 + h_max is evaluated: the first stop time may be a time event of the FMU.
pub(crate) fn initial_step(
    eval: &mut Eval<'_>,
    t0: f64,
    y0: &[f64],
    f0: &[f64],
    order: u32,
    tol: &Tolerances,
    h_max: f64,
) -> Result<f64, SolverError> {
    let scale: Vec<f64> = y0
        .iter()
        .map(|y| tol.absolute + tol.relative * y.abs())
        .collect();
    let d0 = scaled_rms(y0, &scale);
    let d1 = scaled_rms(f0, &scale);
    let h0 = if d0 < 1e-5 || d1 < 1e-5 {
        1e-6
    } else {
        0.01 * d0 / d1
    }
    .min(h_max);
    let y1: Vec<f64> = y0.iter().zip(f0).map(|(y, f)| y + h0 * f).collect();
    let mut f1 = vec![0.0; y0.len()];
    eval.rhs(t0 + h0, &y1, &mut f1)?;
    let df: Vec<f64> = f1.iter().zip(f0).map(|(a, b)| a - b).collect();
    let d2 = scaled_rms(&df, &scale) / h0;
    let d = d1.max(d2);
    let h1 = if d <= 1e-15 {
        (h0 * 1e-3).max(1e-6)
    } else {
        libm::pow(0.01 / d, 1.0 / f64::from(order + 1))
    };
    Ok((100.0 * h0).min(h1).min(h_max))
}

/// Step-size factor after a rejected step of a method whose error estimate has `order`:
/// the factor that would have met the tolerance, with a safety margin, never growing and at
/// most a fivefold cut. A non-finite error gets the largest cut.
pub(crate) fn reject_factor(err: f64, order: u32) -> f64 {
    if !err.is_finite() {
        return MIN_FACTOR;
    }
    (SAFETY * libm::pow(err, -1.0 / f64::from(order + 1))).clamp(MIN_FACTOR, SAFETY)
}

pub(crate) const SAFETY: f64 = 0.9;
pub(crate) const MIN_FACTOR: f64 = 0.2;
const MAX_FACTOR: f64 = 10.0;

/// Gustafsson's PI step-size controller with Hairer's DOPRI5 gains: the previous step's error
/// enters so that the step size does not oscillate between accepted and rejected steps.
#[derive(Clone, Debug)]
pub(crate) struct PiControl {
    alpha: f64,
    beta: f64,
    err_prev: f64,
}

impl PiControl {
    /// For a method whose error estimate has order `order` (4 for Tsitouras 5(4)).
    pub fn new(order: u32) -> Self {
        let beta = 0.04;
        Self {
            alpha: 1.0 / f64::from(order + 1) - 0.75 * beta,
            beta,
            // A small "previous error" damps the growth of the first step.
            err_prev: 1e-4,
        }
    }

    /// Factor for the next step after an accepted one with error `err` (<= 1). Right after a
    /// rejection the step may not grow: the rejected size was just shown to be too large.
    pub fn accept_factor(&mut self, err: f64, after_rejection: bool) -> f64 {
        let err = err.max(1e-10);
        let factor = SAFETY * libm::pow(err, -self.alpha) * libm::pow(self.err_prev, self.beta);
        self.err_prev = err.max(1e-4);
        let max = if after_rejection { 1.0 } else { MAX_FACTOR };
        factor.clamp(MIN_FACTOR, max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_step_that_reaches_t_stop_lands_on_it_bit_exactly() {
        let t = 0.1 + 0.2;
        let t_stop = 0.7;
        let (h, t_new, lands) = toward(t, 10.0, t_stop);
        assert!(lands);
        assert_eq!(t_new.to_bits(), t_stop.to_bits());
        assert_eq!(h, t_stop - t);
        // Within the stretch it lands rather than leave a sliver.
        assert!(toward(0.0, 0.995, 1.0).2);
        let (h, t_new, lands) = toward(0.0, 0.5, 1.0);
        assert_eq!((h, t_new, lands), (0.5, 0.5, false));
        // At 1e9 the floats are 1.2e-7 apart: the step is what t + h rounds to.
        let (h, t_new, _) = toward(1e9, 0.01, 1e9 + 1.0);
        assert_eq!(h, t_new - 1e9);
        assert_ne!(h, 0.01);
    }

    #[test]
    fn factors_stay_in_bounds() {
        assert_eq!(reject_factor(f64::NAN, 4), MIN_FACTOR);
        assert_eq!(reject_factor(f64::INFINITY, 4), MIN_FACTOR);
        assert!(reject_factor(1.0 + 1e-12, 4) <= SAFETY);
        let mut pi = PiControl::new(4);
        assert_eq!(pi.accept_factor(0.0, false), MAX_FACTOR);
        assert!(pi.accept_factor(0.0, true) <= 1.0);
        assert!(pi.accept_factor(1.0, false) < 1.0);
        assert!(min_step(0.0) > 0.0 && min_step(1e9) > 1e-7 && min_step(1e9) < 1e-5);
    }
}
