//! Requirements for integration testing: `[[requirement]]` entries of a scenario, temporal
//! formulas over recorded signals (see [`formula`]), judged with their quantitative
//! robustness (see [`robustness`]) and reported in the summary, the exit code and JUnit XML.
pub mod formula;
pub mod junit;
pub mod robustness;

use crate::master::Trajectory;
use formula::Formula;
use robustness::{Robustness, Signals};

/// One requirement: its name, its formula as written and parsed.
#[derive(Debug, Clone, PartialEq)]
pub struct Requirement {
    pub name: String,
    pub text: String,
    pub formula: Formula,
}

/// The `[[requirement]]` entries of a scenario's TOML text, every bad one named at once
/// (which entry, where in its formula).
pub fn from_toml(text: &str) -> Result<Vec<Requirement>, String> {
    #[derive(serde::Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Entry {
        name: String,
        formula: String,
    }
    let mut table: toml::Table = toml::from_str(text).map_err(|e| e.to_string())?;
    let Some(entries) = table.remove("requirement") else {
        return Ok(Vec::new());
    };
    let entries: Vec<Entry> = entries
        .try_into()
        .map_err(|e: toml::de::Error| format!("[[requirement]]: {}", e.message()))?;
    let mut problems = Vec::new();
    let mut out: Vec<Requirement> = Vec::new();
    for (k, e) in entries.into_iter().enumerate() {
        if out.iter().any(|r| r.name == e.name) {
            problems.push(format!(
                "requirement {} ({:?}): the name is used twice",
                k + 1,
                e.name
            ));
            continue;
        }
        match formula::parse(&e.formula) {
            Ok(formula) => out.push(Requirement {
                name: e.name,
                text: e.formula,
                formula,
            }),
            Err(error) => problems.push(format!(
                "requirement {} ({:?}): formula {:?} {error}",
                k + 1,
                e.name,
                e.formula
            )),
        }
    }
    if problems.is_empty() {
        Ok(out)
    } else {
        Err(problems.join("\n"))
    }
}

/// Every signal a requirement reads that the run does not record, as problems.
pub fn unrecorded(requirements: &[Requirement], columns: &[String]) -> Vec<String> {
    requirements
        .iter()
        .flat_map(|r| {
            r.formula
                .signals()
                .into_iter()
                .filter(|s| !columns.iter().any(|c| c == s))
                .map(move |s| {
                    format!(
                        "requirement {:?}: {s} is not a recorded signal (an output of an \
                         instance, or in the scenario's `record`)",
                        r.name
                    )
                })
        })
        .collect()
}

/// Adds the signals `requirements` read to a run's `record` list, unless a recorded vector
/// holds them already: a run that records a chosen few columns still judges its scenario's
/// requirements.
pub fn record_signals(record: &mut Vec<String>, requirements: &[Requirement]) {
    for r in requirements {
        for signal in r.formula.signals() {
            let base = signal.split('[').next().unwrap_or(signal);
            if !record.iter().any(|c| c == signal || c == base) {
                record.push(signal.to_owned());
            }
        }
    }
}

/// A requirement judged on a run.
#[derive(Debug, Clone, PartialEq)]
pub struct Judged {
    pub name: String,
    pub text: String,
    pub robustness: Robustness,
    /// The time span the run recorded.
    pub recorded_s: (f64, f64),
}

impl Judged {
    /// Holds when its robustness is positive, or zero for a non-strict requirement that
    /// is exactly met; a robustness of 0 is reported as holding at the margin.
    pub fn holds(&self) -> bool {
        self.robustness.value >= 0.0
    }

    pub fn describe(&self) -> String {
        let r = self.robustness;
        let margin = if r.value.is_infinite() {
            if r.value > 0.0 {
                "holds vacuously: no recorded sample falls in its window".to_owned()
            } else {
                "no recorded sample falls in its window".to_owned()
            }
        } else {
            format!("robustness {:+.6e} at t = {} s", r.value, r.at_s)
        };
        format!(
            "requirement {}: {} ({margin}; recorded {} to {} s): {}",
            self.name,
            if self.holds() { "holds" } else { "VIOLATED" },
            short(self.recorded_s.0),
            short(self.recorded_s.1),
            self.text
        )
    }
}

/// A time as a reader wants it: to the millisecond, without trailing zeros (172, 141.735).
fn short(t: f64) -> String {
    let text = format!("{t:.3}");
    text.trim_end_matches('0').trim_end_matches('.').to_owned()
}

/// Each requirement's robustness at the start of the recorded run.
pub fn judge(requirements: &[Requirement], trajectory: &Trajectory) -> Vec<Judged> {
    let times = &trajectory.times;
    let recorded_s = (
        times.first().copied().unwrap_or(0.0),
        times.last().copied().unwrap_or(0.0),
    );
    judge_span(requirements, trajectory, recorded_s)
}

/// [`judge`] on the rows [`Kept`] held of a run that recorded `recorded_s`.
fn judge_span(
    requirements: &[Requirement],
    trajectory: &Trajectory,
    recorded_s: (f64, f64),
) -> Vec<Judged> {
    let times = &trajectory.times;
    requirements
        .iter()
        .map(|r| {
            let columns = r
                .formula
                .signals()
                .into_iter()
                .map(|name| {
                    let j = trajectory
                        .names
                        .iter()
                        .position(|c| c == name)
                        .expect("checked by `unrecorded` before the run");
                    let values = (0..times.len())
                        .map(|k| trajectory.values[k * trajectory.names.len() + j])
                        .collect();
                    (name, values)
                })
                .collect();
            let signals = Signals { times, columns };
            let robustness = robustness::robustness(&r.formula, &signals)
                .first()
                .copied()
                .unwrap_or(Robustness {
                    value: f64::NEG_INFINITY,
                    at_s: 0.0,
                });
            Judged {
                name: r.name.clone(),
                text: r.text.clone(),
                robustness,
                recorded_s,
            }
        })
        .collect()
}

/// What judging requirements needs of a run, kept while it records (a
/// [`Recorder`](crate::master::Recorder)): the columns they read and, of those, only the
/// rows up to the requirements' horizon after the first one (the rows after it cannot
/// change a robustness at the start). A run streamed to its results file judges its
/// requirements as [`judge`] would on the whole trajectory, holding at most
/// `min(run, horizon)` rows of a few columns.
#[derive(Debug, Clone)]
pub struct Kept {
    /// Where each kept column is in a recorded row.
    sources: Vec<usize>,
    horizon_s: f64,
    /// The last time kept: the first row's plus the horizon.
    until_s: f64,
    rows: Trajectory,
    recorded_s: Option<(f64, f64)>,
}

impl Kept {
    /// For a run recording `columns` (which must hold every signal of `requirements`, as
    /// [`unrecorded`] checks).
    pub fn new(requirements: &[Requirement], columns: &[String]) -> Self {
        let mut names: Vec<String> = Vec::new();
        for r in requirements {
            for signal in r.formula.signals() {
                if !names.iter().any(|n| n == signal) {
                    names.push(signal.to_owned());
                }
            }
        }
        let sources = names
            .iter()
            .map(|name| {
                columns
                    .iter()
                    .position(|c| c == name)
                    .expect("checked by `unrecorded` before the run")
            })
            .collect();
        let horizon_s = requirements
            .iter()
            .map(|r| r.formula.horizon_s())
            .fold(0.0, f64::max);
        Kept {
            sources,
            horizon_s,
            until_s: f64::INFINITY,
            rows: Trajectory {
                names,
                ..Default::default()
            },
            recorded_s: None,
        }
    }

    /// Seconds of rows after the first one that are kept.
    pub fn horizon_s(&self) -> f64 {
        self.horizon_s
    }

    /// Values kept per row (the time and the requirements' columns).
    pub fn width(&self) -> usize {
        self.sources.len() + 1
    }

    /// Each requirement's robustness at the start of the run, with the span it recorded.
    pub fn judge(&self, requirements: &[Requirement]) -> Vec<Judged> {
        judge_span(
            requirements,
            &self.rows,
            self.recorded_s.unwrap_or((0.0, 0.0)),
        )
    }
}

impl crate::master::Recorder for Kept {
    fn record(&mut self, time: f64, values: &[f64]) {
        let span = self.recorded_s.get_or_insert((time, time));
        span.1 = time;
        if self.rows.is_empty() {
            // A margin past the horizon: rows beyond it change nothing, rows short of it
            // would.
            self.until_s = time + self.horizon_s * (1.0 + 1e-9) + 1e-9 * (1.0 + time.abs());
        }
        if time <= self.until_s {
            self.rows.times.push(time);
            self.rows
                .values
                .extend(self.sources.iter().map(|&j| values[j]));
        }
    }
}

#[cfg(test)]
mod kept_tests {
    use super::*;
    use crate::master::Recorder;

    /// Requirements judged on what [`Kept`] held of a run equal those judged on the whole
    /// trajectory: nested windows, until, a window past the end, a run far longer than
    /// the horizon, and columns in another order than the formulas name them.
    #[test]
    fn kept_rows_judge_as_the_whole_trajectory() {
        let text = r#"
            [[requirement]]
            name = "nested"
            formula = "always [1, 3] eventually [0, 0.5] b.y < 0.9"
            [[requirement]]
            name = "until"
            formula = "(a.x > -2) until [0.5, 2] (b.y > 0.5)"
            [[requirement]]
            name = "late"
            formula = "eventually [50, 60] a.x > 0"
            [[requirement]]
            name = "not and or"
            formula = "not (always [0, 4] abs(a.x) < 0.1) or (b.y >= 0 and a.x < 2)"
        "#;
        let requirements = from_toml(text).unwrap();
        for (rows, start) in [(0usize, 0.0), (1, 0.0), (40, 0.0), (5000, 3.0)] {
            let names = vec!["c.z".to_owned(), "b.y".to_owned(), "a.x".to_owned()];
            let mut whole = Trajectory {
                names: names.clone(),
                ..Default::default()
            };
            let mut kept = Kept::new(&requirements, &names);
            for k in 0..rows {
                let t = start + k as f64 * 0.1;
                let row = [7.0, (t * 1.3).sin(), (t * 0.7).cos() * 1.5];
                whole.record(t, &row);
                kept.record(t, &row);
            }
            assert_eq!(kept.judge(&requirements), judge(&requirements, &whole));
            assert!(kept.rows.len() <= 602, "{} rows kept", kept.rows.len());
        }
    }
}
