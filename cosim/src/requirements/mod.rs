//! Requirements for integration testing: `[[requirement]]` entries of a scenario, temporal
//! formulas over recorded signals (see [`formula`]), judged with their quantitative
//! robustness (see [`robustness`]) and reported in the summary, the exit code and JUnit XML.
mod continued;
pub mod formula;
pub mod junit;
pub mod robustness;

use crate::master::Trajectory;
use formula::Formula;
use robustness::{Robustness, Signals, Truth};

/// One requirement: its name, its formula as written and parsed, and how a window the run
/// ended before is judged.
#[derive(Debug, Clone, PartialEq)]
pub struct Requirement {
    pub name: String,
    pub text: String,
    pub formula: Formula,
    pub early_end: EarlyEnd,
}

/// How a requirement judges a window the run ended before (`early_end` of its
/// `[[requirement]]` entry).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum EarlyEnd {
    /// Inconclusive, which fails, unless the samples recorded decide it: a run that stops
    /// early has not shown what the requirement asks of the rest of the window.
    #[default]
    Inconclusive,
    /// Judged over the samples recorded: for a run that may legitimately stop early (a
    /// touchdown), where the part after its end does not exist.
    Accept,
}

#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct Entry {
    name: String,
    formula: String,
    #[serde(default)]
    early_end: EarlyEnd,
}

/// The keys a `[[requirement]]` entry accepts.
pub fn keys() -> &'static [&'static str] {
    crate::system::fields::of::<Entry>()
}

/// The `[[requirement]]` entries of a scenario's TOML text, every bad one named at once
/// (which entry, where in its formula).
pub fn from_toml(text: &str) -> Result<Vec<Requirement>, String> {
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
                early_end: e.early_end,
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

/// Every signal a requirement reads that the run does not record, as problems: where in
/// the formula, and the recorded signal it may have meant.
pub fn unrecorded(requirements: &[Requirement], columns: &[String]) -> Vec<String> {
    requirements
        .iter()
        .flat_map(|r| {
            r.formula
                .signals()
                .into_iter()
                .filter(|s| !columns.iter().any(|c| c == s))
                .map(move |s| {
                    let at = formula::signal_position(&r.text, s)
                        .map(|k| format!(" at character {k}"))
                        .unwrap_or_default();
                    format!(
                        "requirement {:?}: formula {:?}{at}: {s} is not a recorded signal (an \
                         output of an instance, or in the scenario's `record`){}",
                        r.name,
                        r.text,
                        crate::suggest::hint(s, columns.iter().map(String::as_str))
                    )
                })
        })
        .collect()
}

/// Every signal a requirement reads whose column is not a number in a row (an Int64 or
/// UInt64, whose slot holds its bits, a String or a Binary; see `results::ColumnType`), as
/// problems. `types[j]` is the type of `columns[j]`.
pub fn not_numbers(
    requirements: &[Requirement],
    columns: &[String],
    types: &[crate::results::ColumnType],
) -> Vec<String> {
    requirements
        .iter()
        .flat_map(|r| {
            r.formula.signals().into_iter().filter_map(move |s| {
                let j = columns.iter().position(|c| c == s)?;
                let kind = *types.get(j)?;
                (kind.in_bits() || kind.is_text()).then(|| {
                    format!(
                        "requirement {:?}: formula {:?}: {s} is a {} column, which a formula \
                         does not read (it reads Float64, Float32, Boolean and integers of up \
                         to 32 bits)",
                        r.name,
                        r.text,
                        kind.name()
                    )
                })
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
    /// Its robustness and truth at the start of the run.
    pub robustness: Robustness,
    /// The time span the run recorded.
    pub recorded_s: (f64, f64),
    pub early_end: EarlyEnd,
    /// Why the robustness is undefined (which signal is not a number, from when), when it
    /// is.
    pub undefined: Option<String>,
}

impl Judged {
    /// Only a requirement that holds passes: a violated, inconclusive or undefined one
    /// fails.
    pub fn holds(&self) -> bool {
        self.robustness.truth == Truth::Holds
    }

    pub fn describe(&self) -> String {
        let r = self.robustness;
        let at = short(r.at_s);
        let margin = if r.value == 0.0 {
            // The sign cannot say whether the limit itself is allowed: `<` and `<=` differ.
            let allowed = match r.truth {
                Truth::Holds => ", which it allows",
                Truth::Violated => ", which it does not allow",
                _ => "",
            };
            format!("robustness 0 at t = {at} s: exactly at its limit{allowed}")
        } else if r.value.is_infinite() && self.early_end == EarlyEnd::Accept {
            format!(
                "no recorded sample falls in its window at t = {at} s, and the scenario \
                 accepts an early end"
            )
        } else {
            format!("robustness {:+.6e} at t = {at} s", r.value)
        };
        let (word, why) = match r.truth {
            Truth::Holds => ("holds", margin),
            Truth::Violated => ("VIOLATED", margin),
            Truth::Inconclusive { from_s, to_s } => {
                let recorded = if r.value.is_infinite() {
                    "no recorded sample falls in it".to_owned()
                } else {
                    format!("over the recorded part {margin}")
                };
                (
                    "INCONCLUSIVE",
                    format!(
                        "window [{}, {}] s, run ended at {} s: {recorded}; early_end = \
                         \"accept\" would judge it over the recorded part",
                        short(from_s),
                        short(to_s),
                        short(self.recorded_s.1)
                    ),
                )
            }
            Truth::Undefined => (
                "UNDEFINED",
                format!(
                    "robustness undefined: {}",
                    self.undefined
                        .as_deref()
                        .unwrap_or("a value it reads is not a number")
                ),
            ),
        };
        format!(
            "requirement {}: {word} ({why}; recorded {} to {} s): {}",
            self.name,
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
            let signals = Signals {
                times,
                columns,
                ended_s: match r.early_end {
                    EarlyEnd::Inconclusive => Some(recorded_s.1),
                    EarlyEnd::Accept => None,
                },
            };
            let robustness = robustness::robustness(&r.formula, &signals)
                .first()
                .copied()
                .unwrap_or(Robustness {
                    value: f64::NEG_INFINITY,
                    at_s: recorded_s.0,
                    truth: Truth::Violated,
                });
            let undefined = (robustness.truth == Truth::Undefined)
                .then(|| not_a_number(&signals, robustness.at_s));
            Judged {
                name: r.name.clone(),
                text: r.text.clone(),
                robustness,
                recorded_s,
                early_end: r.early_end,
                undefined,
            }
        })
        .collect()
}

/// Which of `signals` are not a number at `at_s`, the first sample an undefined robustness
/// reads: the windows that read it keep the earliest such sample.
fn not_a_number(signals: &Signals, at_s: f64) -> String {
    let k = signals.times.iter().position(|&t| t == at_s);
    let bad: Vec<String> = signals
        .columns
        .iter()
        .filter_map(|(name, values)| {
            let x = values[k?];
            (!x.is_finite()).then(|| format!("{name} is {x}"))
        })
        .collect();
    if bad.is_empty() {
        format!(
            "its expression has no value at t = {} s (0 / 0, inf - inf or the square root \
             of a negative number)",
            short(at_s)
        )
    } else {
        format!("{} at t = {} s", bad.join(", "), short(at_s))
    }
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

    /// The last time kept of a run whose first row is at `first`: a margin past the
    /// horizon, as rows beyond it change nothing and rows short of it would.
    fn until_after(&self, first: f64) -> f64 {
        first + self.horizon_s * (1.0 + 1e-9) + 1e-9 * (1.0 + first.abs())
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
            self.until_s = self.until_after(time);
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
                let row = [7.0, libm::sin(t * 1.3), libm::cos(t * 0.7) * 1.5];
                whole.record(t, &row);
                kept.record(t, &row);
            }
            assert_eq!(kept.judge(&requirements), judge(&requirements, &whole));
            assert!(kept.rows.len() <= 602, "{} rows kept", kept.rows.len());
        }
    }
}

#[cfg(test)]
mod judging_tests {
    use super::*;
    use crate::master::Recorder;

    /// `requirements` (TOML) judged on `m.y` and `m.z` sampled at `times`.
    fn judged(requirements: &str, times: &[f64], y: &[f64], z: &[f64]) -> Vec<Judged> {
        let requirements = from_toml(requirements).unwrap();
        let mut run = Trajectory {
            names: vec!["m.y".into(), "m.z".into()],
            ..Default::default()
        };
        for k in 0..times.len() {
            run.record(times[k], &[y[k], z[k]]);
        }
        judge(&requirements, &run)
    }

    fn requirement(name: &str, formula: &str, early_end: Option<&str>) -> String {
        let option = early_end
            .map(|e| format!("early_end = \"{e}\"\n"))
            .unwrap_or_default();
        format!("[[requirement]]\nname = \"{name}\"\nformula = \"{formula}\"\n{option}")
    }

    #[test]
    fn a_not_a_number_sample_fails_the_requirement_naming_the_signal_and_its_first_time() {
        let times: Vec<f64> = (0..=10).map(f64::from).collect();
        // 0.49 below 10 until t = 5, NaN from then on: the minimum ignoring NaN says +9.51.
        let y: Vec<f64> = times
            .iter()
            .map(|&t| if t < 5.0 { 0.49 } else { f64::NAN })
            .collect();
        let z = vec![1.0; times.len()];
        let text = [
            requirement("y below 10", "always [0, 10] m.y < 10", None),
            // Negated, a NaN comparison must not turn into a success either.
            requirement("not y above 10", "always [0, 10] not m.y > 10", None),
            requirement("y reaches 0", "eventually [0, 10] m.y < 0.5", None),
            requirement("z or y", "always [0, 10] (m.z > 0 or m.y > 0)", None),
        ]
        .concat();
        let judged = judged(&text, &times, &y, &z);
        for j in &judged {
            assert!(!j.holds(), "{}", j.describe());
            assert_eq!(j.robustness.truth, Truth::Undefined, "{}", j.describe());
            assert!(j.robustness.value.is_nan());
            assert!(
                j.describe()
                    .contains("UNDEFINED (robustness undefined: m.y is NaN at t = 5 s;"),
                "{}",
                j.describe()
            );
        }
    }

    #[test]
    fn an_infinite_signal_or_an_expression_without_value_is_undefined() {
        let times = [0.0, 1.0, 2.0];
        let y = [1.0, f64::NEG_INFINITY, 1.0];
        let z = [1.0, 1.0, -1.0];
        let text = [
            requirement("y below 10", "always [0, 2] m.y < 10", None),
            requirement("sqrt", "always [0, 2] sqrt(m.z) < 10", None),
            // 1 / 0 is a comparable infinity: it holds.
            requirement("division", "m.y / 0 > 0", None),
        ]
        .concat();
        let judged = judged(&text, &times, &y, &z);
        assert!(
            judged[0]
                .describe()
                .contains("robustness undefined: m.y is -inf at t = 1 s"),
            "{}",
            judged[0].describe()
        );
        assert!(
            judged[1]
                .describe()
                .contains("its expression has no value at t = 2 s"),
            "{}",
            judged[1].describe()
        );
        assert!(judged[2].holds(), "{}", judged[2].describe());
    }

    #[test]
    fn a_strict_comparison_met_with_equality_fails_and_a_non_strict_one_holds() {
        let times = [0.0, 1.0, 2.0];
        let y = [2.0, 1.0, -1.5];
        let z = [0.0; 3];
        let text = [
            requirement("strict", "always [0, 2] abs(m.y) < 2", None),
            requirement("non-strict", "always [0, 2] abs(m.y) <= 2", None),
            requirement("strict above", "always [0, 2] 2 > abs(m.y)", None),
            requirement("not non-strict", "not m.y >= 2", None),
            requirement("not strict", "not m.y > 2", None),
        ]
        .concat();
        let judged = judged(&text, &times, &y, &z);
        let holds: Vec<bool> = judged.iter().map(Judged::holds).collect();
        assert_eq!(holds, [false, true, false, false, true]);
        for j in &judged {
            assert_eq!(j.robustness.value, 0.0, "{}", j.describe());
            assert_eq!(j.robustness.at_s, 0.0, "{}", j.describe());
        }
        assert!(
            judged[0].describe().contains(
                "strict: VIOLATED (robustness 0 at t = 0 s: exactly at its limit, which it \
                 does not allow;"
            ),
            "{}",
            judged[0].describe()
        );
        assert!(
            judged[1].describe().contains(
                "non-strict: holds (robustness 0 at t = 0 s: exactly at its limit, which it \
                 allows;"
            ),
            "{}",
            judged[1].describe()
        );
    }

    #[test]
    fn a_window_past_the_end_is_inconclusive_for_always_and_eventually_alike() {
        // The run ends at 5 s; y = t.
        let times: Vec<f64> = (0..=10).map(|k| 0.5 * f64::from(k)).collect();
        let y = times.clone();
        let z = vec![0.0; times.len()];
        let text = [
            requirement("always", "always [0, 8] m.y < 100", None),
            requirement("eventually", "eventually [0, 8] m.y > 6", None),
            requirement("beyond", "always [6, 8] m.y < 100", None),
            // Decided by what was recorded: a violation of always, a success of eventually.
            requirement("always decided", "always [0, 8] m.y < 3", None),
            requirement("eventually decided", "eventually [0, 8] m.y > 4", None),
            requirement("until", "m.y >= 0 until [0, 8] m.y > 6", None),
            requirement("covered", "always [0, 5] m.y < 100", None),
            requirement("at its limit", "always [0, 8] m.y <= 5", None),
        ]
        .concat();
        let judged = judged(&text, &times, &y, &z);
        let truths: Vec<Truth> = judged.iter().map(|j| j.robustness.truth).collect();
        let open = |from_s, to_s| Truth::Inconclusive { from_s, to_s };
        assert_eq!(
            truths,
            [
                open(0.0, 8.0),
                open(0.0, 8.0),
                open(6.0, 8.0),
                Truth::Violated,
                Truth::Holds,
                open(0.0, 8.0),
                Truth::Holds,
                open(0.0, 8.0)
            ]
        );
        assert!(
            judged[7].describe().contains(
                "over the recorded part robustness 0 at t = 5 s: exactly at its limit; early_end"
            ),
            "{}",
            judged[7].describe()
        );
        for j in &judged[..3] {
            assert!(!j.holds());
            assert!(
                j.describe().contains(": INCONCLUSIVE (window [")
                    && j.describe().contains(" s, run ended at 5 s: "),
                "{}",
                j.describe()
            );
        }
        // The honest robustness over the recorded part: 95 short of 100 at t = 5 s.
        assert_eq!(judged[0].robustness.value, 95.0);
        assert!(
            judged[0]
                .describe()
                .contains("over the recorded part robustness +9.500000e1 at t = 5 s"),
            "{}",
            judged[0].describe()
        );
        assert!(
            judged[2]
                .describe()
                .contains("window [6, 8] s, run ended at 5 s: no recorded sample falls in it"),
            "{}",
            judged[2].describe()
        );
    }

    #[test]
    fn a_scenario_accepting_an_early_end_judges_the_recorded_part() {
        let times: Vec<f64> = (0..=10).map(|k| 0.5 * f64::from(k)).collect();
        let y = times.clone();
        let z = vec![0.0; times.len()];
        let text = [
            requirement("always", "always [0, 8] m.y < 100", Some("accept")),
            requirement("eventually", "eventually [0, 8] m.y > 6", Some("accept")),
            requirement("beyond", "always [6, 8] m.y < 100", Some("accept")),
            requirement(
                "nested",
                "always [0, 5] eventually [0, 2] m.y >= 0",
                Some("accept"),
            ),
        ]
        .concat();
        let judged = judged(&text, &times, &y, &z);
        let truths: Vec<Truth> = judged.iter().map(|j| j.robustness.truth).collect();
        assert_eq!(
            truths,
            [Truth::Holds, Truth::Violated, Truth::Holds, Truth::Holds]
        );
        assert!(
            judged[2].describe().contains(
                "holds (no recorded sample falls in its window at t = 0 s, and the scenario \
                 accepts an early end;"
            ),
            "{}",
            judged[2].describe()
        );
        let bad = from_toml(&requirement("x", "m.y < 1", Some("pass"))).unwrap_err();
        assert!(bad.contains("unknown variant `pass`"), "{bad}");
    }

    #[test]
    fn an_unrecorded_signal_is_named_with_its_position_and_the_signal_meant() {
        let requirements = from_toml(&requirement(
            "typo",
            "always [0, 10] m.y > 0 and plant.r_neu[2] < 3",
            None,
        ))
        .unwrap();
        let columns = ["m.y".to_owned(), "plant.r_nue[2]".to_owned()];
        let problems = unrecorded(&requirements, &columns);
        assert_eq!(
            problems,
            [
                "requirement \"typo\": formula \"always [0, 10] m.y > 0 and plant.r_neu[2] < 3\" \
              at character 28: plant.r_neu[2] is not a recorded signal (an output of an \
              instance, or in the scenario's `record`) (did you mean 'plant.r_nue[2]'?)"
            ]
        );
    }
}
