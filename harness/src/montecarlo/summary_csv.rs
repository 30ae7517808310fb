//! `summary.csv`: one row per cell (law x phi_cmd) of a campaign, what a dispersion review
//! reads: runs, errors and failed verdicts, the order-statistics confidence statement for the
//! scenario's requirement, the 3-sigma dispersion ellipse of the touchdown points (or, without
//! touchdowns, of the end-of-descent points), and p50 / p95 / p99.73 / max of every metric.
use super::manifest::{self, Row, METRIC_NAMES};
use super::stats::{self, THREE_SIGMA};
use crate::scenarios::Law;
use crate::verdict::Expect;
use std::path::Path;

pub const FILE_NAME: &str = "summary.csv";

/// The confidence level of the statement's reliability bound.
pub const CONFIDENCE: f64 = 0.90;

const PERCENTILES: [(&str, f64); 3] = [("p50", 0.5), ("p95", 0.95), ("p99_73", THREE_SIGMA)];

/// The requirement the confidence statement is about.
pub fn requirement(expect: Expect) -> &'static str {
    match expect {
        Expect::Landed => "touchdown inside the envelope",
        Expect::Completed => "completes without touchdown or error",
    }
}

pub fn header() -> Vec<String> {
    let mut h: Vec<String> = [
        "law",
        "phi_cmd_deg",
        "runs",
        "errors",
        "failed_verdicts",
        "requirement",
        "reliability_lower_bound_at_90pct",
        "confidence_of_99_73pct",
        "statement",
        "ellipse_of",
        "ellipse_points",
        "ellipse_centre_north_m",
        "ellipse_centre_east_m",
        "ellipse_semi_major_m",
        "ellipse_semi_minor_m",
        "ellipse_major_azimuth_deg",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    for name in METRIC_NAMES {
        for (p, _) in PERCENTILES {
            h.push(format!("{name}_{p}"));
        }
        h.push(format!("{name}_max"));
    }
    h
}

/// "0 failures in 852 runs: touchdown inside the envelope holds in >= 99.73 % of cases with
/// 90 % confidence".
pub fn statement(failures: u64, runs: u64, expect: Expect) -> String {
    let bound = stats::reliability_lower_bound(failures, runs, CONFIDENCE);
    let needed = stats::runs_needed(THREE_SIGMA, CONFIDENCE);
    let mut text = format!(
        "{failures} failures in {runs} runs: '{}' holds in >= {:.2} % of cases with {:.0} % \
         confidence",
        requirement(expect),
        100.0 * bound,
        100.0 * CONFIDENCE
    );
    if failures == 0 && runs < needed {
        text += &format!(" (99.73 % at 90 % needs {needed} failure-free runs)");
    }
    text
}

fn number(x: f64) -> String {
    if x.is_finite() {
        ryu::Buffer::new().format_finite(x).to_owned()
    } else {
        x.to_string()
    }
}

/// The cells present, ordered by law then phi_cmd.
fn cells(rows: &[Row]) -> Vec<(Law, f64)> {
    let mut keys: Vec<(Law, f64)> = Vec::new();
    for row in rows {
        let key = (row.flight.law, row.flight.phi_cmd_deg);
        if !keys.contains(&key) {
            keys.push(key);
        }
    }
    keys.sort_by(|a, b| (a.0 as i32).cmp(&(b.0 as i32)).then(a.1.total_cmp(&b.1)));
    keys
}

/// The records of `summary.csv`, one per cell.
pub fn records(rows: &[Row], expect: Expect) -> Vec<Vec<String>> {
    cells(rows)
        .into_iter()
        .map(|(law, phi)| {
            let cell: Vec<&Row> = rows
                .iter()
                .filter(|r| r.flight.law == law && r.flight.phi_cmd_deg == phi)
                .collect();
            let runs = cell.len() as u64;
            let errors = cell.iter().filter(|r| r.end.is_error()).count() as u64;
            let failures = cell.iter().filter(|r| !r.verdict.as_expected).count() as u64;
            let touchdowns: Vec<(f64, f64)> = cell
                .iter()
                .map(|r| (r.metrics.touchdown_north_m, r.metrics.touchdown_east_m))
                .filter(|(n, e)| n.is_finite() && e.is_finite())
                .collect();
            let (of, points) = if touchdowns.len() >= 3 {
                ("touchdown", touchdowns)
            } else {
                let ends = cell
                    .iter()
                    .map(|r| (r.metrics.descent_end_north_m, r.metrics.descent_end_east_m))
                    .filter(|(n, e)| n.is_finite() && e.is_finite())
                    .collect();
                ("descent_end", ends)
            };
            let ellipse = stats::three_sigma_ellipse(&points);
            let e = |f: fn(&stats::Ellipse) -> f64| number(ellipse.as_ref().map_or(f64::NAN, f));
            let mut record = vec![
                law.name().to_owned(),
                number(phi),
                runs.to_string(),
                errors.to_string(),
                failures.to_string(),
                requirement(expect).to_owned(),
                number(stats::reliability_lower_bound(failures, runs, CONFIDENCE)),
                number(stats::confidence(failures, runs, THREE_SIGMA)),
                statement(failures, runs, expect),
                of.to_owned(),
                points.len().to_string(),
                e(|x| x.centre_north_m),
                e(|x| x.centre_east_m),
                e(|x| x.semi_major_m),
                e(|x| x.semi_minor_m),
                e(|x| x.major_azimuth_deg),
            ];
            let values: Vec<[f64; manifest::METRIC_COUNT]> = cell
                .iter()
                .map(|r| manifest::metric_values(&r.metrics))
                .collect();
            for k in 0..METRIC_NAMES.len() {
                let mut column: Vec<f64> = values
                    .iter()
                    .map(|v| v[k])
                    .filter(|v| !v.is_nan())
                    .collect();
                column.sort_by(f64::total_cmp);
                for (_, p) in PERCENTILES {
                    record.push(number(stats::percentile_of_sorted(&column, p)));
                }
                record.push(number(column.last().copied().unwrap_or(f64::NAN)));
            }
            record
        })
        .collect()
}

/// Writes `summary.csv` into `dir`.
pub fn write(rows: &[Row], expect: Expect, dir: &Path) -> anyhow::Result<std::path::PathBuf> {
    let path = dir.join(FILE_NAME);
    let mut out = csv::Writer::from_path(&path)?;
    out.write_record(header())?;
    for record in records(rows, expect) {
        out.write_record(&record)?;
    }
    out.flush()?;
    Ok(path)
}

/// The flights that did not end as expected, one line each (for the terminal and the report).
pub fn failed_lines(rows: &[Row]) -> Vec<String> {
    rows.iter()
        .filter(|r| !r.verdict.as_expected)
        .map(|r| {
            let f = &r.flight;
            let why = match &r.end {
                manifest::End::Error { message } => message.clone(),
                _ => r.verdict.detail.clone(),
            };
            format!(
                "flight {} (run {}, {}, phi_cmd {} deg): {}{}{}",
                f.index,
                f.run,
                f.law.name(),
                f.phi_cmd_deg,
                r.verdict.word,
                if why.is_empty() { "" } else { ": " },
                why
            )
        })
        .collect()
}
