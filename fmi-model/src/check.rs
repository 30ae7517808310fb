//! The checks every layer relies on, independent of the FMI version: one problem per line.
use crate::declaration::{Causality, Declaration, Dependencies, Kind, Shape, Variability};
use crate::model::Model;
use std::collections::HashSet;

/// Checks `M`'s declarations against `M::default()` (where the start values live); `Ok` or
/// every problem found.
pub fn check_declarations<M: Model>() -> Result<(), Vec<String>> {
    let declarations = M::declarations();
    let fresh = M::default();
    let mut problems = Vec::new();
    let mut names = HashSet::new();
    let mut fields = HashSet::new();
    for d in declarations {
        let mut problem = |text: String| problems.push(format!("{}: {text}", d.name));
        let valid_name = d
            .name
            .chars()
            .next()
            .is_some_and(|c| c.is_ascii_alphabetic())
            && d.name
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '_');
        if !valid_name {
            problem("a name is a letter then letters, digits and underscores".into());
        }
        if !names.insert(d.name) {
            problem("declared twice".into());
        }
        if !d.field.is_empty() && !fields.insert(d.field) {
            problem(format!("field {} is declared by two variables", d.field));
        }
        let settable = Declaration::<M>::settable(crate::Role {
            causality: d.causality,
            variability: d.variability,
            initial: d.initial,
        });
        let has_set = match &d.kind {
            Kind::Real { set, .. } => set.is_some(),
            Kind::Integer { set, .. } | Kind::Enumeration { set, .. } => set.is_some(),
            Kind::Boolean { set, .. } => set.is_some(),
            Kind::String { set, .. } => set.is_some(),
        };
        if settable != has_set {
            problem(format!(
                "a setter exactly for what may be set (has one: {has_set})"
            ));
        }
        let is_real = matches!(d.kind, Kind::Real { .. });
        if !is_real && d.variability == Variability::Continuous {
            problem("only Real variables can be continuous".into());
        }
        if !is_real && d.unit.is_some() {
            problem("only Real variables have a unit".into());
        }
        if let (Shape::Vector(n), false) = (d.shape(), d.components.is_empty()) {
            if d.components.len() != n {
                problem(format!(
                    "{} component words for {n} elements",
                    d.components.len()
                ));
            }
        }
        if d.shape().is_empty() {
            problem("a vector of no elements".into());
        }
        let has_start = matches!(d.causality, Causality::Input | Causality::Parameter)
            || d.variability == Variability::Constant;
        match &d.kind {
            Kind::Real {
                shape,
                min,
                max,
                get,
                ..
            } => {
                if let (Some(lo), Some(hi)) = (min, max) {
                    if lo.value() > hi.value() {
                        problem(format!("min {} > max {}", lo.value(), hi.value()));
                    }
                }
                for i in (0..shape.len()).filter(|_| has_start) {
                    let start = get(&fresh, i);
                    let inside = start.is_finite()
                        && min.is_none_or(|m| m.admits_above(start))
                        && max.is_none_or(|m| m.admits_below(start));
                    if !inside {
                        problem(format!(
                            "start {start} (element {i}) is not finite within the bounds"
                        ));
                    }
                }
            }
            Kind::Integer { min, max, get, .. } => {
                let start = get(&fresh);
                if has_start && (min.is_some_and(|m| start < m) || max.is_some_and(|m| start > m)) {
                    problem(format!("start {start} is outside [min, max]"));
                }
            }
            Kind::Enumeration { ty, get, .. } => {
                if ty.items.is_empty() {
                    problem(format!("enumeration {} has no items", ty.name));
                }
                let values: HashSet<i32> = ty.items.iter().map(|i| i.value).collect();
                let item_names: HashSet<&str> = ty.items.iter().map(|i| i.name).collect();
                if values.len() != ty.items.len() || item_names.len() != ty.items.len() {
                    problem(format!(
                        "enumeration {} repeats an item name or value",
                        ty.name
                    ));
                }
                let start = get(&fresh);
                if has_start && ty.item(start).is_none() {
                    problem(format!("start {start} is not an item of {}", ty.name));
                }
            }
            Kind::Boolean { .. } | Kind::String { .. } => {}
        }
        if d.causality == Causality::Output {
            let named = match M::output_dependencies(d.name) {
                Dependencies::Inputs(inputs) => inputs.to_vec(),
                Dependencies::SameElementOf(input) => {
                    let same_shape = declarations
                        .iter()
                        .find(|i| i.name == input)
                        .is_some_and(|i| i.shape() == d.shape());
                    if !same_shape {
                        problem(format!(
                            "depends element-wise on {input}, which has another shape"
                        ));
                    }
                    vec![input]
                }
                _ => Vec::new(),
            };
            for input in named {
                let is_input = declarations
                    .iter()
                    .any(|v| v.name == input && v.causality == Causality::Input);
                if !is_input {
                    problem(format!("depends on {input}, which is not an input"));
                }
            }
        }
    }
    if let Err(more) = crate::terminal::check_terminals::<M>() {
        problems.extend(more);
    }
    if problems.is_empty() {
        Ok(())
    } else {
        Err(problems)
    }
}
