//! `summary.csv`: one row per cell (law x phi_cmd) of a campaign, what a dispersion review
//! reads: runs, errors and failed verdicts, the order-statistics confidence statement for the
//! scenario's requirement, the 3-sigma dispersion ellipse of the touchdown points (or, without
//! touchdowns, of the end-of-descent points), and of every metric the median, the maximum and
//! the 90 %-confidence upper bounds of its 95th, 99th and 99.73rd percentiles where the cell's
//! runs support them (empty where they do not: 45, 230 and 852 runs are needed); of every
//! metric too,
//! the inputs that drive it (significant partial rank correlations, strongest first) and the
//! cell's law against the reference law on the same runs (median difference and its
//! distribution-free 90 % interval; the reference is the coupled law when the campaign flies
//! it, else its first law).
use crate::analysis;
use crate::manifest::{self, Row};
use crate::stats::{self, THREE_SIGMA};
use lander::laws::Law;
use lander::metrics::{self, METRIC_NAMES};
use lander::verdict::Expect;
use std::path::Path;

pub const FILE_NAME: &str = "summary.csv";

/// The confidence level of the statement's reliability bound.
pub const CONFIDENCE: f64 = 0.90;

/// The tail percentiles given as upper confidence bounds (order statistics), at
/// [`CONFIDENCE`]: `<metric>_p95_ub90`, `<metric>_p99_ub90`, `<metric>_p99_73_ub90`.
const BOUNDED_PERCENTILES: [(&str, f64); 3] = [
    ("p95_ub90", 0.95),
    ("p99_ub90", 0.99),
    ("p99_73_ub90", THREE_SIGMA),
];

/// The requirement the confidence statement is about: the scenario's expected end, and its
/// `requirements` `[[requirement]]` entries when it has any.
pub fn requirement(expect: Expect, requirements: usize) -> String {
    let end = match expect {
        Expect::Landed => "touchdown inside the envelope",
        Expect::Completed => "completes without touchdown or error",
        Expect::Stopped => "an FMU ends the run before the stop time",
    };
    match requirements {
        0 => end.to_owned(),
        1 => format!("{end}, meeting its requirement"),
        n => format!("{end}, meeting its {n} requirements"),
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
        "paired_against",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    for name in METRIC_NAMES {
        h.push(format!("{name}_p50"));
        for (p, _) in BOUNDED_PERCENTILES {
            h.push(format!("{name}_{p}"));
        }
        h.push(format!("{name}_max"));
        h.push(format!("{name}_influential_inputs"));
        for column in ["paired_median_diff", "paired_ci90_low", "paired_ci90_high"] {
            h.push(format!("{name}_{column}"));
        }
    }
    h
}

/// How many influential inputs a `<metric>_influential_inputs` field names at most.
const INFLUENTIAL_SHOWN: usize = 3;

/// The law the others are paired against: coupled when the campaign flies it (the classical
/// law the paper improves on), else the first law.
pub fn reference_law(cells: &[(Law, f64)]) -> Option<Law> {
    cells
        .iter()
        .map(|c| c.0)
        .find(|l| *l == Law::COUPLED)
        .or(cells.first().map(|c| c.0))
}

/// "0 failures in 852 runs: touchdown inside the envelope holds in >= 99.73 % of cases with
/// 90 % confidence".
pub fn statement(failures: u64, runs: u64, expect: Expect, requirements: usize) -> String {
    let bound = stats::reliability_lower_bound(failures, runs, CONFIDENCE);
    let needed = stats::runs_needed(THREE_SIGMA, CONFIDENCE);
    let mut text = format!(
        "{failures} failures in {runs} runs: '{}' holds in >= {:.2} % of cases with {:.0} % \
         confidence",
        requirement(expect, requirements),
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

/// The cells present, ordered by law (by name) then phi_cmd.
fn cells(rows: &[Row]) -> Vec<(Law, f64)> {
    let mut keys: Vec<(Law, f64)> = Vec::new();
    for row in rows {
        let key = (row.flight.law, row.flight.phi_cmd_deg);
        if !keys.contains(&key) {
            keys.push(key);
        }
    }
    keys.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
    keys
}

/// The records of `summary.csv`, one per cell.
pub fn records(rows: &[Row], expect: Expect, requirements: usize) -> Vec<Vec<String>> {
    let cells = cells(rows);
    let reference = reference_law(&cells);
    let of = |law: Law, phi: f64| -> Vec<&Row> {
        rows.iter()
            .filter(|r| r.flight.law == law && r.flight.phi_cmd_deg == phi)
            .collect()
    };
    cells
        .iter()
        .map(|&(law, phi)| {
            let cell = of(law, phi);
            let against = reference.filter(|r| *r != law);
            let other = against.map(|r| of(r, phi)).unwrap_or_default();
            let runs = cell.len() as u64;
            let errors = cell.iter().filter(|r| r.end.is_error()).count() as u64;
            let failures = cell.iter().filter(|r| !r.verdict.as_expected).count() as u64;
            // A flight that failed its verdict (a hard landing, a crash) is no sample of where
            // the lander sets down: it is counted in the statement, not in the ellipse.
            let touchdowns: Vec<(f64, f64)> = cell
                .iter()
                .filter(|r| r.verdict.as_expected)
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
                requirement(expect, requirements),
                number(stats::reliability_lower_bound(failures, runs, CONFIDENCE)),
                number(stats::confidence(failures, runs, THREE_SIGMA)),
                statement(failures, runs, expect, requirements),
                of.to_owned(),
                points.len().to_string(),
                e(|x| x.centre_north_m),
                e(|x| x.centre_east_m),
                e(|x| x.semi_major_m),
                e(|x| x.semi_minor_m),
                e(|x| x.major_azimuth_deg),
                against.map_or_else(String::new, |l| l.name().to_owned()),
            ];
            let values: Vec<[f64; metrics::METRIC_COUNT]> = cell
                .iter()
                .map(|r| metrics::metric_values(&r.metrics))
                .collect();
            for k in 0..METRIC_NAMES.len() {
                let mut column: Vec<f64> = values
                    .iter()
                    .map(|v| v[k])
                    .filter(|v| !v.is_nan())
                    .collect();
                column.sort_by(f64::total_cmp);
                record.push(number(stats::percentile_of_sorted(&column, 0.5)));
                for (_, p) in BOUNDED_PERCENTILES {
                    // Empty: the runs cannot support the percentile.
                    record.push(
                        stats::quantile_upper_bound(&column, p, CONFIDENCE)
                            .map_or_else(String::new, number),
                    );
                }
                record.push(number(column.last().copied().unwrap_or(f64::NAN)));
                let ranking = analysis::sensitivities(&cell, k);
                record.push(analysis::ranking_text(&ranking, INFLUENTIAL_SHOWN));
                match against {
                    Some(reference) => {
                        let p = analysis::paired(&cell, &other, reference, k);
                        for v in [p.median_difference, p.low, p.high] {
                            record.push(if p.runs == 0 {
                                String::new()
                            } else {
                                number(v)
                            });
                        }
                    }
                    None => record.extend([String::new(), String::new(), String::new()]),
                }
            }
            record
        })
        .collect()
}

/// Writes `summary.csv` into `dir`.
pub fn write(
    rows: &[Row],
    expect: Expect,
    requirements: usize,
    dir: &Path,
) -> anyhow::Result<std::path::PathBuf> {
    let path = dir.join(FILE_NAME);
    let mut out = csv::Writer::from_path(&path)?;
    out.write_record(header())?;
    for record in records(rows, expect, requirements) {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::definition::Flight;
    use crate::dispersion::{Dispersion, DispersionRanges};
    use crate::manifest::{End, Judged};
    use lander::metrics::nan_metrics;

    /// Run `j` of a landing cell: touchdown at (j, -j) m, vertical speed j/10 m/s; run 3
    /// lands hard.
    fn row(j: u64, law: Law) -> Row {
        let mut metrics = nan_metrics();
        metrics.touchdown_north_m = j as f64;
        metrics.touchdown_east_m = -(j as f64) + if j.is_multiple_of(2) { 0.5 } else { 0.0 };
        metrics.touchdown_vertical_speed_mps = j as f64 / 10.0;
        Row {
            flight: Flight {
                index: j,
                run: j,
                run_seed: j,
                law,
                phi_cmd_deg: 150.0,
            },
            dispersion: Dispersion::draw(j, &DispersionRanges::default()),
            metrics,
            end: End::Terminated {
                instance: "plant".into(),
            },
            verdict: Judged {
                word: if j == 3 { "hard landing" } else { "landed" }.into(),
                as_expected: j != 3,
                detail: String::new(),
            },
        }
    }

    #[test]
    fn a_cell_row_holds_counts_confidence_ellipse_and_percentiles() {
        let rows: Vec<Row> = (0..11).map(|j| row(j, Law::DECOUPLED)).collect();
        let records = records(&rows, Expect::Landed, 0);
        assert_eq!(records.len(), 1);
        let header = header();
        let get = |name: &str| {
            let k = header.iter().position(|h| h == name).unwrap();
            records[0][k].clone()
        };
        assert_eq!(get("runs"), "11");
        assert_eq!(get("failed_verdicts"), "1");
        assert_eq!(get("errors"), "0");
        let bound: f64 = get("reliability_lower_bound_at_90pct").parse().unwrap();
        assert_eq!(bound, stats::reliability_lower_bound(1, 11, 0.9));
        assert!(get("statement").starts_with("1 failures in 11 runs"));
        assert_eq!(get("ellipse_of"), "touchdown");
        // Flight 3, the hard landing, is no sample of where the lander sets down.
        assert_eq!(get("ellipse_points"), "10");
        let azimuth: f64 = get("ellipse_major_azimuth_deg").parse().unwrap();
        assert!(
            (azimuth + 45.0).abs() < 2.0,
            "points along North = -East: {azimuth}"
        );
        // vertical speeds 0.0 .. 1.0: median 0.5, max 1; 11 runs support no tail percentile
        // (45 for p95 at 90 %, 230 for p99, 852 for p99.73): those cells are empty, not
        // estimates.
        assert_eq!(get("touchdown_vertical_speed_mps_p50"), "0.5");
        assert_eq!(get("touchdown_vertical_speed_mps_max"), "1.0");
        assert_eq!(get("touchdown_vertical_speed_mps_p95_ub90"), "");
        assert_eq!(get("touchdown_vertical_speed_mps_p99_ub90"), "");
        assert_eq!(get("touchdown_vertical_speed_mps_p99_73_ub90"), "");
        assert!(!header
            .iter()
            .any(|h| h.ends_with("_p95") || h.ends_with("_p99") || h.ends_with("_p99_73")));
        // 100 runs bound p95 at 90 % by the 99th of them (P(Bin(100, 0.95) <= 98) = 0.963,
        // <= 97: 0.882); still nothing for p99 or p99.73.
        let rows: Vec<Row> = (0..100).map(|j| row(j, Law::DECOUPLED)).collect();
        let hundred = super::records(&rows, Expect::Landed, 0);
        let get = |name: &str| {
            let k = header.iter().position(|h| h == name).unwrap();
            hundred[0][k].clone()
        };
        let mut speeds: Vec<f64> = (0..100).map(|j| j as f64 / 10.0).collect();
        speeds.sort_by(f64::total_cmp);
        let expected = stats::quantile_upper_bound(&speeds, 0.95, 0.9).unwrap();
        assert_eq!(
            get("touchdown_vertical_speed_mps_p95_ub90"),
            number(expected)
        );
        assert_eq!(expected, speeds[98], "the 99th of 100 runs");
        assert_eq!(get("touchdown_vertical_speed_mps_p99_ub90"), "");
        assert_eq!(get("touchdown_vertical_speed_mps_p99_73_ub90"), "");
        // 230 runs bound p99 at 90 % by the largest (1 - 0.99^230 = 0.901; 229 runs: 0.899)
        let rows: Vec<Row> = (0..230).map(|j| row(j, Law::DECOUPLED)).collect();
        let records = super::records(&rows, Expect::Landed, 0);
        let k = header
            .iter()
            .position(|h| h == "touchdown_vertical_speed_mps_p99_ub90")
            .unwrap();
        assert_eq!(records[0][k], number(22.9));
        assert_eq!(stats::runs_for_quantile_bound(0.99, 0.9), 230);
        // a metric no run has is NaN, not zero
        assert_eq!(get("descent_end_position_error_m_p50"), "NaN");
    }

    #[test]
    fn without_touchdowns_the_ellipse_is_of_the_end_of_descent() {
        let mut rows: Vec<Row> = (0..5).map(|j| row(j, Law::COUPLED)).collect();
        for r in &mut rows {
            r.metrics.descent_end_north_m = r.metrics.touchdown_north_m;
            r.metrics.descent_end_east_m = 0.1 * r.metrics.touchdown_north_m;
            r.metrics.touchdown_north_m = f64::NAN;
        }
        let records = records(&rows, Expect::Completed, 0);
        let k = header().iter().position(|h| h == "ellipse_of").unwrap();
        assert_eq!(records[0][k], "descent_end");
        assert_eq!(failed_lines(&rows).len(), 1);
        assert!(failed_lines(&rows)[0].starts_with("flight 3 (run 3, coupled"));
    }
}
