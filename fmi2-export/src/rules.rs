//! Which variable may be set in which state (FMI 2.0.4 §4.2.4, simplified to the
//! variables our tables declare settable: parameters and inputs), and the value checks
//! applied before anything is written.
use crate::error::CallError;
use crate::state::State;
use crate::variable::{Causality, EnumType, Limit, Variability, Variable};

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
    min: Option<Limit>,
    max: Option<Limit>,
) -> Result<(), CallError> {
    if !value.is_finite() {
        return Err(CallError::NonFinite {
            name: var.name,
            vr: var.value_reference,
            value,
        });
    }
    let below = min.is_some_and(|m| !m.admits_above(value));
    let above = max.is_some_and(|m| !m.admits_below(value));
    if below || above {
        let (open, close) = (
            if matches!(min, Some(Limit::Exclusive(_))) {
                "("
            } else {
                "["
            },
            if matches!(max, Some(Limit::Exclusive(_))) {
                ")"
            } else {
                "]"
            },
        );
        return Err(CallError::OutOfRange {
            name: var.name,
            vr: var.value_reference,
            value: value.to_string(),
            range: format!(
                "{open}{}, {}{close}",
                min.map_or("-inf".to_string(), |m| m.value().to_string()),
                max.map_or("inf".to_string(), |m| m.value().to_string()),
            ),
        });
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
        let bound = |b: Option<i32>, open: &str| b.map_or(open.to_string(), |b| b.to_string());
        return Err(CallError::OutOfRange {
            name: var.name,
            vr: var.value_reference,
            value: value.to_string(),
            range: format!("[{}, {}]", bound(min, "-inf"), bound(max, "inf")),
        });
    }
    Ok(())
}

/// An enumeration value must be one of the items of its type.
pub fn check_enumeration<M>(var: &Variable<M>, value: i32, ty: &EnumType) -> Result<(), CallError> {
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
        name: var.name,
        vr: var.value_reference,
        reason: format!(
            "value {value} is not an item of enumeration {type_name}: allowed {}",
            allowed.join(", ")
        ),
    })
}
