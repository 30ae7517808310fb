//! Scenario events: a value set on one variable of one instance during the run (a fault
//! thrown mid-flight, a gain retuned), at the first communication point at or after a time.
//! What can be checked without the FMUs is checked here, when the system is loaded, with
//! the variable, its causality, variability and type against the FMU
//! (`cosim/src/master/events.rs`), so that every event's problems are named at once.
use super::{split_path, ParamValue, SystemDescription};

/// One `[[event]]` of a scenario. Public and plain so that a campaign can disperse `time_s`.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Event {
    /// Printed when the event is applied and in the summary; unique within the system.
    pub name: String,
    /// When it is due, s: it is applied at the first communication point `t_k >= time_s`
    /// (see [`application_time`]), before the step from `t_k`.
    pub time_s: f64,
    pub instance: String,
    /// A tunable parameter or an input that no connection and no input table drives.
    pub variable: String,
    pub value: ParamValue,
}

/// How close below a communication point an event time still counts as that point, as a
/// fraction of the step: `0.3` in steps of `0.1` is the point `3 * 0.1 = 0.30000000000000004`.
const ON_GRID: f64 = 1e-9;

/// The communication point an event due at `time_s` is applied at: the first
/// `t_k = start + k h` with `t_k >= time_s - 1e-9 h`, `k` counted as the master counts its
/// steps (never accumulated). `None` when no step starts at or after it (the stop time, or a
/// time in the last, shortened step).
pub fn application_time(system: &SystemDescription, time_s: f64) -> Option<f64> {
    let (start, h) = (system.start_time, system.step_size);
    let k = ((time_s - start) / h - ON_GRID).ceil().max(0.0);
    let t_k = start + k * h;
    (t_k < system.stop_time - ON_GRID * h).then_some(t_k)
}

/// Whether an event due at `time_s` is due at the communication point `t` of a step `h`
/// (the run-time form of [`application_time`], for every time grid).
pub fn is_due(time_s: f64, t: f64, h: f64) -> bool {
    t >= time_s - ON_GRID * h
}

/// The events a run continued from its communication point `t` finds in the FMU states it
/// restores: those due at a point before `t` (`t` less a step, on the regular grid, so also
/// when the step from `t` is a shortened last one), in the order they were applied (by
/// time, declaration order at one time). Those due at `t` are the continued run's.
pub fn applied_before(system: &SystemDescription, t: f64) -> Vec<&Event> {
    let h = system.step_size;
    let mut before: Vec<&Event> = system
        .events
        .iter()
        .filter(|event| is_due(event.time_s, t - h, h))
        .collect();
    before.sort_by(|a, b| a.time_s.total_cmp(&b.time_s));
    before
}

impl Event {
    /// `instance.variable`.
    pub fn path(&self) -> String {
        format!("{}.{}", self.instance, self.variable)
    }

    /// What the event sets, as a scenario writes it (`plant.engine_health = 0.5`).
    pub fn describe(&self) -> String {
        let value = match &self.value {
            ParamValue::Real(x) => x.to_string(),
            ParamValue::Integer(i) => i.to_string(),
            ParamValue::Boolean(b) => b.to_string(),
            ParamValue::String(s) => format!("\"{s}\""),
        };
        format!("{} = {value}", self.path())
    }

    /// The event as a saved run names it: `'name' (instance.variable = value) due at T s`.
    pub fn label(&self) -> String {
        format!(
            "'{}' ({}) due at {} s",
            self.name,
            self.describe(),
            self.time_s
        )
    }
}

/// The problems of the system's events that need no FMU: names, times, values, instances.
pub fn problems(system: &SystemDescription) -> Vec<String> {
    (0..system.events.len())
        .flat_map(|i| problems_of(system, i))
        .collect()
}

/// The problems of the system's event `i` that need no FMU.
fn problems_of(system: &SystemDescription, i: usize) -> Vec<String> {
    let mut problems = Vec::new();
    {
        let event = &system.events[i];
        let label = format!("event '{}' ({})", event.name, event.describe());
        if event.name.is_empty() {
            problems.push(format!("{label}: the name must not be empty"));
        }
        if system.events[..i].iter().any(|e| e.name == event.name) {
            problems.push(format!("{label}: a second event of this name"));
        }
        if !event.time_s.is_finite() {
            problems.push(format!("{label}: time {} is not a number", event.time_s));
        } else if event.time_s < system.start_time || event.time_s > system.stop_time {
            problems.push(format!(
                "{label}: time {} s is outside [start_time, stop_time] = [{}, {}] s",
                event.time_s, system.start_time, system.stop_time
            ));
        } else if system.step_size > 0.0 && application_time(system, event.time_s).is_none() {
            problems.push(format!(
                "{label}: time {} s is after the last communication point a step starts \
                 from, so the event would change nothing",
                event.time_s
            ));
        }
        match event.value {
            ParamValue::Real(x) if !x.is_finite() => {
                problems.push(format!("{label}: value {x} is not a finite number"))
            }
            ParamValue::String(_) => problems.push(format!(
                "{label}: a text value; an event sets a number, an integer or a boolean"
            )),
            _ => {}
        }
        if !system.instances.iter().any(|i| i.name == event.instance) {
            let names = system.instances.iter().map(|i| i.name.as_str());
            problems.push(format!(
                "{label}: unknown instance '{}'{}",
                event.instance,
                crate::suggest::hint(&event.instance, names)
            ));
        }
    }
    problems
}

/// A change to one event for the following runs: a campaign's drawn or swept fault time or
/// value.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Change {
    Time(f64),
    Value(ParamValue),
}

impl SystemDescription {
    /// Changes event `name` as `change` says, checked as the scenario's own events are (a
    /// time on a communication point a step starts from, a finite value); a new value keeps
    /// the event's type, which the FMU was checked against when the system was loaded.
    /// Refused with the reason, the event unchanged.
    pub fn change_event(&mut self, name: &str, change: &Change) -> Result<(), String> {
        let Some(i) = self.events.iter().position(|e| e.name == name) else {
            let known: Vec<&str> = self.events.iter().map(|e| e.name.as_str()).collect();
            return Err(format!(
                "no event named '{name}' (the scenario has {})",
                match known.is_empty() {
                    true => "none".to_owned(),
                    false => known.join(", "),
                }
            ));
        };
        let before = self.events[i].clone();
        match change {
            Change::Time(time_s) => self.events[i].time_s = *time_s,
            Change::Value(value) => {
                if std::mem::discriminant(value) != std::mem::discriminant(&before.value) {
                    return Err(format!(
                        "event '{name}' ({}): the new value {value:?} is not of the event's type",
                        before.describe()
                    ));
                }
                self.events[i].value = value.clone();
            }
        }
        let problems = problems_of(self, i);
        if problems.is_empty() {
            return Ok(());
        }
        self.events[i] = before;
        Err(problems.join("; "))
    }
}

/// Reads `set = "instance.variable"` into its two parts.
pub(super) fn target(set: &str) -> Option<(String, String)> {
    split_path(set).map(|(i, v)| (i.to_owned(), v.to_owned()))
}
