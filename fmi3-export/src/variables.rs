//! The FMI 3.0 view of a model's declarations: one variable per declaration (a vector is
//! one Float64 array with one `Dimension`), found by its value reference.
use fmi_model::{Causality, Declaration, Kind, Model, Variability};
use std::collections::HashMap;

/// Value reference of the independent variable `time`, which FMI 3.0 requires to be
/// declared; far above the model's own value references (checked by `check`).
pub const TIME_VR: u32 = 999_999;

/// The FMI 3.0 type of a declaration.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Type {
    Float64,
    Int32,
    /// An enumeration: exchanged as Int64 through the API.
    Enumeration,
    Boolean,
    String,
}

impl Type {
    pub fn of<M>(d: &Declaration<M>) -> Type {
        match d.kind {
            Kind::Real { .. } => Type::Float64,
            Kind::Integer { .. } => Type::Int32,
            // A selector every master must be able to set is exchanged as a plain Int32.
            Kind::Enumeration {
                as_integer: true, ..
            } => Type::Int32,
            Kind::Enumeration { .. } => Type::Enumeration,
            Kind::Boolean { .. } => Type::Boolean,
            Kind::String { .. } => Type::String,
        }
    }

    /// The name of the get/set functions' type and of the XML element.
    pub fn api_name(self) -> &'static str {
        match self {
            Type::Float64 => "Float64",
            Type::Int32 => "Int32",
            Type::Enumeration => "Int64 (Enumeration)",
            Type::Boolean => "Boolean",
            Type::String => "String",
        }
    }
}

/// Value reference -> position in `M::declarations()`.
pub struct Index {
    rows: HashMap<u32, usize>,
}

impl Index {
    pub fn new<M: Model>() -> Index {
        Index {
            rows: M::declarations()
                .iter()
                .enumerate()
                .map(|(i, d)| (d.value_reference, i))
                .collect(),
        }
    }

    pub fn get<M: Model>(&self, vr: u32) -> Option<&'static Declaration<M>> {
        self.rows.get(&vr).map(|&i| &M::declarations()[i])
    }
}

/// The problems that would make an invalid FMI 3.0 description (duplicate value
/// references, a clash with `time`); empty when there are none.
pub fn check<M: Model>() -> Vec<String> {
    let mut problems = Vec::new();
    let mut seen: HashMap<u32, &str> = HashMap::new();
    for d in M::declarations() {
        if d.value_reference == TIME_VR {
            problems.push(format!("{}: value reference {TIME_VR} is `time`'s", d.name));
        }
        if let Some(other) = seen.insert(d.value_reference, d.name) {
            problems.push(format!(
                "{} and {other} share value reference {}",
                d.name, d.value_reference
            ));
        }
    }
    problems
}

/// Why the master may not set `d` in `state`, if it may not.
pub fn settable<M>(d: &Declaration<M>, initializing: bool) -> Result<(), &'static str> {
    if d.variability == Variability::Constant {
        return Err("a constant is never settable");
    }
    match d.causality {
        Causality::Input => Ok(()),
        Causality::Parameter => {
            if d.variability == Variability::Tunable || initializing {
                Ok(())
            } else {
                Err("a fixed parameter can only be set before fmi3ExitInitializationMode")
            }
        }
        Causality::Output => Err("an output is computed by the FMU"),
        Causality::CalculatedParameter => Err("a calculated parameter is computed by the FMU"),
        Causality::Local => Err("a local variable is computed by the FMU"),
        Causality::Independent => Err("the independent variable is set by the master's calls"),
    }
}
