//! The error of one signal group over one communication interval `k` (from `t_k` to
//! `t_k+1`):
//!
//! ```text
//! e_k = bias + w_k + n_k
//! n_k = noise_sigma * N_k                           white, a new sample every interval
//! w_0 = 0,  w_k+1 = w_k + random_walk * sqrt(h_k / 1 s) * M_k+1     random walk
//! ```
//! with `N_k`, `M_k` the standard normal draws of interval `k` and `h_k` the length of
//! interval `k`: the walk's variance at `t_k` is `random_walk^2 (t_k - t_0) / 1 s`.
use super::draws::Draws;
use super::parameters::{Group, GroupErrors};
use serde::{Deserialize, Serialize};

/// The random parts of a group's error during one interval.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct GroupError {
    pub walk: [f64; 3],
    pub white: [f64; 3],
}

impl GroupError {
    /// The error of the first interval: no walk yet.
    pub fn first(errors: &GroupErrors, group: Group, draws: &Draws) -> GroupError {
        GroupError {
            walk: [0.0; 3],
            white: draws.white[group as usize].map(|n| errors.noise_sigma * n),
        }
    }

    /// The error of the next interval, after an interval of `h_s` seconds.
    pub fn next(&self, errors: &GroupErrors, group: Group, draws: &Draws, h_s: f64) -> GroupError {
        let walk_sigma = errors.random_walk * h_s.sqrt();
        let walk_draws = draws.walk[group as usize];
        GroupError {
            walk: std::array::from_fn(|i| self.walk[i] + walk_sigma * walk_draws[i]),
            white: draws.white[group as usize].map(|n| errors.noise_sigma * n),
        }
    }

    /// Total error on each axis.
    pub fn total(&self, errors: &GroupErrors) -> [f64; 3] {
        std::array::from_fn(|i| errors.bias[i] + self.walk[i] + self.white[i])
    }
}

/// A value with its error added, then rounded to the quantum. A zero error leaves the value
/// untouched (`-0.0 + 0.0` would be `+0.0`), so with every error off the output is the
/// input bit for bit.
///
/// Near the largest f64 a finite value plus a finite error can overflow; the estimate then
/// saturates at the largest finite value of its sign (an overflowing sensor reads full
/// scale), so an output is never infinite.
pub fn corrupt(value: f64, error: f64, quantum: f64) -> f64 {
    let erroneous = if error != 0.0 {
        (value + error).clamp(-f64::MAX, f64::MAX)
    } else {
        value
    };
    if quantum > 0.0 {
        quantise(erroneous, quantum)
    } else {
        erroneous
    }
}

/// The multiple of `quantum` nearest to `value` (halves away from zero). A quantum so fine
/// that `value / quantum` overflows is below the resolution of `value` itself: the value is
/// returned as it is rather than as infinity. Near the largest f64 the nearest multiple may
/// not be representable (found by the fuzzer: 1.8e308 in quanta of 8e295); then the next
/// multiple towards zero, and if rounding the product overflows that too (1.8e308 in quanta
/// of 1.3e213, found next), the value as it is.
pub fn quantise(value: f64, quantum: f64) -> f64 {
    let steps = value / quantum;
    if !steps.is_finite() {
        return value;
    }
    [steps.round() * quantum, steps.trunc() * quantum]
        .into_iter()
        .find(|q| q.is_finite())
        .unwrap_or(value)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_zero_error_keeps_the_sign_of_zero_and_every_bit() {
        for value in [-0.0, 0.0, 5e-324, -1.5e300, 800.0] {
            assert_eq!(corrupt(value, 0.0, 0.0).to_bits(), value.to_bits());
            assert_eq!(corrupt(value, -0.0, 0.0).to_bits(), value.to_bits());
        }
    }

    #[test]
    fn quantisation_rounds_to_the_nearest_multiple() {
        assert_eq!(quantise(0.26, 0.5), 0.5);
        assert_eq!(quantise(-0.74, 0.5), -0.5);
        assert_eq!(quantise(1.0, 0.25), 1.0);
        assert_eq!(corrupt(1.0, 0.3, 0.5), 1.5);
    }

    #[test]
    fn values_near_the_largest_f64_stay_finite() {
        // The fuzzer's case: a bias of f64::MAX on a rate, quantised in steps of 8.04e295.
        let q = corrupt(0.0, f64::MAX, 8.040407952793562e295);
        assert!(q.is_finite() && q > 1.79e308, "{q}");
        // And the next one: an input of f64::MAX in quanta of 1.28e213, where even the
        // multiple towards zero rounds beyond f64::MAX.
        let q = quantise(f64::MAX, 1.2791103236040028e213);
        assert_eq!(q, f64::MAX);
        // A finite value plus a finite error that overflows saturates.
        assert_eq!(corrupt(1e308, 1e308, 0.0), f64::MAX);
        assert_eq!(corrupt(-1e308, -1e308, 0.0), -f64::MAX);
        assert!(corrupt(-1e308, -1e308, 1e300).is_finite());
    }

    #[test]
    fn a_quantum_finer_than_the_value_resolves_leaves_it_finite() {
        for value in [800.0, -1e300, 5e-324] {
            let q = quantise(value, 5e-324);
            assert!(
                q.is_finite() && (q - value).abs() <= 2.5e-324,
                "{value}: {q}"
            );
        }
    }
}
