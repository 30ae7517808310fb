//! Per (law, phi_cmd) statistics of a campaign's rows: what the figure's mean lines show
//! and what `harness monte-carlo` prints.
use super::manifest::Row;
use crate::scenarios::Law;

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
        Self {
            mean,
            median,
            std: if values.len() > 1 { var.sqrt() } else { 0.0 },
            min: values.iter().copied().fold(f64::INFINITY, f64::min),
            max: values.iter().copied().fold(f64::NEG_INFINITY, f64::max),
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
}

impl PointSummary {
    pub fn get(&self, statistic: Statistic) -> Moments {
        match statistic {
            Statistic::DescentEndPositionError => self.descent_end_position_error_m,
            Statistic::MaxHorizontalDeviation => self.max_horizontal_deviation_m,
        }
    }
}

/// One summary per (law, phi_cmd) present, ordered by law then phi_cmd.
pub fn summarise(rows: &[Row]) -> Vec<PointSummary> {
    let mut keys: Vec<(Law, f64)> = Vec::new();
    for row in rows {
        let key = (row.flight.law, row.flight.phi_cmd_deg);
        if !keys.contains(&key) {
            keys.push(key);
        }
    }
    keys.sort_by(|a, b| (a.0 as i32).cmp(&(b.0 as i32)).then(a.1.total_cmp(&b.1)));
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
            }
        })
        .collect()
}

/// The summary as a text table: median, mean and maximum of each metric per point.
pub fn table(summary: &[PointSummary]) -> String {
    use std::fmt::Write;
    let mut out = format!(
        "{:<10} {:>8} {:>7} {:>6}  {:^32}  {:^32}\n{:<35}  {:>10} {:>10} {:>10}  {:>10} {:>10} {:>10}\n",
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
    );
    for s in summary {
        let (t, d) = (s.descent_end_position_error_m, s.max_horizontal_deviation_m);
        let _ = writeln!(
            out,
            "{:<10} {:>8.1} {:>7} {:>6}  {:>10.4} {:>10.4} {:>10.4}  {:>10.3} {:>10.3} {:>10.3}",
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
    }
}
