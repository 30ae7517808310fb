//! Per (law, phi_cmd) statistics of a campaign's rows: what the figure's mean lines show
//! and what `harness monte-carlo` prints.
use crate::manifest::Row;
use lander::laws::Law;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Statistic {
    DescentEndPositionError,
    MaxHorizontalDeviation,
}

/// Mean, median, extremes and sample standard deviation of one metric over the flights of
/// a point that did not fail.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Moments {
    pub mean: f64,
    /// Insensitive to a minority of runs that go far off, unlike the mean.
    pub median: f64,
    pub std: f64,
    pub min: f64,
    pub max: f64,
    /// Upper bounds of the 95th and 99.73rd percentiles at 90 % confidence (order
    /// statistics); `None` where the runs cannot support them.
    pub p95_ub90: Option<f64>,
    pub p99_73_ub90: Option<f64>,
}

impl Moments {
    fn of(values: &[f64]) -> Self {
        let n = values.len() as f64;
        let mean = values.iter().sum::<f64>() / n;
        let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
        let mut sorted = values.to_vec();
        sorted.sort_by(f64::total_cmp);
        let half = sorted.len() / 2;
        let median = match sorted.len() {
            0 => f64::NAN,
            n if n % 2 == 1 => sorted[half],
            _ => 0.5 * (sorted[half - 1] + sorted[half]),
        };
        let bound =
            |p| crate::stats::quantile_upper_bound(&sorted, p, crate::summary_csv::CONFIDENCE);
        Self {
            mean,
            median,
            std: if values.len() > 1 { var.sqrt() } else { 0.0 },
            min: values.iter().copied().fold(f64::INFINITY, f64::min),
            max: values.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            p95_ub90: bound(0.95),
            p99_73_ub90: bound(crate::stats::THREE_SIGMA),
        }
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct PointSummary {
    pub law: Law,
    pub phi_cmd_deg: f64,
    pub flights: usize,
    /// Flights that ended in an error.
    pub failed: usize,
    /// Flights that did not end as the scenario expects (errors included).
    pub failed_verdicts: usize,
    /// |r - target| at the end of the polynomial descent, before the hover corrects it.
    pub descent_end_position_error_m: Moments,
    pub max_horizontal_deviation_m: Moments,
    /// The divert's statistics, when the scenario commands a retarget.
    pub divert: Option<DivertSummary>,
}

/// A point's divert statistics over its flights that did not fail.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DivertSummary {
    pub overshoot_m: Moments,
    pub cross_track_m: Moments,
    /// Over the flights that settled within 1 m of the new site.
    pub settle_time_s: Moments,
    /// Flights not within 1 m of the new site at the end of the run.
    pub unsettled: usize,
    pub peak_tilt_deg: Moments,
}

impl PointSummary {
    pub fn get(&self, statistic: Statistic) -> Moments {
        match statistic {
            Statistic::DescentEndPositionError => self.descent_end_position_error_m,
            Statistic::MaxHorizontalDeviation => self.max_horizontal_deviation_m,
        }
    }
}

/// One summary per (law, phi_cmd) present, ordered by law (by name) then phi_cmd.
pub fn summarise(rows: &[Row]) -> Vec<PointSummary> {
    let mut keys: Vec<(Law, f64)> = Vec::new();
    for row in rows {
        let key = (row.flight.law, row.flight.phi_cmd_deg);
        if !keys.contains(&key) {
            keys.push(key);
        }
    }
    keys.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
    keys.into_iter()
        .map(|(law, phi)| {
            let point: Vec<&Row> = rows
                .iter()
                .filter(|r| r.flight.law == law && r.flight.phi_cmd_deg == phi)
                .collect();
            let ok: Vec<&Row> = point
                .iter()
                .copied()
                .filter(|r| !r.end.is_error())
                .collect();
            let metric =
                |f: fn(&Row) -> f64| Moments::of(&ok.iter().map(|r| f(r)).collect::<Vec<_>>());
            PointSummary {
                law,
                phi_cmd_deg: phi,
                flights: point.len(),
                failed: point.len() - ok.len(),
                failed_verdicts: point.iter().filter(|r| !r.verdict.as_expected).count(),
                descent_end_position_error_m: metric(|r| r.metrics.descent_end_position_error_m),
                max_horizontal_deviation_m: metric(|r| r.metrics.max_horizontal_deviation_m),
                divert: divert_summary(&ok),
            }
        })
        .collect()
}

fn divert_summary(ok: &[&Row]) -> Option<DivertSummary> {
    if ok.is_empty() || ok.iter().any(|r| r.metrics.divert_overshoot_m.is_nan()) {
        return None;
    }
    let of = |f: fn(&Row) -> f64| Moments::of(&ok.iter().map(|r| f(r)).collect::<Vec<_>>());
    let settled: Vec<f64> = ok
        .iter()
        .map(|r| r.metrics.divert_settle_time_s)
        .filter(|t| t.is_finite())
        .collect();
    Some(DivertSummary {
        overshoot_m: of(|r| r.metrics.divert_overshoot_m),
        cross_track_m: of(|r| r.metrics.divert_cross_track_m),
        settle_time_s: Moments::of(&settled),
        unsettled: ok.len() - settled.len(),
        peak_tilt_deg: of(|r| r.metrics.divert_peak_tilt_rad.to_degrees()),
    })
}

/// The divert block of [`table`], for the points that have one.
fn divert_table(summary: &[PointSummary]) -> String {
    use std::fmt::Write;
    let mut out = format!(
        "\n{:<19} {:^21}  {:^21}  {:^30}  {:^21}\n{:<19} {:>10} {:>10}  {:>10} {:>10}  {:>10} {:>10} {:>8}  {:>10} {:>10}\n",
        "divert",
        "overshoot (m)",
        "cross-track (m)",
        "within 1 m for good after (s)",
        "peak tilt (deg)",
        "law      phi(deg)",
        "median",
        "max",
        "median",
        "max",
        "median",
        "max",
        "never",
        "median",
        "max",
    );
    for s in summary {
        let Some(d) = s.divert else { continue };
        let settle = |x: f64| {
            if d.unsettled == s.flights - s.failed {
                "-".to_owned()
            } else {
                format!("{x:.2}")
            }
        };
        let _ = writeln!(
            out,
            "{:<10} {:>8.1} {:>10.3} {:>10.3}  {:>10.3} {:>10.3}  {:>10} {:>10} {:>8}  {:>10.2} {:>10.2}",
            s.law.name(),
            s.phi_cmd_deg,
            d.overshoot_m.median,
            d.overshoot_m.max,
            d.cross_track_m.median,
            d.cross_track_m.max,
            settle(d.settle_time_s.median),
            settle(d.settle_time_s.max),
            d.unsettled,
            d.peak_tilt_deg.median,
            d.peak_tilt_deg.max,
        );
    }
    out
}

/// The summary as a text table: median, mean and maximum of each metric per point, and the
/// descent deviation's p95 and p99.73 as upper bounds at 90 % confidence where the runs
/// support them (the footer says how many runs each needs).
pub fn table(summary: &[PointSummary]) -> String {
    use std::fmt::Write;
    let mut out = format!(
        "{:<10} {:>8} {:>7} {:>6}  {:^32}  {:^54}\n{:<35}  {:>10} {:>10} {:>10}  {:>10} {:>10} {:>10} {:>10} {:>10}\n",
        "law",
        "phi(deg)",
        "flights",
        "not ok",
        "end-of-descent position error (m)",
        "max horizontal deviation (m)",
        "",
        "median",
        "mean",
        "max",
        "median",
        "mean",
        "max",
        "p95<=",
        "p99.73<=",
    );
    let shown = |b: Option<f64>| b.map_or_else(|| "-".to_owned(), |x| format!("{x:.3}"));
    for s in summary {
        let (t, d) = (s.descent_end_position_error_m, s.max_horizontal_deviation_m);
        let _ = writeln!(
            out,
            "{:<10} {:>8.1} {:>7} {:>6}  {:>10.4} {:>10.4} {:>10.4}  {:>10.3} {:>10.3} {:>10.3} {:>10} {:>10}",
            s.law.name(),
            s.phi_cmd_deg,
            s.flights,
            s.failed_verdicts,
            t.median,
            t.mean,
            t.max,
            d.median,
            d.mean,
            d.max,
            shown(d.p95_ub90),
            shown(d.p99_73_ub90),
        );
    }
    let confidence = crate::summary_csv::CONFIDENCE;
    let _ = writeln!(
        out,
        "p95<=, p99.73<=: the smallest run that exceeds the percentile with {:.0} % confidence; \
         '-' where the runs cannot support it: p95 needs {} runs per point, p99.73 {}",
        100.0 * confidence,
        crate::stats::runs_for_quantile_bound(0.95, confidence),
        crate::stats::runs_for_quantile_bound(crate::stats::THREE_SIGMA, confidence)
    );
    if summary.iter().any(|s| s.divert.is_some()) {
        out.push_str(&divert_table(summary));
        let _ = writeln!(
            out,
            "divert: from the retarget command on; overshoot past the new site along the line \
             from the position at the command, cross-track off that line; 'never': flights \
             not within 1 m of the new site at the end (the settling time's median and \
             maximum are over the others)"
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn moments_of_known_samples() {
        let m = Moments::of(&[4.0, 1.0, 300.0, 2.0, 3.0]);
        assert_eq!((m.median, m.mean, m.min, m.max), (3.0, 62.0, 1.0, 300.0));
        let m = Moments::of(&[2.0, 4.0]);
        assert_eq!(m.median, 3.0);
        assert!((m.std - 2f64.sqrt()).abs() < 1e-15);
        assert!(Moments::of(&[]).median.is_nan());
        // Five runs support no tail percentile; 1,000 support both (p99.73's bound is an
        // order statistic of the top ones).
        assert_eq!((m.p95_ub90, m.p99_73_ub90), (None, None));
        let many: Vec<f64> = (1..=1000).map(f64::from).collect();
        let m = Moments::of(&many);
        // The 960th: the smallest k with P(Binomial(1000, 0.95) <= k - 1) >= 0.9.
        assert_eq!(m.p95_ub90, Some(960.0));
        assert!(m.p99_73_ub90.is_some_and(|b| b > 997.3 && b <= 1000.0));
    }

    #[test]
    fn the_printed_table_gives_tail_bounds_only_where_supported_and_says_what_they_need() {
        let row = |p95_ub90, p99_73_ub90| PointSummary {
            law: Law::DECOUPLED,
            phi_cmd_deg: 150.0,
            flights: 30,
            failed: 0,
            failed_verdicts: 0,
            descent_end_position_error_m: Moments::of(&[1.0, 2.0]),
            max_horizontal_deviation_m: Moments {
                p95_ub90,
                p99_73_ub90,
                ..Moments::of(&[1.0, 2.0])
            },
            divert: None,
        };
        let text = table(&[row(None, None), row(Some(12.5), None)]);
        assert!(!text.contains("divert"), "{text}");
        let lines: Vec<&str> = text.lines().collect();
        assert!(lines[2].ends_with("         -          -"), "{text}");
        assert!(lines[3].ends_with("    12.500          -"), "{text}");
        assert!(
            text.contains("p95 needs 45 runs per point, p99.73 852"),
            "{text}"
        );
        assert!(
            !text.contains("p99.73 ") || !text.contains("p99.73 = "),
            "{text}"
        );
    }
}
