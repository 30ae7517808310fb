//! The statistics of a scenario campaign's manifest: the pass rate with its Clopper-Pearson
//! interval, each requirement's robustness (minimum, median, and the low percentiles the run
//! count supports, by the rule of [`crate::stats::quantile_upper_bound`]), for the whole
//! campaign and per sweep point; and each input's Spearman rank correlation with each
//! robustness. `summary.csv`, `sensitivity.csv` and the printed text.
use crate::analysis::spearman;
use crate::generic::manifest::{Layout, Row};
use crate::generic::plan::Plan;
use crate::stats::{self, binomial_cdf};
use anyhow::Context;
use std::fmt::Write;
use std::path::{Path, PathBuf};

/// The two-sided confidence of the pass-rate interval.
pub const PASS_RATE_CONFIDENCE: f64 = 0.95;
/// The one-sided confidence of the robustness percentiles' lower bounds.
pub const PERCENTILE_CONFIDENCE: f64 = 0.90;
/// The low percentiles of a robustness bounded from below, when the runs support them.
pub const PERCENTILES: [f64; 2] = [0.05, 0.01];

/// The exact (Clopper-Pearson) two-sided interval of a success probability from `passed`
/// of `runs`: the probabilities under which `passed` or more (fewer) successes have
/// probability (1 - confidence) / 2, found by bisection of the binomial CDF.
pub fn clopper_pearson(passed: u64, runs: u64, confidence: f64) -> (f64, f64) {
    if runs == 0 {
        return (0.0, 1.0);
    }
    let tail = (1.0 - confidence) / 2.0;
    let solve = |f: &dyn Fn(f64) -> bool| {
        let (mut lo, mut hi) = (0.0_f64, 1.0_f64);
        for _ in 0..100 {
            let mid = 0.5 * (lo + hi);
            if f(mid) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        0.5 * (lo + hi)
    };
    // Lower end: P(X >= passed | p) = tail, P(X >= passed) grows with p.
    let low = match passed {
        0 => 0.0,
        k => solve(&|p| 1.0 - binomial_cdf(k - 1, runs, p) < tail),
    };
    // Upper end: P(X <= passed | p) = tail, P(X <= passed) falls with p.
    let high = match passed {
        k if k == runs => 1.0,
        k => solve(&|p| binomial_cdf(k, runs, p) > tail),
    };
    (low, high)
}

/// A robustness's statistics over some runs (NaN runs, which failed, left out).
#[derive(Debug, Clone, PartialEq)]
pub struct Robustness {
    pub runs: usize,
    pub min: f64,
    pub median: f64,
    /// A lower bound of each of [`PERCENTILES`] at [`PERCENTILE_CONFIDENCE`]; `None` when
    /// the runs cannot support it.
    pub low_percentiles: Vec<Option<f64>>,
}

impl Robustness {
    pub fn of(values: impl Iterator<Item = f64>) -> Self {
        let mut sorted: Vec<f64> = values.filter(|v| !v.is_nan()).collect();
        sorted.sort_by(f64::total_cmp);
        // A lower bound of the p-quantile is minus an upper bound of the (1 - p)-quantile of
        // the negated values.
        let negated: Vec<f64> = sorted.iter().rev().map(|v| -v).collect();
        Self {
            runs: sorted.len(),
            min: sorted.first().copied().unwrap_or(f64::NAN),
            median: stats::percentile_of_sorted(&sorted, 0.5),
            low_percentiles: PERCENTILES
                .iter()
                .map(|p| {
                    stats::quantile_upper_bound(&negated, 1.0 - p, PERCENTILE_CONFIDENCE)
                        .map(|b| -b)
                })
                .collect(),
        }
    }
}

/// The pass rate and the robustness of each requirement over some runs.
#[derive(Debug, Clone, PartialEq)]
pub struct Scope {
    /// `None`: the whole campaign; else the sweep point.
    pub point: Option<u64>,
    pub runs: u64,
    pub passed: u64,
    pub errors: u64,
    pub interval: (f64, f64),
    pub robustness: Vec<Robustness>,
}

impl Scope {
    fn of(point: Option<u64>, rows: &[&Row], requirements: usize) -> Self {
        let passed = rows.iter().filter(|r| r.passed()).count() as u64;
        let runs = rows.len() as u64;
        Self {
            point,
            runs,
            passed,
            errors: rows
                .iter()
                .filter(|r| r.verdict == super::manifest::ERROR)
                .count() as u64,
            interval: clopper_pearson(passed, runs, PASS_RATE_CONFIDENCE),
            robustness: (0..requirements)
                .map(|k| Robustness::of(rows.iter().map(|r| r.robustness[k])))
                .collect(),
        }
    }
}

/// What drives each robustness: an input's Spearman rank correlation with it.
#[derive(Debug, Clone, PartialEq)]
pub struct Sensitivity {
    pub input: String,
    pub requirement: String,
    pub spearman: f64,
    pub runs: usize,
}

impl Sensitivity {
    /// Whether the correlation differs from 0 at the 5 % level (Fisher's z, |z| > 1.96).
    pub fn significant(&self) -> bool {
        self.runs > 3 && (self.spearman.atanh() * ((self.runs - 3) as f64).sqrt()).abs() > 1.96
    }
}

#[derive(Debug, Clone)]
pub struct Summary {
    pub layout: Layout,
    pub whole: Scope,
    pub points: Vec<Scope>,
    pub sensitivities: Vec<Sensitivity>,
}

pub fn summarise(plan: &Plan, layout: &Layout, rows: &[Row]) -> Summary {
    let all: Vec<&Row> = rows.iter().collect();
    let n = layout.requirements.len();
    let points = match plan.points() {
        1 => Vec::new(),
        count => (0..count)
            .map(|p| {
                let at: Vec<&Row> = rows.iter().filter(|r| r.id.point == p).collect();
                Scope::of(Some(p), &at, n)
            })
            .collect(),
    };
    let mut sensitivities = Vec::new();
    for (i, input) in layout.inputs.iter().enumerate() {
        for (k, requirement) in layout.requirements.iter().enumerate() {
            let (x, y): (Vec<f64>, Vec<f64>) = rows
                .iter()
                .filter(|r| r.robustness[k].is_finite())
                .map(|r| (r.inputs[i], r.robustness[k]))
                .unzip();
            let constant = x.iter().all(|v| *v == x[0]);
            if x.len() >= 3 && !constant {
                sensitivities.push(Sensitivity {
                    input: input.clone(),
                    requirement: requirement.clone(),
                    spearman: spearman(&x, &y),
                    runs: x.len(),
                });
            }
        }
    }
    Summary {
        layout: layout.clone(),
        whole: Scope::of(None, &all, n),
        points,
        sensitivities,
    }
}

fn percent(x: f64) -> String {
    format!("{:.1} %", 100.0 * x)
}

fn number(x: Option<f64>) -> String {
    x.map(crate::manifest::number).unwrap_or_default()
}

impl Summary {
    /// The sweep values of `point`, named.
    fn point_name(&self, plan: &Plan, point: u64) -> String {
        let names = plan.sweeps.iter().map(|(t, _)| t.to_string());
        names
            .zip(plan.point_values(point))
            .map(|(n, v)| format!("{n} = {v}"))
            .collect::<Vec<_>>()
            .join(", ")
    }

    fn pass_line(scope: &Scope) -> String {
        let (low, high) = scope.interval;
        let rate = scope.passed as f64 / scope.runs.max(1) as f64;
        let errors = match scope.errors {
            0 => String::new(),
            e => format!(", {e} ended in error"),
        };
        format!(
            "pass {}/{} = {} (95 % Clopper-Pearson {} to {}){errors}",
            scope.passed,
            scope.runs,
            percent(rate),
            percent(low),
            percent(high)
        )
    }

    /// The printed summary.
    pub fn text(&self, plan: &Plan) -> String {
        let mut out = String::new();
        let w = &mut out;
        let _ = writeln!(
            w,
            "{} runs ({} sweep point{} x {} runs), seed {}, {} sampling",
            plan.total(),
            plan.points(),
            if plan.points() == 1 { "" } else { "s" },
            plan.runs,
            plan.seed,
            match plan.sampling {
                super::sampling::Sampling::Random => "random",
                super::sampling::Sampling::LatinHypercube => "latin-hypercube",
            }
        );
        let _ = writeln!(w, "{}", Self::pass_line(&self.whole));
        if !self.layout.requirements.is_empty() {
            let needs: Vec<String> = PERCENTILES
                .iter()
                .map(|p| stats::runs_for_quantile_bound(1.0 - p, PERCENTILE_CONFIDENCE).to_string())
                .collect();
            let _ = writeln!(
                w,
                "robustness        min          median       p5 >= (90 %) p1 >= (90 %)   \
                 requirement"
            );
            for (requirement, r) in self.layout.requirements.iter().zip(&self.whole.robustness) {
                let bound = |k: usize| match r.low_percentiles[k] {
                    Some(b) => format!("{b:<12.5e}"),
                    None => format!("{:<12}", format!("({} runs)", needs[k])),
                };
                let _ = writeln!(
                    w,
                    "                  {:<12.5e} {:<12.5e} {} {}   {requirement}",
                    r.min,
                    r.median,
                    bound(0),
                    bound(1)
                );
            }
            let _ = writeln!(
                w,
                "  (pN >= x: the N-th percentile is at least x with 90 % confidence; a \
                 percentile needs the runs in parentheses)"
            );
        }
        for scope in &self.points {
            let point = scope.point.unwrap_or_default();
            let mins: Vec<String> = self
                .layout
                .requirements
                .iter()
                .zip(&scope.robustness)
                .map(|(n, r)| format!("{n} {:.4e}", r.min))
                .collect();
            let _ = writeln!(
                w,
                "point {point} ({}): {}; min robustness: {}",
                self.point_name(plan, point),
                Self::pass_line(scope),
                mins.join(", ")
            );
        }
        if !self.sensitivities.is_empty() {
            let _ = writeln!(
                w,
                "sensitivity (Spearman rank correlation with robustness):"
            );
            for s in &self.sensitivities {
                let mark = if s.significant() {
                    ""
                } else {
                    "  (not significant at 5 %)"
                };
                let _ = writeln!(
                    w,
                    "  {:<24} {:<24} {:+.3}{mark}",
                    s.input, s.requirement, s.spearman
                );
            }
        }
        out
    }

    /// Writes `summary.csv` and `sensitivity.csv` into `dir`.
    pub fn write(&self, plan: &Plan, dir: &Path) -> anyhow::Result<Vec<PathBuf>> {
        let path = dir.join("summary.csv");
        let mut csv =
            csv::Writer::from_path(&path).with_context(|| format!("writing {}", path.display()))?;
        let sweeps: Vec<String> = plan.sweeps.iter().map(|(t, _)| t.to_string()).collect();
        let mut header: Vec<String> = vec!["point".into()];
        header.extend(sweeps.iter().cloned());
        header.extend(
            [
                "requirement",
                "runs",
                "passed",
                "pass_rate",
                "pass_rate_low95",
                "pass_rate_high95",
                "robustness_min",
                "robustness_median",
                "robustness_p5_low90",
                "robustness_p1_low90",
            ]
            .map(String::from),
        );
        csv.write_record(&header)?;
        for scope in std::iter::once(&self.whole).chain(&self.points) {
            let mut lead: Vec<String> = match scope.point {
                None => std::iter::once("all".to_owned())
                    .chain(sweeps.iter().map(|_| String::new()))
                    .collect(),
                Some(p) => std::iter::once(p.to_string())
                    .chain(
                        plan.point_values(p)
                            .into_iter()
                            .map(crate::manifest::number),
                    )
                    .collect(),
            };
            let mut verdict = lead.clone();
            let rate = scope.passed as f64 / scope.runs.max(1) as f64;
            verdict.extend([
                String::new(),
                scope.runs.to_string(),
                scope.passed.to_string(),
                number(Some(rate)),
                number(Some(scope.interval.0)),
                number(Some(scope.interval.1)),
            ]);
            verdict.extend(["", "", "", ""].map(String::from));
            csv.write_record(&verdict)?;
            for (name, r) in self.layout.requirements.iter().zip(&scope.robustness) {
                let mut line = std::mem::take(&mut lead);
                lead.clone_from(&line);
                line.extend([name.clone(), r.runs.to_string()]);
                line.extend(["", "", "", ""].map(String::from));
                line.extend([number(Some(r.min)), number(Some(r.median))]);
                line.extend(r.low_percentiles.iter().map(|b| number(*b)));
                csv.write_record(&line)?;
            }
        }
        csv.flush()?;
        let sensitivity = dir.join("sensitivity.csv");
        let mut csv = csv::Writer::from_path(&sensitivity)
            .with_context(|| format!("writing {}", sensitivity.display()))?;
        csv.write_record(["input", "requirement", "spearman", "runs", "significant"])?;
        for s in &self.sensitivities {
            csv.write_record([
                s.input.clone(),
                s.requirement.clone(),
                number(Some(s.spearman)),
                s.runs.to_string(),
                s.significant().to_string(),
            ])?;
        }
        csv.flush()?;
        Ok(vec![path, sensitivity])
    }
}

/// The summary of the campaign in `dir` (its `campaign.toml` and `manifest.csv`).
pub fn of_directory(dir: &Path) -> anyhow::Result<(Plan, Summary)> {
    let file = super::config::CampaignFile::read(dir)?;
    let plan = Plan::new(&file.scenario_campaign.campaign)
        .map_err(|p| anyhow::anyhow!("{}: {}", dir.display(), p.join("; ")))?;
    let path = dir.join(crate::manifest::FILE_NAME);
    let layout = Layout::of_manifest(&path)?;
    let (rows, _) = layout.read_complete(&path)?;
    let summary = summarise(&plan, &layout, &rows);
    Ok((plan, summary))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clopper_pearson_matches_its_published_values() {
        // 8 of 10: (0.4439, 0.9748); 0 of 10: (0, 0.3085); 10 of 10: (0.6915, 1) (exact
        // binomial intervals, e.g. R's binom.test).
        let close =
            |a: (f64, f64), b: (f64, f64)| (a.0 - b.0).abs() < 1e-4 && (a.1 - b.1).abs() < 1e-4;
        assert!(close(clopper_pearson(8, 10, 0.95), (0.4439, 0.9748)));
        assert!(close(clopper_pearson(0, 10, 0.95), (0.0, 0.3085)));
        assert!(close(clopper_pearson(10, 10, 0.95), (0.6915, 1.0)));
    }

    #[test]
    fn a_low_percentile_is_bounded_only_when_the_runs_support_it() {
        let r = Robustness::of((1..=44).map(f64::from));
        assert_eq!(r.low_percentiles, [None, None]);
        assert_eq!((r.min, r.median), (1.0, 22.5));
        // 45 runs: the minimum bounds the 5th percentile from below with 90 % confidence.
        let r = Robustness::of((1..=45).map(f64::from).chain([f64::NAN]));
        assert_eq!(r.runs, 45);
        assert_eq!(r.low_percentiles, [Some(1.0), None]);
    }
}
