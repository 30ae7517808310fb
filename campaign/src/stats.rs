//! The statistics a dispersion review reads: percentiles up to 3 sigma, the order-statistics
//! (binomial) confidence statement, and the 3-sigma dispersion ellipse of a set of points.

/// The two-sided 3-sigma probability of a normal variable, the percentile reviews quote.
pub const THREE_SIGMA: f64 = 0.9973;

/// Percentile `p` (in [0, 1]) of `values` (NaN left out) by linear interpolation between
/// order statistics (Hyndman and Fan's definition 7, numpy's default, so a reader can check
/// a `summary.csv` with `numpy.percentile`). NaN when no value is left.
pub fn percentile(values: &[f64], p: f64) -> f64 {
    let mut sorted: Vec<f64> = values.iter().copied().filter(|v| !v.is_nan()).collect();
    sorted.sort_by(f64::total_cmp);
    percentile_of_sorted(&sorted, p)
}

pub fn percentile_of_sorted(sorted: &[f64], p: f64) -> f64 {
    match sorted.len() {
        0 => f64::NAN,
        n => {
            let h = (n - 1) as f64 * p.clamp(0.0, 1.0);
            let lo = h.floor() as usize;
            let hi = (lo + 1).min(n - 1);
            sorted[lo] + (h - lo as f64) * (sorted[hi] - sorted[lo])
        }
    }
}

/// A distribution-free upper confidence bound of the `p`-quantile from `sorted` runs: the
/// smallest order statistic `x_(k)` with P(x_(k) >= q_p) >= `confidence`, that is
/// P(Binomial(n, p) <= k - 1) >= `confidence`. `None` when even the largest run does not
/// bound it that surely: the runs cannot support that percentile (the maximum of n runs
/// bounds q_p with confidence 1 - p^n; for p95 at 90 % that needs 45 runs, for p99.73 852).
pub fn quantile_upper_bound(sorted: &[f64], p: f64, confidence: f64) -> Option<f64> {
    let n = sorted.len() as u64;
    if n == 0 || binomial_cdf(n - 1, n, p) < confidence {
        return None;
    }
    // The cdf grows with k: the smallest k that reaches the confidence, by bisection.
    let (mut lo, mut hi) = (1u64, n);
    while lo < hi {
        let mid = lo + (hi - lo) / 2;
        if binomial_cdf(mid - 1, n, p) >= confidence {
            hi = mid;
        } else {
            lo = mid + 1;
        }
    }
    Some(sorted[(lo - 1) as usize])
}

/// The runs a percentile's upper bound at `confidence` needs: the smallest n with
/// 1 - p^n >= `confidence`.
pub fn runs_for_quantile_bound(p: f64, confidence: f64) -> u64 {
    ((1.0 - confidence).ln() / p.ln()).ceil() as u64
}

/// P(X <= k) for X ~ Binomial(n, q), summed in logarithms (n up to millions).
pub(crate) fn binomial_cdf(k: u64, n: u64, q: f64) -> f64 {
    if q <= 0.0 {
        return 1.0;
    }
    if q >= 1.0 {
        return if k >= n { 1.0 } else { 0.0 };
    }
    let (ln_q, ln_p) = (q.ln(), (-q).ln_1p());
    let mut ln_choose = 0.0;
    let mut sum = 0.0;
    for i in 0..=k.min(n) {
        if i > 0 {
            ln_choose += ((n - i + 1) as f64).ln() - (i as f64).ln();
        }
        sum += (ln_choose + i as f64 * ln_q + (n - i) as f64 * ln_p).exp();
    }
    sum.min(1.0)
}

/// The confidence with which `failures` in `runs` independent runs show a success
/// probability of at least `reliability`: 1 - P(at most `failures` failures | failure
/// probability 1 - reliability). With no failure this is `1 - reliability^runs` (Hanson and
/// Beard, NASA/TP-2010-216447: 0 failures in 852 runs give 99.73 % with 90 % confidence).
pub fn confidence(failures: u64, runs: u64, reliability: f64) -> f64 {
    1.0 - binomial_cdf(failures, runs, 1.0 - reliability)
}

/// The one-sided Clopper-Pearson lower bound on the success probability at `confidence`:
/// the smallest reliability R still shown with that confidence (`(1 - C)^(1/n)` with no
/// failure). Found by bisection of [`confidence`], which decreases in R.
pub fn reliability_lower_bound(failures: u64, runs: u64, confidence_level: f64) -> f64 {
    if runs == 0 || failures >= runs {
        return 0.0;
    }
    let (mut lo, mut hi) = (0.0_f64, 1.0_f64);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if confidence(failures, runs, mid) >= confidence_level {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

/// The fewest failure-free runs that show `reliability` with `confidence_level`.
pub fn runs_needed(reliability: f64, confidence_level: f64) -> u64 {
    ((1.0 - confidence_level).ln() / reliability.ln()).ceil() as u64
}

/// A dispersion ellipse in the horizontal plane (North, East).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ellipse {
    pub centre_north_m: f64,
    pub centre_east_m: f64,
    pub semi_major_m: f64,
    pub semi_minor_m: f64,
    /// Direction of the major axis, from North towards East (deg, in (-90, 90]).
    pub major_azimuth_deg: f64,
}

/// The scale of the sample covariance ellipse of `n` bivariate-normal points that holds a
/// further point with probability `p`: the normal-theory prediction region
/// `d^2 <= 2 (n + 1) (n - 1) / (n (n - 2)) F(2, n - 2; p)`, the F quantile with 2 numerator
/// degrees of freedom in closed form, `F(2, m; p) = (m / 2) ((1 - p)^(-2/m) - 1)`. It grows
/// from sqrt(-2 ln(1 - p)) (3.44 for 99.73 %, known mean and covariance) as the sample
/// shrinks: 4.31 at n = 20, 3.58 at n = 100. `n` >= 3.
pub fn prediction_ellipse_scale(n: usize, p: f64) -> f64 {
    let (n, m) = (n as f64, n as f64 - 2.0);
    let f = 0.5 * m * ((1.0 - p).powf(-2.0 / m) - 1.0);
    (2.0 * (n + 1.0) * (n - 1.0) / (n * m) * f).sqrt()
}

/// The 3-sigma ellipse of the points: centred on their mean, along the axes of their sample
/// covariance, sized to hold a further flight's point with probability 99.73 % if the points
/// are bivariate normal ([`prediction_ellipse_scale`]: the small-sample factor included; a
/// normal fit, which the report states, not a distribution-free bound). `None` with fewer
/// than 3 finite points.
pub fn three_sigma_ellipse(points: &[(f64, f64)]) -> Option<Ellipse> {
    let finite: Vec<(f64, f64)> = points
        .iter()
        .copied()
        .filter(|(n, e)| n.is_finite() && e.is_finite())
        .collect();
    if finite.len() < 3 {
        return None;
    }
    let count = finite.len() as f64;
    let mn = finite.iter().map(|p| p.0).sum::<f64>() / count;
    let me = finite.iter().map(|p| p.1).sum::<f64>() / count;
    let (mut snn, mut see, mut sne) = (0.0, 0.0, 0.0);
    for (n, e) in &finite {
        snn += (n - mn) * (n - mn);
        see += (e - me) * (e - me);
        sne += (n - mn) * (e - me);
    }
    let (snn, see, sne) = (
        snn / (count - 1.0),
        see / (count - 1.0),
        sne / (count - 1.0),
    );
    // Eigenvalues of the symmetric 2x2 covariance, and the major axis's angle from North.
    let mean = 0.5 * (snn + see);
    let radius = (0.25 * (snn - see).powi(2) + sne * sne).sqrt();
    let (major, minor) = (mean + radius, (mean - radius).max(0.0));
    let angle = 0.5 * (2.0 * sne).atan2(snn - see);
    let scale = prediction_ellipse_scale(finite.len(), THREE_SIGMA);
    Some(Ellipse {
        centre_north_m: mn,
        centre_east_m: me,
        semi_major_m: scale * major.sqrt(),
        semi_minor_m: scale * minor.sqrt(),
        major_azimuth_deg: angle.to_degrees(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentiles_interpolate_order_statistics_like_numpy() {
        let v = [4.0, 1.0, f64::NAN, 3.0, 2.0, 5.0];
        assert_eq!(percentile(&v, 0.5), 3.0);
        assert_eq!(percentile(&v, 0.95), 4.8); // numpy.percentile([1..5], 95) = 4.8
        assert_eq!(percentile(&v, 1.0), 5.0);
        assert_eq!(percentile(&v, 0.0), 1.0);
        assert!(percentile(&[f64::NAN], 0.5).is_nan());
        let hundred: Vec<f64> = (1..=100).map(f64::from).collect();
        // numpy.percentile(range(1, 101), 99.73) = 99.7327
        assert!((percentile(&hundred, THREE_SIGMA) - 99.7327).abs() < 1e-9);
    }

    #[test]
    fn a_percentile_bound_needs_the_runs_that_support_it() {
        let runs = |n: usize| (1..=n).map(|k| k as f64).collect::<Vec<f64>>();
        // p95 at 90 %: 44 runs are not enough (1 - 0.95^44 = 0.895), 45 are (0.901): the
        // bound is then the largest run.
        assert_eq!(quantile_upper_bound(&runs(44), 0.95, 0.9), None);
        assert_eq!(quantile_upper_bound(&runs(45), 0.95, 0.9), Some(45.0));
        assert_eq!(runs_for_quantile_bound(0.95, 0.9), 45);
        assert_eq!(runs_for_quantile_bound(THREE_SIGMA, 0.9), 852);
        assert_eq!(quantile_upper_bound(&runs(851), THREE_SIGMA, 0.9), None);
        assert_eq!(
            quantile_upper_bound(&runs(852), THREE_SIGMA, 0.9),
            Some(852.0)
        );
        // With many runs the bound is an order statistic just above the quantile: for 1000
        // runs the 90 % upper bound of the median is x_(521) (P(Bin(1000, .5) <= 520) =
        // 0.9026, <= 519: 0.8913).
        assert_eq!(quantile_upper_bound(&runs(1000), 0.5, 0.9), Some(521.0));
        assert_eq!(quantile_upper_bound(&[], 0.5, 0.9), None);
    }

    #[test]
    fn the_bound_covers_the_true_quantile_with_its_confidence() {
        // Uniform(0, 1) draws: q_0.95 = 0.95. Over 2,000 campaigns of 60 runs the bound must
        // lie at or above 0.95 in about 90 % of them (binomial spread: +-1.3 %).
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut uniform = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let trials = 2000;
        let covered = (0..trials)
            .filter(|_| {
                let mut v: Vec<f64> = (0..60).map(|_| uniform()).collect();
                v.sort_by(f64::total_cmp);
                quantile_upper_bound(&v, 0.95, 0.9).is_some_and(|b| b >= 0.95)
            })
            .count();
        let share = covered as f64 / f64::from(trials);
        assert!((0.89..=0.99).contains(&share), "{share}");
    }

    #[test]
    fn hanson_and_beard_852_failure_free_runs_give_99_73_percent_at_90_percent() {
        assert_eq!(runs_needed(THREE_SIGMA, 0.90), 852);
        assert!(confidence(0, 852, THREE_SIGMA) >= 0.90);
        assert!(confidence(0, 851, THREE_SIGMA) < 0.90);
        let bound = reliability_lower_bound(0, 852, 0.90);
        assert!((THREE_SIGMA..0.99731).contains(&bound), "{bound}");
        assert!((bound - 0.1f64.powf(1.0 / 852.0)).abs() < 1e-12);
    }

    #[test]
    fn with_failures_the_bound_is_clopper_pearson() {
        // One failure in 10 runs at 90 %: the R with P(F <= 1 | 10, 1 - R) = 0.10 solves
        // R^10 + 10 (1 - R) R^9 = 0.1, R = 0.6632 (tables of the binomial lower bound)
        let r = reliability_lower_bound(1, 10, 0.90);
        assert!((r.powi(10) + 10.0 * (1.0 - r) * r.powi(9) - 0.1).abs() < 1e-12);
        assert!((r - 0.6632).abs() < 1e-4, "{r}");
        // more failures, a lower bound; all failures, nothing shown
        assert!(reliability_lower_bound(2, 10, 0.90) < r);
        assert_eq!(reliability_lower_bound(10, 10, 0.90), 0.0);
        // the binomial sum stays accurate for large n
        assert!(
            (confidence(0, 1_000_000, 0.999_999) - (1.0 - 0.999_999f64.powi(1_000_000))).abs()
                < 1e-9
        );
    }

    #[test]
    fn the_prediction_scale_has_its_small_sample_factor_and_the_chi_square_limit() {
        // 4.30 at n = 20 (the review's figure), tending to sqrt(-2 ln 0.0027) = 3.44.
        assert!((prediction_ellipse_scale(20, THREE_SIGMA) - 4.306).abs() < 5e-3);
        assert!((prediction_ellipse_scale(100, THREE_SIGMA) - 3.582).abs() < 1e-3);
        let limit = (-2.0 * (1.0 - THREE_SIGMA).ln()).sqrt();
        assert!((prediction_ellipse_scale(1_000_000, THREE_SIGMA) - limit).abs() < 1e-4);
        // Coverage: of bivariate normal samples of 20, a further point falls inside the
        // ellipse in 99.73 % of trials (normal draws by Box-Muller from a xorshift).
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut uniform = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            ((state >> 11) as f64 + 0.5) / (1u64 << 53) as f64
        };
        let mut normal = || {
            let (u, v) = (uniform(), uniform());
            (
                (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos(),
                (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).sin(),
            )
        };
        let trials = 40_000;
        let mut inside = 0;
        for _ in 0..trials {
            let points: Vec<(f64, f64)> = (0..20)
                .map(|_| {
                    let (a, b) = normal();
                    (a, 0.5 * a + b)
                })
                .collect();
            let e = three_sigma_ellipse(&points).unwrap();
            let (a, b) = normal();
            let (n, east) = (a - e.centre_north_m, 0.5 * a + b - e.centre_east_m);
            let t = e.major_azimuth_deg.to_radians();
            let (along, across) = (n * t.cos() + east * t.sin(), -n * t.sin() + east * t.cos());
            if (along / e.semi_major_m).powi(2) + (across / e.semi_minor_m).powi(2) <= 1.0 {
                inside += 1;
            }
        }
        let share = f64::from(inside) / f64::from(trials);
        // Binomial spread of 40,000 trials at 0.9973: +-0.00026; 3.44 would give about 0.985.
        assert!((share - THREE_SIGMA).abs() < 0.0012, "{share}");
    }

    #[test]
    fn the_ellipse_of_points_on_known_axes() {
        // GIVEN points spread +-2 along the North-East diagonal and +-1 across it, around (5, -3)
        let (c, s) = (45f64.to_radians().cos(), 45f64.to_radians().sin());
        let mut points = Vec::new();
        for (a, b) in [(2.0, 0.0), (-2.0, 0.0), (0.0, 1.0), (0.0, -1.0)] {
            points.push((5.0 + a * c - b * s, -3.0 + a * s + b * c));
        }
        let e = three_sigma_ellipse(&points).unwrap();
        // THEN the centre, the axis direction and the sample standard deviations (sqrt(8/3),
        // sqrt(2/3)) scaled by the prediction factor of 4 points come out
        let k = prediction_ellipse_scale(4, THREE_SIGMA);
        assert!((e.centre_north_m - 5.0).abs() < 1e-12 && (e.centre_east_m + 3.0).abs() < 1e-12);
        assert!((e.major_azimuth_deg - 45.0).abs() < 1e-9, "{e:?}");
        assert!((e.semi_major_m - k * (8.0f64 / 3.0).sqrt()).abs() < 1e-12);
        assert!((e.semi_minor_m - k * (2.0f64 / 3.0).sqrt()).abs() < 1e-12);
        assert!(three_sigma_ellipse(&points[..2]).is_none());
    }
}
