//! Semantic checks that the schema cannot express. Kept to what a master or another tool
//! would trip over; each problem is one self-contained sentence naming the variable.
use std::collections::HashSet;

use crate::{
    Causality, Initial, ModelDescription, ScalarVariable, UnknownList, Variability, VariableKind,
};

impl ModelDescription {
    /// Checks: fmiVersion "2.0"; a ModelExchange or CoSimulation element; unique variable
    /// names; one type element per variable; declared types and units that exist; a legal
    /// causality/variability pair, no `initial` on inputs; start values where FMI 2.0
    /// requires or forbids them; `derivative` and ModelStructure
    /// indices in range, with Outputs listing exactly the outputs.
    pub fn validate(&self) -> Result<(), Vec<String>> {
        let mut problems = Vec::new();
        if self.fmi_version != "2.0" {
            problems.push(format!(
                "fmiVersion is \"{}\", expected \"2.0\"",
                self.fmi_version
            ));
        }
        if self.model_exchange.is_none() && self.co_simulation.is_none() {
            problems.push("neither <ModelExchange> nor <CoSimulation> is present".to_owned());
        }
        for simple in self.type_definitions.iter().flat_map(|t| &t.simple_types) {
            let unit = simple.real.as_ref().and_then(|real| real.unit.as_ref());
            if let Some(unit) = unit.filter(|unit| self.unit(unit).is_none()) {
                problems.push(format!(
                    "SimpleType '{}': unit \"{unit}\" is not in UnitDefinitions",
                    simple.name
                ));
            }
        }
        let mut names = HashSet::new();
        for (position, variable) in self.variables().enumerate() {
            let at = format!(
                "ScalarVariable '{}' (index {})",
                variable.name,
                position + 1
            );
            if !names.insert(variable.name.as_str()) {
                problems.push(format!("{at}: the name is used by an earlier variable"));
            }
            self.check_variable(variable, &at, &mut problems);
        }
        self.check_model_structure(&mut problems);
        if problems.is_empty() {
            Ok(())
        } else {
            Err(problems)
        }
    }

    fn check_variable(&self, variable: &ScalarVariable, at: &str, problems: &mut Vec<String>) {
        let count = variable.type_element_count();
        if count != 1 {
            problems.push(format!(
                "{at}: has {count} type elements, expected exactly one"
            ));
            return;
        }
        if let Some(declared) = variable.declared_type() {
            match self.simple_type(declared) {
                None => problems.push(format!(
                    "{at}: declaredType \"{declared}\" is not in TypeDefinitions"
                )),
                Some(simple) if simple_type_kind(simple) != variable.kind() => {
                    problems.push(format!(
                        "{at}: declaredType \"{declared}\" is not a {:?} type",
                        variable.kind().unwrap_or(VariableKind::Real)
                    ))
                }
                Some(_) => {}
            }
        }
        if let Some(real) = &variable.real {
            if let Some(unit) = real.unit.as_ref().filter(|unit| self.unit(unit).is_none()) {
                problems.push(format!("{at}: unit \"{unit}\" is not in UnitDefinitions"));
            }
            if let Some(display) = &real.display_unit {
                let unit = self.unit_of(variable);
                let defined = unit
                    .and_then(|unit| self.unit(unit))
                    .is_some_and(|u| u.display_units.iter().any(|d| &d.name == display));
                if !defined {
                    problems.push(format!(
                        "{at}: displayUnit \"{display}\" is not a DisplayUnit of unit \"{}\"",
                        unit.unwrap_or_default()
                    ));
                }
            }
            if let Some(derivative) = real.derivative {
                if self
                    .variable_at(derivative)
                    .and_then(|v| v.real.as_ref())
                    .is_none()
                {
                    problems.push(format!(
                        "{at}: derivative=\"{derivative}\" is not the index of a Real variable"
                    ));
                }
            }
        }
        let causality = variable.causality_or_default();
        let variability = variable.variability_or_default();
        if !legal_combination(causality, variability) {
            problems.push(format!(
                "{at}: causality {causality:?} with variability {variability:?} is not a combination FMI 2.0 allows"
            ));
        }
        if variable.initial.is_some()
            && matches!(causality, Causality::Input | Causality::Independent)
        {
            problems.push(format!(
                "{at}: an {causality:?} variable may not have an initial attribute"
            ));
        }
        let has_start = variable.start().is_some();
        let initial = variable.initial_or_default();
        let start_required = matches!(causality, Causality::Input | Causality::Parameter)
            || matches!(initial, Some(Initial::Exact | Initial::Approx));
        let start_forbidden =
            causality == Causality::Independent || initial == Some(Initial::Calculated);
        if start_required && !has_start {
            problems.push(format!(
                "{at}: has no start value, which its causality/initial requires"
            ));
        }
        if start_forbidden && has_start {
            problems.push(format!(
                "{at}: has a start value, which FMI 2.0 forbids for a calculated or independent variable"
            ));
        }
    }

    fn check_model_structure(&self, problems: &mut Vec<String>) {
        let structure = &self.model_structure;
        let lists = [
            ("Outputs", &structure.outputs),
            ("Derivatives", &structure.derivatives),
            ("InitialUnknowns", &structure.initial_unknowns),
        ];
        for (list_name, list) in lists {
            let Some(UnknownList { unknowns }) = list else {
                continue;
            };
            for (position, unknown) in unknowns.iter().enumerate() {
                let at = format!("ModelStructure > {list_name} > Unknown #{}", position + 1);
                let Some(variable) = self.variable_at(unknown.index) else {
                    problems.push(format!(
                        "{at}: index {} is not the index of a variable (1..={})",
                        unknown.index,
                        self.model_variables.variables.len()
                    ));
                    continue;
                };
                if list_name == "Outputs" && variable.causality_or_default() != Causality::Output {
                    problems.push(format!("{at}: '{}' is not an output", variable.name));
                }
                if list_name == "Derivatives"
                    && variable.real.as_ref().and_then(|r| r.derivative).is_none()
                {
                    problems.push(format!("{at}: '{}' is not a derivative", variable.name));
                }
                let dependencies: Vec<&str> = unknown
                    .dependencies
                    .as_deref()
                    .map(|d| d.split_ascii_whitespace().collect())
                    .unwrap_or_default();
                for dependency in &dependencies {
                    let in_range = dependency
                        .parse::<u32>()
                        .ok()
                        .and_then(|index| self.variable_at(index))
                        .is_some();
                    if !in_range {
                        problems.push(format!(
                            "{at}: dependency \"{dependency}\" is not the index of a variable"
                        ));
                    }
                }
                if let Some(kinds) = &unknown.dependencies_kind {
                    let kinds = kinds.split_ascii_whitespace().count();
                    if kinds != dependencies.len() {
                        problems.push(format!(
                            "{at}: {kinds} dependenciesKind entries for {} dependencies",
                            dependencies.len()
                        ));
                    }
                }
            }
        }
        let listed: HashSet<u32> = structure
            .outputs
            .iter()
            .flat_map(|list| &list.unknowns)
            .map(|unknown| unknown.index)
            .collect();
        for (position, variable) in self.variables().enumerate() {
            let index = u32::try_from(position + 1).unwrap_or(u32::MAX);
            if variable.causality_or_default() == Causality::Output && !listed.contains(&index) {
                problems.push(format!(
                    "ScalarVariable '{}' (index {index}): an output missing from ModelStructure > Outputs",
                    variable.name
                ));
            }
        }
    }
}

/// The cells of the causality/variability table in FMI 2.0 §2.2.7 that are not forbidden.
fn legal_combination(causality: Causality, variability: Variability) -> bool {
    use {Causality as C, Variability as V};
    match variability {
        V::Constant => matches!(causality, C::Output | C::Local),
        V::Fixed | V::Tunable => {
            matches!(causality, C::Parameter | C::CalculatedParameter | C::Local)
        }
        V::Discrete => matches!(causality, C::Input | C::Output | C::Local),
        V::Continuous => matches!(causality, C::Input | C::Output | C::Local | C::Independent),
    }
}

fn simple_type_kind(simple: &crate::SimpleType) -> Option<VariableKind> {
    if simple.real.is_some() {
        Some(VariableKind::Real)
    } else if simple.integer.is_some() {
        Some(VariableKind::Integer)
    } else if simple.boolean.is_some() {
        Some(VariableKind::Boolean)
    } else if simple.string.is_some() {
        Some(VariableKind::String)
    } else if simple.enumeration.is_some() {
        Some(VariableKind::Enumeration)
    } else {
        None
    }
}
