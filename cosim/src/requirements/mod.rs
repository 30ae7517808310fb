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
