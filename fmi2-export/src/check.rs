//! `check_table`: the rules of FMI 2.0 §2.2.7 that the scalar view of a model's
//! declarations must keep (plus the version-neutral checks of `fmi-model`), checked in the
//! model crates' tests and before any XML is written.
use crate::index::BaseType;
use crate::model::Model;
use crate::variable::{effective_initial, initial_rule, variables, Access, Causality, Initial};
use fmi_export::base_unit;
use std::collections::HashSet;

/// Everything wrong with a table, one line per problem.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("invalid variable table of {model}:\n  {}", problems.join("\n  "))]
pub struct TableError {
    pub model: &'static str,
    pub problems: Vec<String>,
}

/// Checks a model's table and declarations; `Ok` or every problem found.
pub fn check_table<M: Model>() -> Result<(), TableError> {
    let mut problems = fmi_model::check_declarations::<M>()
        .err()
        .unwrap_or_default();
    let table = variables::<M>();
    let mut names = HashSet::new();
    let mut references = HashSet::new();

    if !is_c_identifier(M::MODEL_IDENTIFIER) {
        problems.push(format!(
            "modelIdentifier {:?} is not a C identifier",
            M::MODEL_IDENTIFIER
        ));
    }
    let e = M::DEFAULT_EXPERIMENT;
    if !(e.start_time.is_finite() && e.stop_time > e.start_time && e.step_size > 0.0) {
        problems.push(format!(
            "DefaultExperiment {e:?} is not a forward time span with a positive step"
        ));
    }
    for var in &table {
        let name = var.name();
        let mut problem = |text: String| problems.push(format!("{name}: {text}"));
        if name.is_empty() || name.chars().any(char::is_whitespace) {
            problem("name is empty or contains white space".into());
        }
        if !names.insert(name.clone()) {
            problem("FMI 2.0 name used twice".into());
        }
        let base = BaseType::of(&var.access);
        if !references.insert((base, var.value_reference)) {
            problem(format!(
                "value reference {} used twice among {} variables",
                var.value_reference,
                base.name()
            ));
        }

        let Some((_, allowed)) = initial_rule(var.causality, var.variability) else {
            problem(format!(
                "causality {:?} with variability {:?} is not allowed",
                var.causality, var.variability
            ));
            continue;
        };
        if let Some(initial) = var.initial {
            if !allowed.contains(&initial) {
                problem(format!(
                    "initial {initial:?} is not allowed for {:?}/{:?} (allowed: {allowed:?})",
                    var.causality, var.variability
                ));
            }
        }
        let needs_start = var.causality == Causality::Input
            || matches!(
                effective_initial(var),
                Some(Initial::Exact | Initial::Approx)
            );
        let has_start = match &var.access {
            Access::Real { start, .. } => start.is_some(),
            Access::Integer { start, .. } | Access::Enumeration { start, .. } => start.is_some(),
            Access::Boolean { start, .. } => start.is_some(),
            // A String's start is read from `M::default()` exactly where one is needed.
            Access::String { .. } => needs_start,
        };
        // Start values are read from `M::default()` exactly where the standard asks for one.
        if needs_start != has_start {
            problem(format!(
                "start value {} (causality {:?}, initial {:?})",
                if needs_start {
                    "required"
                } else {
                    "not allowed"
                },
                var.causality,
                effective_initial(var)
            ));
        }
        match &var.access {
            Access::Real { .. } => match var.unit {
                Some(u) if base_unit(u).is_none() => problem(format!(
                    "unit {u:?} is not in the unit table of fmi2-export (src/units.rs)"
                )),
                _ => {}
            },
            Access::Enumeration { ty, .. } => {
                let same_name = table.iter().any(|v| {
                    matches!(&v.access, Access::Enumeration { ty: other, .. }
                        if other.name == ty.name && other != ty)
                });
                if same_name {
                    problem(format!(
                        "two different enumeration types are named {}",
                        ty.name
                    ));
                }
            }
            Access::Integer { .. } | Access::Boolean { .. } | Access::String { .. } => {}
        }
    }

    if problems.is_empty() {
        Ok(())
    } else {
        Err(TableError {
            model: M::MODEL_IDENTIFIER,
            problems,
        })
    }
}

fn is_c_identifier(s: &str) -> bool {
    let mut chars = s.chars();
    chars
        .next()
        .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn c_identifiers() {
        assert!(is_c_identifier("LanderGnc"));
        assert!(is_c_identifier("_x1"));
        assert!(!is_c_identifier("1x"));
        assert!(!is_c_identifier("a-b"));
        assert!(!is_c_identifier(""));
    }
}
