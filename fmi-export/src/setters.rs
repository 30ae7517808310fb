//! Which variable may be set in which state, and the checks every value passes before
//! anything is written (so a refused set changes nothing), with their messages. Both
//! versions use these; the name a message shows is the variable's (FMI 2.0 scalar or FMI
//! 3.0 array element, `r0_nue[2]` in both).
use crate::state::State;
use crate::status::CallError;
use fmi_model::{readable, Causality, EnumType, Limit, Variability};

/// `Ok` if a variable of this causality and variability may be set in `state` (a state in
/// which setting is legal at all), otherwise why not.
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
        Causality::Parameter if variability == Variability::Tunable || state.initializing() => {
            Ok(())
        }
        Causality::Parameter => {
            Err("a fixed parameter can only be set before the end of initialization")
        }
        Causality::Output => Err("an output is computed by the FMU"),
        Causality::CalculatedParameter => Err("a calculated parameter is computed by the FMU"),
        Causality::Local => Err("a local variable is computed by the FMU"),
        Causality::Independent => Err("the independent variable is advanced by the master"),
    }
}

/// [`settable`] as the error of a set of variable `name` (vr `vr`).
pub fn check_settable(
    name: impl FnOnce() -> String,
    vr: u32,
    causality: Causality,
    variability: Variability,
    state: State,
) -> Result<(), CallError> {
    settable(causality, variability, state).map_err(|reason| CallError::NotSettable {
        name: name(),
        vr,
        reason,
    })
}

/// Whether `value` is finite and within the bounds.
pub fn real_in_range(value: f64, min: Option<Limit>, max: Option<Limit>) -> bool {
    value.is_finite()
        && min.is_none_or(|m| m.admits_above(value))
        && max.is_none_or(|m| m.admits_below(value))
}

/// A real value for variable `name` (declared in `unit`): finite and within its declared
/// bounds. A refusal names the unit and, where the unit has a display unit (rad: deg), says
/// what the value would be had it been meant in that one, when that would be in range: a
/// user who typed 150 for 150 deg reads the fix in the refusal.
#[cold]
pub fn check_real(
    name: impl FnOnce() -> String,
    vr: u32,
    value: f64,
    min: Option<Limit>,
    max: Option<Limit>,
    unit: Option<&str>,
) -> Result<(), CallError> {
    if !value.is_finite() {
        return Err(CallError::NonFinite {
            name: name(),
            vr,
            value,
        });
    }
    if !real_in_range(value, min, max) {
        let symbol = unit.filter(|u| *u != "1");
        let with_unit = |text: String| match symbol {
            Some(u) => format!("{text} {u}"),
            None => text,
        };
        let mut range = with_unit(crate::units::range_in_unit(min, max, symbol));
        if let Some(u) = symbol {
            if let Some((display, factor)) = crate::units::display_unit(u) {
                let meant = value / factor;
                if real_in_range(meant, min, max) {
                    range.push_str(&format!(
                        "; did you mean {} {display} = {} {u}?",
                        readable(value),
                        crate::units::short(meant)
                    ));
                }
            }
        }
        return Err(CallError::OutOfRange {
            name: name(),
            vr,
            value: with_unit(readable(value)),
            range,
        });
    }
    Ok(())
}

/// An integer value within its declared bounds (checked as i64, so that a 64-bit value of
/// FMI 3.0 is never truncated before the check).
pub fn check_integer(
    name: impl FnOnce() -> String,
    vr: u32,
    value: i64,
    min: Option<i32>,
    max: Option<i32>,
) -> Result<(), CallError> {
    let below = min.is_some_and(|m| value < i64::from(m));
    let above = max.is_some_and(|m| value > i64::from(m));
    if below || above {
        let bound = |b: Option<i32>, open: &str| b.map_or(open.to_string(), |b| b.to_string());
        return Err(CallError::OutOfRange {
            name: name(),
            vr,
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
pub fn check_enumeration(
    name: impl FnOnce() -> String,
    vr: u32,
    value: i64,
    ty: &EnumType,
) -> Result<(), CallError> {
    if i32::try_from(value).is_ok_and(|v| ty.item(v).is_some()) {
        return Ok(());
    }
    let allowed: Vec<String> = ty
        .items
        .iter()
        .map(|i| format!("{} ({})", i.value, i.name))
        .collect();
    Err(CallError::InvalidValue {
        name: name(),
        vr,
        reason: format!(
            "value {value} is not an item of enumeration {}: allowed {}",
            ty.name,
            allowed.join(", ")
        ),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fixed_parameters_only_before_the_end_of_initialization() {
        let fixed = (Causality::Parameter, Variability::Fixed);
        assert!(settable(fixed.0, fixed.1, State::InitializationMode).is_ok());
        assert!(settable(fixed.0, fixed.1, State::StepComplete).is_err());
        assert!(settable(
            Causality::Parameter,
            Variability::Tunable,
            State::StepComplete
        )
        .is_ok());
        assert!(settable(
            Causality::Output,
            Variability::Continuous,
            State::Instantiated
        )
        .is_err());
    }

    #[test]
    fn an_out_of_range_angle_names_its_unit_and_the_degrees_it_may_have_meant() {
        let four_pi = 4.0 * std::f64::consts::PI;
        let refused = |value: f64, unit: Option<&str>| {
            check_real(
                || "phi_cmd".into(),
                201,
                value,
                Some(Limit::Inclusive(-four_pi)),
                Some(Limit::Inclusive(four_pi)),
                unit,
            )
            .unwrap_err()
            .to_string()
        };
        assert_eq!(
            refused(150.0, Some("rad")),
            "variable phi_cmd (vr 201): value 150 rad is outside [-4π, 4π] rad; did you mean \
             150 deg = 2.618 rad?"
        );
        // no guess that would itself be refused, and no unit for a pure number
        assert_eq!(
            refused(1e4, Some("rad")),
            "variable phi_cmd (vr 201): value 10000 rad is outside [-4π, 4π] rad"
        );
        assert_eq!(
            refused(13.0, Some("1")),
            "variable phi_cmd (vr 201): value 13 is outside [-12.566370614359172, 12.566370614359172]"
        );
        let mass = check_real(
            || "m0".into(),
            113,
            -5.0,
            Some(Limit::Exclusive(0.0)),
            None,
            Some("kg"),
        );
        assert_eq!(
            mass.unwrap_err().to_string(),
            "variable m0 (vr 113): value -5 kg is outside (0, inf) kg"
        );
    }

    #[test]
    fn a_sixty_four_bit_value_is_not_truncated_into_range() {
        // 2^32 + 1 would be 1 as an i32.
        let wide = (1_i64 << 32) + 1;
        assert!(check_integer(|| "n".into(), 1, wide, Some(0), Some(10)).is_err());
        assert!(check_integer(|| "n".into(), 1, 1, Some(0), Some(10)).is_ok());
    }
}
