//! What a master asks of a model description: look variables up, read their typed start
//! values, and apply the FMI 2.0 defaults for absent attributes.
use crate::{
    Causality, CoSimulation, Initial, ModelDescription, ScalarVariable, SimpleType, Unit,
    Variability,
};

/// The type element of a ScalarVariable.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum VariableKind {
    Real,
    Integer,
    Boolean,
    String,
    Enumeration,
}

impl VariableKind {
    /// The kind whose `fmi2Get*`/`fmi2Set*` functions access this one: enumerations go
    /// through the Integer functions and share the Integer value-reference space.
    pub fn accessed_as(self) -> VariableKind {
        match self {
            VariableKind::Enumeration => VariableKind::Integer,
            other => other,
        }
    }
}

/// A start value, typed by the variable's type element.
#[derive(Debug, Clone, PartialEq)]
pub enum StartValue {
    Real(f64),
    Integer(i32),
    Boolean(bool),
    String(String),
    Enumeration(i32),
}

impl ScalarVariable {
    /// The kind of the type element; `None` only for a hand-built variable without one
    /// (`from_xml` refuses such files and [`ModelDescription::validate`] reports them).
    pub fn kind(&self) -> Option<VariableKind> {
        if self.real.is_some() {
            Some(VariableKind::Real)
        } else if self.integer.is_some() {
            Some(VariableKind::Integer)
        } else if self.boolean.is_some() {
            Some(VariableKind::Boolean)
        } else if self.string.is_some() {
            Some(VariableKind::String)
        } else if self.enumeration.is_some() {
            Some(VariableKind::Enumeration)
        } else {
            None
        }
    }

    /// Number of type elements present; exactly one in a valid description.
    pub(crate) fn type_element_count(&self) -> usize {
        [
            self.real.is_some(),
            self.integer.is_some(),
            self.boolean.is_some(),
            self.string.is_some(),
            self.enumeration.is_some(),
        ]
        .into_iter()
        .filter(|present| *present)
        .count()
    }

    pub fn start(&self) -> Option<StartValue> {
        if let Some(real) = &self.real {
            real.start.map(StartValue::Real)
        } else if let Some(integer) = &self.integer {
            integer.start.map(StartValue::Integer)
        } else if let Some(boolean) = &self.boolean {
            boolean.start.map(StartValue::Boolean)
        } else if let Some(string) = &self.string {
            string.start.clone().map(StartValue::String)
        } else {
            self.enumeration
                .as_ref()
                .and_then(|e| e.start)
                .map(StartValue::Enumeration)
        }
    }

    /// The `declaredType` of whichever type element is present.
    pub fn declared_type(&self) -> Option<&str> {
        if let Some(real) = &self.real {
            real.declared_type.as_deref()
        } else if let Some(integer) = &self.integer {
            integer.declared_type.as_deref()
        } else if let Some(boolean) = &self.boolean {
            boolean.declared_type.as_deref()
        } else if let Some(string) = &self.string {
            string.declared_type.as_deref()
        } else {
            self.enumeration.as_ref().map(|e| e.declared_type.as_str())
        }
    }

    /// FMI 2.0 §2.2.7: an absent `causality` means `local`.
    pub fn causality_or_default(&self) -> Causality {
        self.causality.unwrap_or(Causality::Local)
    }

    /// FMI 2.0 §2.2.7: an absent `variability` means `continuous`.
    pub fn variability_or_default(&self) -> Variability {
        self.variability.unwrap_or(Variability::Continuous)
    }

    /// The explicit `initial`, or the default of FMI 2.0 §2.2.7 for this causality and
    /// variability; `None` where the standard allows no `initial` (inputs, the independent
    /// variable, and combinations it forbids).
    pub fn initial_or_default(&self) -> Option<Initial> {
        self.initial.or_else(|| {
            use {Causality as C, Variability as V};
            match (self.causality_or_default(), self.variability_or_default()) {
                (C::Output | C::Local, V::Constant) => Some(Initial::Exact),
                (C::Parameter, V::Fixed | V::Tunable) => Some(Initial::Exact),
                (C::CalculatedParameter | C::Local, V::Fixed | V::Tunable) => {
                    Some(Initial::Calculated)
                }
                (C::Output | C::Local, V::Discrete | V::Continuous) => Some(Initial::Calculated),
                _ => None,
            }
        })
    }
}

impl ModelDescription {
    pub fn variables(&self) -> impl Iterator<Item = &ScalarVariable> {
        self.model_variables.variables.iter()
    }

    pub fn variable(&self, name: &str) -> Option<&ScalarVariable> {
        self.variables().find(|v| v.name == name)
    }

    /// The variable at a 1-based `ModelStructure` index.
    pub fn variable_at(&self, index: u32) -> Option<&ScalarVariable> {
        let zero_based = usize::try_from(index).ok()?.checked_sub(1)?;
        self.model_variables.variables.get(zero_based)
    }

    /// The 1-based `ModelStructure` index of the named variable.
    pub fn index_of(&self, name: &str) -> Option<u32> {
        let position = self.variables().position(|v| v.name == name)?;
        u32::try_from(position + 1).ok()
    }

    /// Every variable accessed through the same `fmi2Get*` function and value reference,
    /// i.e. `vr` and its aliases.
    pub fn variables_with_reference(
        &self,
        kind: VariableKind,
        value_reference: u32,
    ) -> impl Iterator<Item = &ScalarVariable> {
        self.variables().filter(move |v| {
            v.value_reference == value_reference
                && v.kind().map(VariableKind::accessed_as) == Some(kind.accessed_as())
        })
    }

    pub fn with_causality(&self, causality: Causality) -> impl Iterator<Item = &ScalarVariable> {
        self.variables()
            .filter(move |v| v.causality_or_default() == causality)
    }

    pub fn inputs(&self) -> impl Iterator<Item = &ScalarVariable> {
        self.with_causality(Causality::Input)
    }

    pub fn outputs(&self) -> impl Iterator<Item = &ScalarVariable> {
        self.with_causality(Causality::Output)
    }

    pub fn parameters(&self) -> impl Iterator<Item = &ScalarVariable> {
        self.with_causality(Causality::Parameter)
    }

    pub fn co_simulation(&self) -> Option<&CoSimulation> {
        self.co_simulation.as_ref()
    }

    /// The `modelIdentifier` of the Co-Simulation interface: the shared library's file name.
    pub fn co_simulation_identifier(&self) -> Option<&str> {
        self.co_simulation().map(|cs| cs.model_identifier.as_str())
    }

    pub fn unit(&self, name: &str) -> Option<&Unit> {
        self.unit_definitions
            .as_ref()?
            .units
            .iter()
            .find(|u| u.name == name)
    }

    pub fn simple_type(&self, name: &str) -> Option<&SimpleType> {
        self.type_definitions
            .as_ref()?
            .simple_types
            .iter()
            .find(|t| t.name == name)
    }

    /// A Real variable's unit: its own `unit`, else the one of its declared type.
    pub fn unit_of<'a>(&'a self, variable: &'a ScalarVariable) -> Option<&'a str> {
        let real = variable.real.as_ref()?;
        real.unit.as_deref().or_else(|| {
            let declared = self.simple_type(real.declared_type.as_deref()?)?;
            declared.real.as_ref()?.unit.as_deref()
        })
    }
}

impl crate::types::Causality {
    /// The attribute value as `modelDescription.xml` spells it.
    pub fn name(self) -> &'static str {
        use crate::types::Causality::*;
        match self {
            Parameter => "parameter",
            CalculatedParameter => "calculatedParameter",
            Input => "input",
            Output => "output",
            Local => "local",
            Independent => "independent",
        }
    }

    /// The causality an attribute value names.
    pub fn from_name(name: &str) -> Option<Self> {
        use crate::types::Causality::*;
        [
            Parameter,
            CalculatedParameter,
            Input,
            Output,
            Local,
            Independent,
        ]
        .into_iter()
        .find(|c| c.name() == name)
    }
}

impl crate::types::Variability {
    /// The attribute value as `modelDescription.xml` spells it.
    pub fn name(self) -> &'static str {
        use crate::types::Variability::*;
        match self {
            Constant => "constant",
            Fixed => "fixed",
            Tunable => "tunable",
            Discrete => "discrete",
            Continuous => "continuous",
        }
    }
}
