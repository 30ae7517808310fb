//! Scenario events at run time (the description is `crate::system::event`): checked against
//! the FMUs when the system is loaded, applied at their communication point.
//!
//! An event due at `time_s` is applied at the first communication point `t_k >= time_s`
//! (up to 1e-9 of a step below it), after that point's exchange and row are done and
//! before any instance steps from it: the row at `t_k` shows the values before the event,
//! the step from `t_k` to `t_k + h` the new value, from its start. Both FMI versions allow
//! setting a tunable parameter or an input there: FMI 2.0 in the Co-Simulation state
//! "slave initialized", FMI 3.0 in Step Mode ("Set tunable parameters", 4.2.1) and in Event
//! Mode. A Model Exchange instance is set in Event Mode, its event iteration done and its
//! solver started afresh, as after any event (FMI 2.0 and 3.0 allow tunable parameters to
//! change only in Event Mode there).
//!
//! A run held at `t_k` (`linearize.rs`) stops after the events due at `t_k`, before the
//! step from it: its linear model is that of the step, which flies with them. A continued
//! saved run finds those due before its first point in the FMU states it restored, and is
//! refused when its own events before that point are not the saved run's (`saved.rs`).
//!
//! Only tunable parameters and inputs that nothing else drives may be set: a connected
//! input, or one driven by an input table, is refused rather than overridden, since the
//! master would set it again at the next point and silently win.
use super::model_exchange::ModelExchangeUnit;
use super::{resolve, MasterError, Unit};
use crate::system::event::is_due;
use crate::system::{Event, SystemDescription};
use fmi_import::Fmu;
use model_description::{Causality, Variability};

/// The events of a loaded system in the order they fall due (declaration order at one time).
#[derive(Debug, Default)]
pub(super) struct Schedule {
    /// (event index in the system, unit), by due time.
    order: Vec<(usize, usize)>,
    /// How many of `order` this run applied (or found already applied in a continued run).
    next: usize,
}

/// Every problem of the system's events against its FMUs, each naming the event and value.
pub(super) fn problems(
    system: &SystemDescription,
    fmus: &[Fmu],
    connections: &[(String, String)],
    table_inputs: &[super::table::TableInput],
) -> Vec<String> {
    let mut problems = crate::system::event::problems(system);
    for event in &system.events {
        let label = format!("event '{}' ({})", event.name, event.describe());
        let Some(u) = system
            .instances
            .iter()
            .position(|i| i.name == event.instance)
        else {
            // Named among the description's problems.
            continue;
        };
        if matches!(event.value, crate::system::ParamValue::String(_)) {
            continue;
        }
        let variable = event.variable.as_str();
        if fmus[u].structural_parameters().contains(&variable) {
            problems.push(format!(
                "{label}: '{variable}' is a structural parameter, which sizes the FMU's \
                 arrays and cannot change during a run"
            ));
            continue;
        }
        if let Some(problem) =
            resolve::parameter_problem(system, fmus, connections, u, variable, &event.value)
        {
            problems.push(format!("{label}: {problem}"));
            continue;
        }
        if let Some(declared) = fmus[u].model_description().variable(variable) {
            let causality = declared.causality_or_default();
            let tunable = causality == Causality::Parameter
                && declared.variability_or_default() == Variability::Tunable;
            if !(tunable || causality == Causality::Input) {
                problems.push(format!(
                    "{label}: '{variable}' is neither a tunable parameter nor an input (it is \
                     {causality:?}, {:?}): FMI lets a master change only those once the run \
                     has started",
                    declared.variability_or_default()
                ));
                continue;
            }
        }
        if table_inputs
            .iter()
            .any(|t| t.port.instance == u && t.port.name == variable)
        {
            problems.push(format!(
                "{label}: '{variable}' is driven by the input table, which would set it again \
                 at the next communication point"
            ));
        }
    }
    problems
}

impl Schedule {
    pub(super) fn new(system: &SystemDescription) -> Self {
        let mut order: Vec<(usize, usize)> = system
            .events
            .iter()
            .enumerate()
            .filter_map(|(e, event)| {
                let u = system
                    .instances
                    .iter()
                    .position(|i| i.name == event.instance)?;
                Some((e, u))
            })
            .collect();
        // Stable: events due at one time keep their declaration order.
        order.sort_by(|a, b| {
            system.events[a.0]
                .time_s
                .total_cmp(&system.events[b.0].time_s)
        });
        Self { order, next: 0 }
    }

    /// A new run: nothing applied yet.
    pub(super) fn restart(&mut self) {
        self.next = 0;
    }

    /// A run continued from the communication point `t`: the events due before it are in
    /// the FMU states it restored (`crate::system::event::applied_before`, which the saved
    /// run's file lists and a continuation is checked against).
    pub(super) fn skip_before(&mut self, system: &SystemDescription, t: f64) {
        let before = crate::system::event::applied_before(system, t).len();
        self.next = self.next.max(before.min(self.order.len()));
    }

    /// Applies every event due at the communication point `t` (step `h`), in order. `Some`
    /// unit when a Model Exchange instance asked to end the run in the event's iteration.
    pub(super) fn apply_due(
        &mut self,
        system: &SystemDescription,
        units: &mut [Unit],
        t: f64,
        h: f64,
    ) -> Result<Option<usize>, MasterError> {
        while let Some(&(e, u)) = self.order.get(self.next) {
            let event = &system.events[e];
            if !is_due(event.time_s, t, h) {
                break;
            }
            self.next += 1;
            let unit = &mut units[u];
            if apply(event, unit, t)? {
                return Ok(Some(u));
            }
        }
        Ok(None)
    }
}

/// Sets one event's value on its unit at `t`; true when a Model Exchange instance ended the
/// run in the event iteration that follows.
fn apply(event: &Event, unit: &mut Unit, t: f64) -> Result<bool, MasterError> {
    log::info!(
        "event '{}' (due at {} s): {} at t = {t} s",
        event.name,
        event.time_s,
        event.describe()
    );
    let context = format!(
        "applying event '{}' ({}) at t = {t}",
        event.name,
        event.describe()
    );
    let set = |instance: &mut fmi_import::Instance| {
        super::set_parameter(instance, &event.variable, &event.value)
    };
    match &mut unit.model_exchange {
        None => set(&mut unit.instance)
            .map(|()| false)
            .map_err(|e| super::call(&unit.name, &context, e)),
        Some(me) => ModelExchangeUnit::event(me, &mut unit.instance, t, set).map_err(|source| {
            MasterError::ModelExchange {
                instance: unit.name.clone(),
                time: t,
                source: Box::new(source),
            }
        }),
    }
}

/// What became of each of the system's events in a run that ended with `end`, one line
/// each (see [`outcome`]).
pub fn outcomes(system: &SystemDescription, end: &super::RunEnd) -> Vec<String> {
    system
        .events
        .iter()
        .map(|event| {
            let point = crate::system::event::application_time(system, event.time_s);
            outcome(&event.name, &event.describe(), event.time_s, point, end)
        })
        .collect()
}

/// One event's line: the point `applied_at_s` it was applied at (as
/// [`crate::system::event::application_time`] computes it, on the master's own time grid),
/// or that the run ended before it.
pub fn outcome(
    name: &str,
    set: &str,
    time_s: f64,
    applied_at_s: Option<f64>,
    end: &super::RunEnd,
) -> String {
    let label = format!("event '{name}' ({set}) due at {time_s} s");
    match (applied_at_s, end) {
        (Some(t_k), super::RunEnd::Terminated { time, .. }) if t_k >= *time => {
            format!("{label}: not reached, the run ended at {time} s")
        }
        (Some(t_k), _) => format!("{label}: applied at {t_k} s"),
        (None, _) => format!("{label}: after the last step, not applied"),
    }
}
