//! Per (law, phi_cmd) statistics of a campaign's rows: what the figure's mean lines show
//! and what `harness monte-carlo` prints.
use super::manifest::Row;
use crate::scenarios::Law;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Statistic {
    TerminalPositionError,
    MaxHorizontalDeviation,
}

/// Mean, extremes and sample standard deviation of one metric over the flights of a point
/// that did not fail.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Moments {
    pub mean: f64,
    pub std: f64,
    pub min: f64,
    pub max: f64,
}

impl Moments {
    fn of(values: &[f64]) -> Self {
        let n = values.len() as f64;
        let mean = values.iter().sum::<f64>() / n;
        let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
        Self {
            mean,
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
    pub failed: usize,
    pub terminal_position_error_m: Moments,
    pub max_horizontal_deviation_m: Moments,
}

impl PointSummary {
    pub fn get(&self, statistic: Statistic) -> Moments {
        match statistic {
            Statistic::TerminalPositionError => self.terminal_position_error_m,
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
                terminal_position_error_m: metric(|r| r.metrics.terminal_position_error_m),
                max_horizontal_deviation_m: metric(|r| r.metrics.max_horizontal_deviation_m),
            }
        })
        .collect()
}

/// The summary as a text table.
pub fn table(summary: &[PointSummary]) -> String {
    use std::fmt::Write;
    let mut out = format!(
        "{:<10} {:>8} {:>7} {:>6}  {:>22}  {:>22}\n",
        "law",
        "phi(deg)",
        "flights",
        "failed",
        "terminal err mean/max (m)",
        "max horiz dev mean/max (m)"
    );
    for s in summary {
        let _ = writeln!(
            out,
            "{:<10} {:>8.1} {:>7} {:>6}  {:>11.4} {:>11.4}  {:>11.3} {:>11.3}",
            s.law.name(),
            s.phi_cmd_deg,
            s.flights,
            s.failed,
            s.terminal_position_error_m.mean,
            s.terminal_position_error_m.max,
            s.max_horizontal_deviation_m.mean,
            s.max_horizontal_deviation_m.max,
        );
    }
    out
}
