//! Which variable may be set in which state (FMI 2.0.4 §4.2.4, simplified to the
//! variables our tables declare settable: parameters and inputs), and the value checks
//! applied before anything is written.
use crate::error::CallError;
use crate::model::Model;
use crate::state::State;
use crate::variable::{Causality, EnumType, Limit, Variability, Variable};

/// `Ok` if a variable of this causality and variability may be set in `state` (a state in
/// which `fmi2Set*` is legal at all), otherwise why not.
pub fn settable(
    causality: Causality,
    variability: Variability,
    state: State,
) -> Result<(), &'static str> {
    if variability == Variability::Constant {
        return Err("a constant is never settable");
    }
    match causality {
        Causality::Input => Ok(()),
        Causality::Parameter => match (variability, state) {
            (Variability::Tunable, _) => Ok(()),
            (_, State::Instantiated | State::InitializationMode) => Ok(()),
            _ => Err("a fixed parameter can only be set before fmi2ExitInitializationMode"),
        },
        Causality::Output => Err("an output is computed by the FMU"),
        Causality::CalculatedParameter => Err("a calculated parameter is computed by the FMU"),
        Causality::Local => Err("a local variable is computed by the FMU"),
        Causality::Independent => Err("the independent variable is set by fmi2DoStep"),
    }
}

/// Whether `value` is finite and within the bounds.
pub fn real_in_range(value: f64, min: Option<Limit>, max: Option<Limit>) -> bool {
    value.is_finite()
        && min.is_none_or(|m| m.admits_above(value))
        && max.is_none_or(|m| m.admits_below(value))
}

/// `Ok` if `var` may be set in `state`.
pub fn check_settable<M: Model>(var: &Variable<M>, state: State) -> Result<(), CallError> {
    settable(var.causality, var.variability, state).map_err(|reason| CallError::NotSettable {
        name: var.name().into_owned(),
        vr: var.value_reference,
        reason,
    })
}

pub fn check_real<M: Model>(
    var: &Variable<M>,
    value: f64,
    min: Option<Limit>,
    max: Option<Limit>,
) -> Result<(), CallError> {
    if !value.is_finite() {
        return Err(CallError::NonFinite {
            name: var.name().into_owned(),
            vr: var.value_reference,
            value,
        });
    }
    if !real_in_range(value, min, max) {
        // An infinite end is open, as is an exclusive bound.
        let open = if matches!(min, Some(Limit::Inclusive(_))) {
            "["
        } else {
            "("
        };
        let close = if matches!(max, Some(Limit::Inclusive(_))) {
            "]"
        } else {
            ")"
        };
        return Err(CallError::OutOfRange {
            name: var.name().into_owned(),
            vr: var.value_reference,
            value: fmi_model::readable(value),
            range: format!(
                "{open}{}, {}{close}",
                min.map_or("-inf".to_string(), |m| m.value().to_string()),
                max.map_or("inf".to_string(), |m| m.value().to_string()),
            ),
        });
    }
    Ok(())
}

pub fn check_integer<M: Model>(
    var: &Variable<M>,
    value: i32,
    min: Option<i32>,
    max: Option<i32>,
) -> Result<(), CallError> {
    if min.is_some_and(|m| value < m) || max.is_some_and(|m| value > m) {
        let bound = |b: Option<i32>, open: &str| b.map_or(open.to_string(), |b| b.to_string());
        return Err(CallError::OutOfRange {
            name: var.name().into_owned(),
            vr: var.value_reference,
            value: value.to_string(),
            range: format!(
                "{}{}, {}{}",
                if min.is_some() { "[" } else { "(" },
                bound(min, "-inf"),
                bound(max, "inf"),
                if max.is_some() { "]" } else { ")" },
            ),
        });
    }
    Ok(())
}

/// An enumeration value must be one of the items of its type.
pub fn check_enumeration<M: Model>(
    var: &Variable<M>,
    value: i32,
    ty: &EnumType,
) -> Result<(), CallError> {
    if ty.item(value).is_some() {
        return Ok(());
    }
    let type_name = ty.name;
    let allowed: Vec<String> = ty
        .items
        .iter()
        .map(|i| format!("{} ({})", i.value, i.name))
        .collect();
    Err(CallError::InvalidValue {
        name: var.name().into_owned(),
        vr: var.value_reference,
        reason: format!(
            "value {value} is not an item of enumeration {type_name}: allowed {}",
            allowed.join(", ")
        ),
    })
}
