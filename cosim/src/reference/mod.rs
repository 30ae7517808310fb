//! The reference results an FMU carries (FMI-LS-REF, `extra/org.fmi-standard.fmi-ls-ref/`):
//! reading them ([`archive`]), judging a run of the FMU against them, each signal in a tube
//! around its reference ([`tube`]), with a verdict per signal that the JUnit report carries
//! as a test case, and writing them from runs of the FMU ([`generate`]).
pub mod archive;
mod elements;
pub mod generate;
pub mod table;
pub mod tube;

pub use archive::{read, Experiment, References, Stimuli, ToleranceOverrides};
pub use tube::{SignalCheck, Tolerances};

use crate::master::Trajectory;
use crate::requirements::junit::{Case, Outcome};

/// One reference signal's verdict, or why it could not be judged (which fails it too).
#[derive(Debug, Clone, PartialEq)]
pub struct SignalOutcome {
    pub name: String,
    /// The reference file it comes from.
    pub source: String,
    pub check: Result<SignalCheck, String>,
}

impl SignalOutcome {
    pub fn passes(&self) -> bool {
        self.check.as_ref().is_ok_and(SignalCheck::passes)
    }

    pub fn describe(&self) -> String {
        match &self.check {
            Ok(check) => check.describe(),
            Err(why) => format!("{}: FAIL: {why}", self.name),
        }
    }
}

/// An experiment's run judged against its references.
#[derive(Debug, Clone, PartialEq)]
pub struct Checked {
    pub experiment: String,
    pub signals: Vec<SignalOutcome>,
    /// What was not compared, and why (text columns, parameter sets).
    pub notes: Vec<String>,
}

impl Checked {
    pub fn passes(&self) -> bool {
        self.signals.iter().all(SignalOutcome::passes)
    }

    /// One JUnit test case per reference signal.
    pub fn cases(&self) -> Vec<Case> {
        self.signals
            .iter()
            .map(|s| Case {
                name: format!("reference {}: {}", self.experiment, s.name),
                time_s: 0.0,
                outcome: if s.passes() {
                    Outcome::Passed
                } else {
                    Outcome::Failed(s.describe())
                },
                detail: format!("{} (reference {})", s.describe(), s.source),
            })
            .collect()
    }
}

/// The result column of reference column `name`: itself, or `instance.name` in the results
/// of one FMU run alone, whose columns carry the instance's name.
fn result_column(result: &Trajectory, instance: Option<&str>, name: &str) -> Option<usize> {
    result.names.iter().position(|n| n == name).or_else(|| {
        let qualified = format!("{}.{name}", instance?);
        result.names.iter().position(|n| *n == qualified)
    })
}

/// Judges `result`, a run over [`start`, `stop`], against the references of `experiment`,
/// each with `tolerances` under the reference's own. The window of a reference is the part
/// of the run it covers. A column that names no variable of the FMU (`is_variable`) is noted,
/// not failed: Reference-FMUs ship one table for both FMI versions, whose FMI 2.0 FMUs lack
/// the FMI 3.0 types; one the FMU has but the run did not record fails.
pub fn compare(
    result: &Trajectory,
    instance: Option<&str>,
    experiment: &Experiment,
    (start, stop): (f64, f64),
    tolerances: &Tolerances,
    given: &ToleranceOverrides,
    is_variable: &dyn Fn(&str) -> bool,
) -> Checked {
    let mut checked = Checked {
        experiment: experiment.name.clone(),
        signals: Vec::new(),
        notes: experiment.notes.clone(),
    };
    let width = result.names.len();
    let ended = result.times.last().copied();
    for reference in &experiment.references {
        let table = &reference.table;
        // The tolerances the command line gave win over the reference's, which win over
        // the defaults.
        let tolerances = given.over(reference.tolerances.over(*tolerances));
        let from = start.max(table.times[0]);
        let to = stop.min(*table.times.last().expect("a table has rows"));
        for name in &table.text_columns {
            checked
                .notes
                .push(format!("{name} ({}): text, not compared", reference.source));
        }
        for name in &reference.signals {
            if !table.names.contains(name) && !table.text_columns.contains(name) {
                checked.signals.push(SignalOutcome {
                    name: name.clone(),
                    source: reference.source.clone(),
                    check: Err(format!(
                        "a <Signal> names it, {} has no such column",
                        reference.source
                    )),
                });
            }
        }
        let selected =
            |name: &String| reference.signals.is_empty() || reference.signals.contains(name);
        for (name, ref_values) in table
            .names
            .iter()
            .zip(&table.columns)
            .filter(|(n, _)| selected(n))
        {
            let column = result_column(result, instance, name);
            if column.is_none() && !is_variable(name) {
                checked.notes.push(format!(
                    "{name} ({}): no variable of this FMU the harness reads, not compared",
                    reference.source
                ));
                continue;
            }
            let outcome = match (column, ended) {
                (None, _) => Err("not among the run's columns".to_owned()),
                (Some(_), None) => Err("the run recorded no row".to_owned()),
                (Some(_), Some(end)) if end < to - 1e-9 * to.abs().max(1.0) => Err(format!(
                    "the run ended at t = {end} s, before the reference's end at {to} s"
                )),
                (Some(j), Some(_)) => {
                    let values: Vec<f64> =
                        result.values[j..].iter().step_by(width).copied().collect();
                    Ok(tube::check(
                        name,
                        &result.times,
                        &values,
                        &table.times,
                        ref_values,
                        from,
                        to,
                        &tolerances,
                    ))
                }
            };
            checked.signals.push(SignalOutcome {
                name: name.clone(),
                source: reference.source.clone(),
                check: outcome,
            });
        }
    }
    if checked.signals.is_empty() {
        checked.signals.push(SignalOutcome {
            name: "(every signal)".into(),
            source: experiment
                .references
                .iter()
                .map(|r| r.source.as_str())
                .collect::<Vec<_>>()
                .join(", "),
            check: Err("no reference column names a variable of this FMU".into()),
        });
    }
    checked
}

/// How a run's end compares with its references': `None` when they run to the
/// experiment's `stop` (within half a `step`); a reference that ends before records an FMU
/// that stopped the run there, and then `Some(Ok(t))` when this run stopped there too (to
/// a step), `Some(Err(why))` when it did not.
pub fn early_end(
    experiment: &Experiment,
    result: &Trajectory,
    stop: f64,
    step: f64,
) -> Option<Result<f64, String>> {
    let reference_end = experiment
        .references
        .iter()
        .filter_map(|r| r.table.times.last().copied())
        .fold(f64::NEG_INFINITY, f64::max);
    if reference_end >= stop - step / 2.0 {
        return None;
    }
    let run_end = result.times.last().copied().unwrap_or(f64::NEG_INFINITY);
    Some(if (run_end - reference_end).abs() <= step {
        Ok(run_end)
    } else {
        Err(format!(
            "the references end at t = {reference_end} s, where the FMU stopped their run \
             before the experiment's stop at {stop} s; this run ended at t = {run_end} s"
        ))
    })
}

#[cfg(test)]
mod tests;
