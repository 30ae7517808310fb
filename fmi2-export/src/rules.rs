//! Which variable may be set in which state (FMI 2.0.4 §4.2.4, simplified to the
//! variables our tables declare settable: parameters and inputs), and the value checks
//! applied before anything is written.
use crate::error::CallError;
use crate::state::State;
use crate::variable::{Causality, Variability, Variable};
use crate::EnumerationDecl;

/// `Ok` if `var` may be set in `state` (a state in which `fmi2Set*` is legal at all).
pub fn check_settable<M>(var: &Variable<M>, state: State) -> Result<(), CallError> {
    let refuse = |reason| {
        Err(CallError::NotSettable {
            name: var.name,
            vr: var.value_reference,
            reason,
        })
    };
    if var.variability == Variability::Constant {
        return refuse("a constant is never settable");
    }
    match var.causality {
        Causality::Input => Ok(()),
        Causality::Parameter => match (var.variability, state) {
            (Variability::Tunable, _) => Ok(()),
            (_, State::Instantiated | State::InitializationMode) => Ok(()),
            _ => refuse("a fixed parameter can only be set before fmi2ExitInitializationMode"),
        },
        Causality::Output => refuse("an output is computed by the FMU"),
        Causality::CalculatedParameter => refuse("a calculated parameter is computed by the FMU"),
        Causality::Local => refuse("a local variable is computed by the FMU"),
        Causality::Independent => refuse("the independent variable is set by fmi2DoStep"),
    }
}

pub fn check_real<M>(
    var: &Variable<M>,
    value: f64,
    min: Option<f64>,
    max: Option<f64>,
) -> Result<(), CallError> {
    if !value.is_finite() {
        return Err(CallError::NonFinite {
            name: var.name,
            vr: var.value_reference,
            value,
        });
    }
    let below = min.is_some_and(|m| value < m);
    let above = max.is_some_and(|m| value > m);
    if below || above {
        return Err(out_of_range(var, value, min, max));
    }
    Ok(())
}

pub fn check_integer<M>(
    var: &Variable<M>,
    value: i32,
    min: Option<i32>,
    max: Option<i32>,
) -> Result<(), CallError> {
    if min.is_some_and(|m| value < m) || max.is_some_and(|m| value > m) {
        return Err(out_of_range(var, value, min, max));
    }
    Ok(())
}

/// An enumeration value must be one of the items of its type.
pub fn check_enumeration<M>(
    var: &Variable<M>,
    value: i32,
    type_name: &str,
    types: &[EnumerationDecl],
) -> Result<(), CallError> {
    let items = types
        .iter()
        .find(|t| t.name == type_name)
        .map(|t| t.items)
        .unwrap_or(&[]);
    if items.iter().any(|&(_, v, _)| v == value) {
        return Ok(());
    }
    let allowed: Vec<String> = items.iter().map(|(n, v, _)| format!("{v} ({n})")).collect();
    Err(CallError::InvalidValue {
        name: var.name,
        vr: var.value_reference,
        reason: format!(
            "value {value} is not an item of enumeration {type_name}: allowed {}",
            allowed.join(", ")
        ),
    })
}

fn out_of_range<M, T: std::fmt::Display>(
    var: &Variable<M>,
    value: T,
    min: Option<T>,
    max: Option<T>,
) -> CallError {
    let bound = |b: Option<T>, open: &str| b.map_or(open.to_string(), |b| b.to_string());
    CallError::OutOfRange {
        name: var.name,
        vr: var.value_reference,
        value: value.to_string(),
        min: bound(min, "-inf"),
        max: bound(max, "inf"),
    }
}
