//! Median and spread of repeated measurements.
//!
//! Every figure of the table is a median over samples (batch means, or whole runs), with
//! the 10th and 90th percentiles as its spread: a shared machine adds occasional slow
//! outliers, which move a mean but not a median.
use serde::{Deserialize, Serialize};

/// Median and 10th/90th percentiles of a set of samples.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    pub median: f64,
    pub p10: f64,
    pub p90: f64,
    pub count: usize,
}

impl Summary {
    /// `None` for no samples or any non-finite sample (a measurement that went wrong
    /// must not turn into a plausible figure).
    pub fn of(samples: &[f64]) -> Option<Self> {
        if samples.is_empty() || samples.iter().any(|x| !x.is_finite()) {
            return None;
        }
        let mut sorted = samples.to_vec();
        sorted.sort_by(f64::total_cmp);
        Some(Self {
            median: percentile(&sorted, 0.5),
            p10: percentile(&sorted, 0.1),
            p90: percentile(&sorted, 0.9),
            count: sorted.len(),
        })
    }

    /// The same figures less `cost` (a fixed overhead included in every sample).
    pub fn less(self, cost: f64) -> Self {
        Self {
            median: self.median - cost,
            p10: self.p10 - cost,
            p90: self.p90 - cost,
            count: self.count,
        }
    }

    /// The same figures multiplied by `factor` (a change of unit).
    pub fn scaled(self, factor: f64) -> Self {
        Self {
            median: self.median * factor,
            p10: self.p10 * factor,
            p90: self.p90 * factor,
            count: self.count,
        }
    }
}

/// The `p` quantile of sorted samples, interpolating linearly between order statistics
/// (the usual "type 7" definition, as numpy's default), so a median of an even count is the
/// mean of the two middle samples.
fn percentile(sorted: &[f64], p: f64) -> f64 {
    let position = p * (sorted.len() - 1) as f64;
    let below = position.floor() as usize;
    let above = position.ceil() as usize;
    let weight = position - below as f64;
    sorted[below] + weight * (sorted[above] - sorted[below])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_of_an_odd_count_is_the_middle_sample_in_any_order() {
        let summary = Summary::of(&[9.0, 1.0, 5.0, 3.0, 7.0]).unwrap();
        assert_eq!(summary.median, 5.0);
        assert_eq!(summary.count, 5);
    }

    #[test]
    fn median_of_an_even_count_is_the_mean_of_the_two_middle_samples() {
        assert_eq!(Summary::of(&[4.0, 1.0, 3.0, 2.0]).unwrap().median, 2.5);
    }

    #[test]
    fn percentiles_of_0_to_10_are_1_and_9() {
        let samples: Vec<f64> = (0..=10).rev().map(f64::from).collect();
        let summary = Summary::of(&samples).unwrap();
        assert_eq!((summary.p10, summary.median, summary.p90), (1.0, 5.0, 9.0));
    }

    #[test]
    fn one_sample_is_its_own_median_and_spread() {
        let summary = Summary::of(&[2.5]).unwrap();
        assert_eq!((summary.p10, summary.median, summary.p90), (2.5, 2.5, 2.5));
    }

    #[test]
    fn a_single_outlier_does_not_move_the_median() {
        let mut samples = vec![1.0; 20];
        samples.push(1e6);
        assert_eq!(Summary::of(&samples).unwrap().median, 1.0);
    }

    #[test]
    fn an_overhead_is_taken_off_every_figure_but_not_the_count() {
        let summary = Summary::of(&[1.0, 2.0, 3.0]).unwrap().less(0.5);
        assert_eq!((summary.median, summary.p10, summary.p90), (1.5, 0.7, 2.3));
        assert_eq!(summary.count, 3);
    }

    #[test]
    fn no_samples_or_a_non_finite_sample_give_no_summary() {
        assert_eq!(Summary::of(&[]), None);
        assert_eq!(Summary::of(&[1.0, f64::NAN]), None);
        assert_eq!(Summary::of(&[1.0, f64::INFINITY]), None);
    }

    #[test]
    fn scaling_changes_every_figure_but_not_the_count() {
        let summary = Summary::of(&[1.0, 2.0, 3.0]).unwrap().scaled(1e3);
        for (got, want) in [
            (summary.median, 2e3),
            (summary.p10, 1.2e3),
            (summary.p90, 2.8e3),
        ] {
            assert!((got - want).abs() < 1e-9, "{got} != {want}");
        }
        assert_eq!(summary.count, 3);
    }
}
