//! What drives each metric, and how two laws differ on the same landers.
//!
//! - **Sensitivity**: for each metric of a cell, the Spearman rank correlation with each
//!   dispersed input and the partial rank correlation coefficient (PRCC: the correlation of
//!   the ranks once the linear effect of every other input's ranks is removed), ranked by
//!   |PRCC|. An input counts as influential when its PRCC differs from zero at the 5 % level
//!   (Fisher's z with `n - 3 - (k - 1)` degrees of freedom for `k` inputs). Rank-based, so a
//!   monotone effect of any shape is found and an outlying flight weighs like any other.
//! - **Paired law difference**: every law flies the same draws (common random numbers), so
//!   the difference of a metric between two laws on the same run removes the draw's own
//!   effect. Given: the median of the run-by-run differences with its distribution-free 90 %
//!   confidence interval (order statistics of Binomial(n, 1/2), the sign test's interval),
//!   and on how many runs the law scored lower.
use crate::dispersion::Dispersion;
use crate::manifest::Row;
use crate::stats;
use lander::laws::Law;
use lander::metrics;

/// How an input is read from a run's draw.
pub type Input = fn(&Dispersion) -> f64;

/// The dispersed inputs a sensitivity is computed for: each drawn quantity whose size can
/// drive a metric monotonically, signed (for signed metrics such as an end point's North
/// offset) and, where the dispersion is symmetric, as a horizontal magnitude too (a
/// deviation grows with the size of a velocity error whatever its sign). Azimuths are left
/// out; a tilt or a misalignment is given by its angle. Names as in the manifest, or saying
/// the magnitude taken.
pub const INPUTS: [(&str, Input); 20] = [
    ("delta_r0_nue_m[1]", |d| d.delta_r0_nue_m[0]),
    ("delta_r0_nue_m[2]", |d| d.delta_r0_nue_m[1]),
    ("delta_r0_nue_m[3]", |d| d.delta_r0_nue_m[2]),
    ("delta_r0_horizontal_m", |d| {
        d.delta_r0_nue_m[0].hypot(d.delta_r0_nue_m[2])
    }),
    ("delta_v0_nue_mps[1]", |d| d.delta_v0_nue_mps[0]),
    ("delta_v0_nue_mps[2]", |d| d.delta_v0_nue_mps[1]),
    ("delta_v0_nue_mps[3]", |d| d.delta_v0_nue_mps[2]),
    ("delta_v0_horizontal_mps", |d| {
        d.delta_v0_nue_mps[0].hypot(d.delta_v0_nue_mps[2])
    }),
    ("tilt_deg", |d| d.tilt_rad.to_degrees()),
    ("roll_about_thrust_rad", |d| d.roll_about_thrust_rad),
    ("abs_roll_about_thrust_rad", |d| {
        d.roll_about_thrust_rad.abs()
    }),
    ("delta_omega0_body_radps[1]", |d| {
        d.delta_omega0_body_radps[0]
    }),
    ("delta_omega0_body_radps[2]", |d| {
        d.delta_omega0_body_radps[1]
    }),
    ("delta_omega0_body_radps[3]", |d| {
        d.delta_omega0_body_radps[2]
    }),
    ("m0_scale", |d| d.m0_scale),
    ("inertia_scale[1]", |d| d.inertia_scale[0]),
    ("inertia_scale[2]", |d| d.inertia_scale[1]),
    ("inertia_scale[3]", |d| d.inertia_scale[2]),
    ("thrust_misalignment_deg", |d| {
        d.thrust_misalignment_rad.to_degrees()
    }),
    ("thrust_scale", |d| d.thrust_scale),
];

/// The two-sided 5 % point of the standard normal distribution.
const Z_5_PERCENT: f64 = 1.959_963_984_540_054;

/// The confidence of the paired difference's interval.
pub const PAIRED_CONFIDENCE: f64 = 0.90;

/// One input's effect on one metric.
#[derive(Debug, Clone, PartialEq)]
pub struct Sensitivity {
    pub input: &'static str,
    pub spearman: f64,
    pub prcc: f64,
    /// PRCC nonzero at the 5 % level.
    pub significant: bool,
}

/// Ranks 1..=n, ties given the mean of the ranks they share.
pub fn ranks(values: &[f64]) -> Vec<f64> {
    let mut order: Vec<usize> = (0..values.len()).collect();
    order.sort_by(|&a, &b| values[a].total_cmp(&values[b]));
    let mut ranks = vec![0.0; values.len()];
    let mut i = 0;
    while i < order.len() {
        let mut j = i;
        while j + 1 < order.len() && values[order[j + 1]] == values[order[i]] {
            j += 1;
        }
        let mean = (i + j) as f64 / 2.0 + 1.0;
        for &k in &order[i..=j] {
            ranks[k] = mean;
        }
        i = j + 1;
    }
    ranks
}

/// Pearson's correlation; NaN when either side does not vary.
pub fn pearson(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len() as f64;
    let (ma, mb) = (a.iter().sum::<f64>() / n, b.iter().sum::<f64>() / n);
    let (mut sab, mut saa, mut sbb) = (0.0, 0.0, 0.0);
    for (x, y) in a.iter().zip(b) {
        sab += (x - ma) * (y - mb);
        saa += (x - ma) * (x - ma);
        sbb += (y - mb) * (y - mb);
    }
    if saa == 0.0 || sbb == 0.0 {
        return f64::NAN;
    }
    (sab / (saa * sbb).sqrt()).clamp(-1.0, 1.0)
}

pub fn spearman(x: &[f64], y: &[f64]) -> f64 {
    pearson(&ranks(x), &ranks(y))
}

/// The inverse of a small symmetric positive definite matrix (Gauss-Jordan with partial
/// pivoting); `None` when it is singular to working precision (a pivot below 1e-12 of the
/// largest diagonal element).
fn inverse(mut a: Vec<Vec<f64>>) -> Option<Vec<Vec<f64>>> {
    let n = a.len();
    let scale = (0..n).map(|i| a[i][i].abs()).fold(0.0, f64::max);
    let mut inv: Vec<Vec<f64>> = (0..n)
        .map(|i| (0..n).map(|j| f64::from(u8::from(i == j))).collect())
        .collect();
    for col in 0..n {
        let pivot = (col..n).max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))?;
        if a[pivot][col].abs() <= 1e-12 * scale {
            return None;
        }
        a.swap(col, pivot);
        inv.swap(col, pivot);
        let p = a[col][col];
        for j in 0..n {
            a[col][j] /= p;
            inv[col][j] /= p;
        }
        for i in 0..n {
            if i != col {
                let f = a[i][col];
                if f != 0.0 {
                    for j in 0..n {
                        a[i][j] -= f * a[col][j];
                        inv[i][j] -= f * inv[col][j];
                    }
                }
            }
        }
    }
    Some(inv)
}

/// The residual of `v` after its least-squares fit on the (centred) columns `basis`; `None`
/// when the basis is collinear.
fn residual(basis: &[Vec<f64>], v: &[f64]) -> Option<Vec<f64>> {
    let m = basis.len();
    let n = v.len() as f64;
    let mean = v.iter().sum::<f64>() / n;
    let v: Vec<f64> = v.iter().map(|x| x - mean).collect();
    if m == 0 {
        return Some(v);
    }
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let gram: Vec<Vec<f64>> = basis
        .iter()
        .map(|a| basis.iter().map(|b| dot(a, b)).collect())
        .collect();
    let inverse = inverse(gram)?;
    let projections: Vec<f64> = basis.iter().map(|b| dot(b, &v)).collect();
    let beta: Vec<f64> = inverse.iter().map(|row| dot(row, &projections)).collect();
    Some(
        (0..v.len())
            .map(|t| v[t] - (0..m).map(|i| beta[i] * basis[i][t]).sum::<f64>())
            .collect(),
    )
}

/// The PRCC of each input (columns of `inputs`) with `y`: the correlation of the residuals of
/// the input's ranks and of `y`'s ranks after each is fitted on the ranks of all the other
/// inputs. NaN for every input when the runs are too few (`n <= inputs + 2`), for one whose
/// ranks the others explain entirely.
pub fn prcc(inputs: &[Vec<f64>], y: &[f64]) -> Vec<f64> {
    let k = inputs.len();
    let n = y.len();
    if n <= k + 2 {
        return vec![f64::NAN; k];
    }
    let centred = |v: Vec<f64>| {
        let mean = v.iter().sum::<f64>() / v.len() as f64;
        v.into_iter().map(|x| x - mean).collect::<Vec<f64>>()
    };
    let columns: Vec<Vec<f64>> = inputs.iter().map(|x| centred(ranks(x))).collect();
    let y = ranks(y);
    (0..k)
        .map(|i| {
            let others: Vec<Vec<f64>> = (0..k)
                .filter(|&j| j != i)
                .map(|j| columns[j].clone())
                .collect();
            match (residual(&others, &columns[i]), residual(&others, &y)) {
                (Some(rx), Some(ry)) => pearson(&rx, &ry),
                _ => f64::NAN,
            }
        })
        .collect()
}

/// Whether a partial correlation `r` over `n` runs controlling for `controlled` other
/// inputs differs from zero at the 5 % level (Fisher's z).
fn significant(r: f64, n: usize, controlled: usize) -> bool {
    let dof = n as f64 - 3.0 - controlled as f64;
    r.is_finite() && dof > 0.0 && (r.atanh() * dof.sqrt()).abs() > Z_5_PERCENT
}

/// The sensitivities of metric `k` over `rows` (runs with a finite value of it), ranked by
/// |PRCC|, then |Spearman|; inputs that do not vary in these runs are left out.
pub fn sensitivities(rows: &[&Row], k: usize) -> Vec<Sensitivity> {
    let used: Vec<(&Row, f64)> = rows
        .iter()
        .map(|r| (*r, metrics::metric_values(&r.metrics)[k]))
        .filter(|(_, y)| y.is_finite())
        .collect();
    let y: Vec<f64> = used.iter().map(|(_, y)| *y).collect();
    let mut names = Vec::new();
    let mut columns = Vec::new();
    for (name, input) in INPUTS {
        let column: Vec<f64> = used.iter().map(|(r, _)| input(&r.dispersion)).collect();
        if column.iter().any(|v| *v != column[0]) {
            names.push(name);
            columns.push(column);
        }
    }
    let partial = prcc(&columns, &y);
    let mut out: Vec<Sensitivity> = names
        .iter()
        .zip(&columns)
        .zip(partial)
        .map(|((name, x), prcc)| Sensitivity {
            input: name,
            spearman: spearman(x, &y),
            prcc,
            significant: significant(prcc, y.len(), names.len().saturating_sub(1)),
        })
        .collect();
    let key = |s: &Sensitivity| (s.prcc.abs(), s.spearman.abs());
    out.sort_by(|a, b| {
        let (ka, kb) = (key(a), key(b));
        kb.0.total_cmp(&ka.0).then(kb.1.total_cmp(&ka.1))
    });
    out
}

/// The influential inputs of a ranking as one field: `tilt_deg +0.93; m0_scale -0.41`
/// (PRCC, significant ones only, at most `most`); `none` when no input is influential,
/// empty when the runs are too few for a PRCC.
pub fn ranking_text(ranking: &[Sensitivity], most: usize) -> String {
    if ranking.iter().all(|s| s.prcc.is_nan()) {
        return String::new();
    }
    let shown: Vec<String> = ranking
        .iter()
        .filter(|s| s.significant)
        .take(most)
        .map(|s| format!("{} {:+.2}", s.input, s.prcc))
        .collect();
    if shown.is_empty() {
        "none".into()
    } else {
        shown.join("; ")
    }
}

/// A law against another on the same runs, for one metric.
#[derive(Debug, Clone, PartialEq)]
pub struct Paired {
    pub against: Law,
    /// Runs where both laws have a finite value.
    pub runs: usize,
    /// Median of (this law - the other), run by run.
    pub median_difference: f64,
    /// Distribution-free [`PAIRED_CONFIDENCE`] interval of that median; NaN when the runs
    /// are too few for one (fewer than 5 at 90 %).
    pub low: f64,
    pub high: f64,
    /// Runs on which this law's value is lower.
    pub lower: usize,
}

/// The order statistics `(j, n + 1 - j)` (1-based) that bracket the median of `n` values
/// with at least `confidence`: the largest `j` with `2 P(Bin(n, 1/2) <= j - 1) <= 1 -
/// confidence`.
pub fn median_interval_ranks(n: u64, confidence: f64) -> Option<(u64, u64)> {
    let alpha = 1.0 - confidence;
    let mut j = 0;
    while j < n / 2 && 2.0 * stats::binomial_cdf(j, n, 0.5) <= alpha {
        j += 1;
    }
    (j >= 1).then_some((j, n + 1 - j))
}

/// Metric `k` of `this` against `other`, paired by run.
pub fn paired(this: &[&Row], other: &[&Row], against: Law, k: usize) -> Paired {
    let mut differences: Vec<f64> = this
        .iter()
        .filter_map(|a| {
            let b = other.iter().find(|b| b.flight.run == a.flight.run)?;
            let d = metrics::metric_values(&a.metrics)[k] - metrics::metric_values(&b.metrics)[k];
            d.is_finite().then_some(d)
        })
        .collect();
    differences.sort_by(f64::total_cmp);
    let n = differences.len();
    let (low, high) = match median_interval_ranks(n as u64, PAIRED_CONFIDENCE) {
        Some((j, m)) => (differences[j as usize - 1], differences[m as usize - 1]),
        None => (f64::NAN, f64::NAN),
    };
    Paired {
        against,
        runs: n,
        median_difference: stats::percentile_of_sorted(&differences, 0.5),
        low,
        high,
        lower: differences.iter().filter(|d| **d < 0.0).count(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranks_share_ties() {
        assert_eq!(ranks(&[3.0, 1.0, 3.0, 2.0]), [3.5, 1.0, 3.5, 2.0]);
    }

    #[test]
    fn spearman_sees_any_monotone_effect_and_its_sign() {
        let x: Vec<f64> = (0..50).map(|i| i as f64 * 0.1).collect();
        let y: Vec<f64> = x.iter().map(|v| (3.0 * v).exp()).collect();
        assert_eq!(spearman(&x, &y), 1.0);
        let y: Vec<f64> = x.iter().map(|v| -v * v * v).collect();
        assert_eq!(spearman(&x, &y), -1.0);
        assert!(spearman(&x, &vec![1.0; 50]).is_nan());
    }

    /// Independent uniform columns, seeded.
    fn column(n: usize, seed: u64) -> Vec<f64> {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        (0..n).map(|_| rng.gen::<f64>()).collect()
    }

    #[test]
    fn prcc_separates_a_strong_from_a_weak_input_and_an_irrelevant_one() {
        let n = 400;
        let (x1, x2, x3) = (column(n, 1), column(n, 2), column(n, 3));
        // y = 10 x1 + x2, x3 does not enter.
        let y: Vec<f64> = (0..n).map(|i| 10.0 * x1[i] + x2[i]).collect();
        let p = prcc(&[x1.clone(), x2.clone(), x3.clone()], &y);
        assert!(p[0] > 0.95, "{p:?}");
        // Once x1 is removed, x2 explains what is left: its partial correlation is high
        // though its plain correlation is small.
        assert!(p[1] > 0.5 && spearman(&x2, &y) < 0.3, "{p:?}");
        assert!(p[2].abs() < 0.1, "{p:?}");
        assert!(significant(p[1], n, 2) && !significant(p[2], n, 2));
    }

    #[test]
    fn a_metric_one_input_determines_has_a_prcc_of_one() {
        let (x1, x2) = (column(50, 1), column(50, 2));
        let y: Vec<f64> = x1.iter().map(|v| v.powi(3)).collect();
        let p = prcc(&[x1.clone(), x2], &y);
        assert!((p[0] - 1.0).abs() < 1e-12, "{p:?}");
        assert_eq!(prcc(std::slice::from_ref(&x1), &y), [1.0]);
    }

    #[test]
    fn prcc_needs_more_runs_than_inputs() {
        let x = vec![column(4, 1), column(4, 2)];
        assert!(prcc(&x, &[1.0, 2.0, 3.0, 4.0]).iter().all(|p| p.is_nan()));
    }

    #[test]
    fn the_median_interval_has_its_binomial_coverage() {
        // n = 10 at 90 %: P(Bin(10, 1/2) <= 1) = 11/1024, doubled 0.021 <= 0.1, and
        // P(<= 2) = 56/1024, doubled 0.109 > 0.1: the 2nd and 9th values.
        assert_eq!(median_interval_ranks(10, 0.9), Some((2, 9)));
        // n = 4: even the extremes cover the median with only 1 - 2/16 = 87.5 %.
        assert_eq!(median_interval_ranks(4, 0.9), None);
        assert_eq!(median_interval_ranks(5, 0.9), Some((1, 5)));
        for n in 5..200 {
            let (j, m) = median_interval_ranks(n, 0.9).unwrap();
            let coverage = 1.0 - 2.0 * stats::binomial_cdf(j - 1, n, 0.5);
            assert!(coverage >= 0.9, "n = {n}");
            assert!(1.0 - 2.0 * stats::binomial_cdf(j, n, 0.5) < 0.9 || j + 1 > n / 2);
            assert_eq!(j + m, n + 1);
        }
    }

    #[test]
    fn the_ranking_text_names_only_influential_inputs() {
        let s = |input, prcc, significant| Sensitivity {
            input,
            spearman: prcc,
            prcc,
            significant,
        };
        let ranking = [
            s("tilt_deg", 0.931, true),
            s("m0_scale", -0.41, true),
            s("x", 0.05, false),
        ];
        assert_eq!(ranking_text(&ranking, 3), "tilt_deg +0.93; m0_scale -0.41");
        assert_eq!(ranking_text(&ranking, 1), "tilt_deg +0.93");
        assert_eq!(ranking_text(&ranking[2..], 3), "none");
        assert_eq!(ranking_text(&[s("x", f64::NAN, false)], 3), "");
    }
}
