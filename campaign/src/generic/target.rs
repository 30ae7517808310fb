//! What a swept or dispersed input sets: a parameter `instance.variable` of the scenario's
//! FMUs (Real, or Integer and Enumeration when swept), or the time or value of one of the
//! scenario's events (`event.NAME.time`, `event.NAME.value`). Every target is parsed and
//! checked here alone.
use cosim::system::event::Change;
use cosim::system::{ParamValue, SystemDescription};
use model_description::{Causality, ModelDescription, Variability, VariableKind};

#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Target {
    /// A parameter of an instance, set before each run is initialised.
    Parameter { instance: String, variable: String },
    /// When the scenario's event `event` is due, s.
    EventTime { event: String },
    /// The value the scenario's event `event` sets.
    EventValue { event: String },
}

/// How a target takes a campaign's number.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Setting {
    Real,
    /// A whole number, within the declared range where one is declared.
    Integer {
        min: Option<i64>,
        max: Option<i64>,
    },
}

const EVENT: &str = "event.";

impl Target {
    /// `event.NAME.time`, `event.NAME.value` or `instance.variable` (the variable's name may
    /// hold dots; the instance's does not; an instance named `event` is reached only through
    /// its variables not ending in `.time` or `.value`).
    pub fn parse(text: &str) -> Result<Self, String> {
        if let Some(rest) = text.strip_prefix(EVENT) {
            match rest.rsplit_once('.') {
                Some((event, "time")) if !event.is_empty() => {
                    return Ok(Target::EventTime {
                        event: event.to_owned(),
                    })
                }
                Some((event, "value")) if !event.is_empty() => {
                    return Ok(Target::EventValue {
                        event: event.to_owned(),
                    })
                }
                _ => {}
            }
        }
        match text.split_once('.') {
            Some((instance, variable)) if !instance.is_empty() && !variable.is_empty() => {
                Ok(Target::Parameter {
                    instance: instance.to_owned(),
                    variable: variable.to_owned(),
                })
            }
            _ => Err(format!(
                "parameter = \"{text}\" is not of the form \"instance.variable\", \
                 \"event.NAME.time\" or \"event.NAME.value\""
            )),
        }
    }

    /// How `system` (whose instance `i` is described by `describe(i)`) takes this target's
    /// numbers, or why it cannot: an unknown instance, variable or event, or one a run cannot
    /// set.
    pub fn check<'a>(
        &self,
        system: &SystemDescription,
        describe: impl Fn(usize) -> &'a ModelDescription,
    ) -> Result<Setting, String> {
        let event_named = |event: &str| {
            system
                .events
                .iter()
                .find(|e| e.name == event)
                .ok_or_else(|| {
                    let known: Vec<&str> = system.events.iter().map(|e| e.name.as_str()).collect();
                    format!(
                        "parameter = \"{self}\": the scenario has no event '{event}' (it has {})",
                        match known.is_empty() {
                            true => "none".to_owned(),
                            false => known.join(", "),
                        }
                    )
                })
        };
        let (instance, variable) = match self {
            Target::EventTime { event } => return event_named(event).map(|_| Setting::Real),
            Target::EventValue { event } => {
                return match event_named(event)?.value {
                    ParamValue::Real(_) => Ok(Setting::Real),
                    ParamValue::Integer(_) => Ok(Setting::Integer {
                        min: None,
                        max: None,
                    }),
                    _ => Err(format!(
                        "parameter = \"{self}\": the event sets a boolean or a text; a \
                         campaign sets numbers"
                    )),
                }
            }
            Target::Parameter { instance, variable } => (instance, variable),
        };
        let Some(index) = system.instances.iter().position(|i| &i.name == instance) else {
            let known: Vec<&str> = system.instances.iter().map(|i| i.name.as_str()).collect();
            return Err(format!(
                "parameter = \"{instance}.{variable}\": the scenario has no instance \
                 '{instance}' (it has {})",
                known.join(", ")
            ));
        };
        let description = describe(index);
        let Some(declared) = description.variable(variable) else {
            return Err(format!(
                "parameter = \"{instance}.{variable}\": {} declares no variable '{variable}'",
                description.model_name
            ));
        };
        let causality = declared.causality_or_default();
        let variability = declared.variability_or_default();
        if causality != Causality::Parameter
            || !matches!(variability, Variability::Fixed | Variability::Tunable)
        {
            return Err(format!(
                "parameter = \"{instance}.{variable}\": '{variable}' has causality \
                 {causality:?} and variability {variability:?}; a campaign sets parameters \
                 (causality Parameter, variability Fixed or Tunable)"
            ));
        }
        match declared.kind() {
            Some(VariableKind::Real) => Ok(Setting::Real),
            Some(VariableKind::Integer | VariableKind::Enumeration) => {
                let range = declared.integer.as_ref();
                Ok(Setting::Integer {
                    min: range.and_then(|r| r.min).map(i64::from),
                    max: range.and_then(|r| r.max).map(i64::from),
                })
            }
            _ => Err(format!(
                "parameter = \"{instance}.{variable}\": '{variable}' is neither a Real nor an \
                 Integer or Enumeration; a campaign sets numbers"
            )),
        }
    }

    /// Why a swept `value` of this target (taken as `setting`) cannot be flown in `system`,
    /// if it cannot.
    pub fn value_problem(
        &self,
        setting: Setting,
        system: &SystemDescription,
        value: f64,
    ) -> Option<String> {
        if let Setting::Integer { min, max } = setting {
            if value.fract() != 0.0 || value.abs() > i32::MAX as f64 {
                return Some(format!("{self}: value {value} is not an integer"));
            }
            let whole = value as i64;
            if min.is_some_and(|m| whole < m) || max.is_some_and(|m| whole > m) {
                let end = |x: Option<i64>| x.map_or("..".into(), |x| x.to_string());
                return Some(format!(
                    "{self}: value {whole} is outside the declared range [{}, {}]",
                    end(min),
                    end(max)
                ));
            }
        }
        let change = self.change(setting, value)?;
        let (Target::EventTime { event } | Target::EventValue { event }) = self else {
            return None;
        };
        system
            .clone()
            .change_event(event, &change)
            .err()
            .map(|problem| format!("{self}: value {value}: {problem}"))
    }

    /// What a run with `value` of this event target changes; `None` for a parameter.
    pub fn change(&self, setting: Setting, value: f64) -> Option<Change> {
        match self {
            Target::Parameter { .. } => None,
            Target::EventTime { .. } => Some(Change::Time(value)),
            Target::EventValue { .. } => Some(Change::Value(setting.value(value))),
        }
    }
}

impl Setting {
    /// `value` as this setting sets it.
    pub fn value(self, value: f64) -> ParamValue {
        match self {
            Setting::Real => ParamValue::Real(value),
            Setting::Integer { .. } => ParamValue::Integer(value as i64),
        }
    }
}

impl std::fmt::Display for Target {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Target::Parameter { instance, variable } => write!(f, "{instance}.{variable}"),
            Target::EventTime { event } => write!(f, "{EVENT}{event}.time"),
            Target::EventValue { event } => write!(f, "{EVENT}{event}.value"),
        }
    }
}
