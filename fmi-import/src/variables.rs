//! Name lookup: variable name -> value reference and type, built once from the model description.
use super::error::{LoadError, VariableError};
use model_description::fmi3::Fmi3Type;
use model_description::{Causality, ModelDescription, Variability, VariableKind};
use std::collections::HashMap;

/// What a master needs to know about one variable to exchange it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct VariableInfo {
    pub value_reference: u32,
    pub kind: VariableKind,
    /// With the FMI 2.0 defaults applied (`local`, `continuous`) when the XML omits them.
    pub causality: Causality,
    pub variability: Variability,
    /// The FMI 3.0 type element (`None` for FMI 2.0). `kind` is its FMI 2.0 counterpart:
    /// Real for Float32, Integer for every integer width, String for Binary; the types that
    /// travel as words ([`crate::word`]) and Binary are exchanged by their own functions.
    pub fmi3_type: Option<Fmi3Type>,
}

impl VariableInfo {
    /// Whether the value travels as a word ([`crate::word`]) rather than through `kind`'s
    /// functions.
    pub fn is_word(&self) -> bool {
        self.fmi3_type.is_some_and(crate::word::is_word)
    }

    /// The type's name as the model description writes it (`UInt64`, `Real`).
    pub fn type_name(&self) -> String {
        match self.fmi3_type {
            Some(kind) => kind.name().to_owned(),
            None => format!("{:?}", self.kind),
        }
    }
}

#[derive(Debug)]
pub(crate) struct VariableIndex {
    model_name: String,
    by_name: HashMap<String, VariableInfo>,
}

impl VariableIndex {
    /// `fmi3_types`: the FMI 3.0 type of each variable of the description, in order (the
    /// scalar view's), or empty for FMI 2.0.
    pub(crate) fn new(
        description: &ModelDescription,
        fmi3_types: &[Fmi3Type],
    ) -> Result<Self, LoadError> {
        let variables = &description.model_variables.variables;
        let mut by_name = HashMap::with_capacity(variables.len());
        for (i, variable) in variables.iter().enumerate() {
            let kind = variable.kind().ok_or_else(|| LoadError::UntypedVariable {
                name: variable.name.clone(),
            })?;
            let info = VariableInfo {
                value_reference: variable.value_reference,
                kind,
                causality: variable.causality_or_default(),
                variability: variable.variability_or_default(),
                fmi3_type: fmi3_types.get(i).copied(),
            };
            if by_name.insert(variable.name.clone(), info).is_some() {
                return Err(LoadError::DuplicateVariableName {
                    name: variable.name.clone(),
                });
            }
        }
        Ok(Self {
            model_name: description.model_name.clone(),
            by_name,
        })
    }

    pub(crate) fn get(&self, name: &str) -> Result<&VariableInfo, VariableError> {
        self.by_name
            .get(name)
            .ok_or_else(|| VariableError::Unknown {
                model: self.model_name.clone(),
                name: name.to_owned(),
            })
    }

    /// The value reference of `name`, if it is exchanged through the `requested` functions.
    pub(crate) fn value_reference(
        &self,
        name: &str,
        requested: VariableKind,
    ) -> Result<u32, VariableError> {
        let info = self.get(name)?;
        let own_functions = info.is_word() || info.fmi3_type == Some(Fmi3Type::Binary);
        // Enumerations travel through the Integer functions.
        if !own_functions && (info.kind == requested || info.kind.accessed_as() == requested) {
            Ok(info.value_reference)
        } else {
            Err(VariableError::TypeMismatch {
                model: self.model_name.clone(),
                name: name.to_owned(),
                actual: info.kind,
                requested,
            })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use model_description::{EnumerationVariable, ModelVariables, RealVariable, ScalarVariable};

    fn description(variables: Vec<ScalarVariable>) -> ModelDescription {
        ModelDescription {
            model_name: "M".into(),
            model_variables: ModelVariables { variables },
            ..Default::default()
        }
    }

    fn real(name: &str, value_reference: u32) -> ScalarVariable {
        ScalarVariable {
            name: name.into(),
            value_reference,
            real: Some(RealVariable::default()),
            ..Default::default()
        }
    }

    #[test]
    fn defaults_of_the_standard_apply_when_attributes_are_absent() {
        let index = VariableIndex::new(&description(vec![real("x", 7)]), &[]).unwrap();
        let info = index.get("x").unwrap();
        assert_eq!(info.value_reference, 7);
        assert_eq!(info.causality, Causality::Local);
        assert_eq!(info.variability, Variability::Continuous);
    }

    #[test]
    fn an_enumeration_is_reached_through_the_integer_functions_only() {
        let mode = ScalarVariable {
            name: "mode".into(),
            value_reference: 3,
            enumeration: Some(EnumerationVariable {
                declared_type: "Mode".into(),
                ..Default::default()
            }),
            ..Default::default()
        };
        let index = VariableIndex::new(&description(vec![mode]), &[]).unwrap();
        assert_eq!(index.value_reference("mode", VariableKind::Integer), Ok(3));
        assert_eq!(
            index.value_reference("mode", VariableKind::Enumeration),
            Ok(3)
        );
        assert!(index.value_reference("mode", VariableKind::Real).is_err());
    }

    #[test]
    fn a_type_mismatch_names_the_variable_and_both_types() {
        let index = VariableIndex::new(&description(vec![real("x", 0)]), &[]).unwrap();
        let error = index
            .value_reference("x", VariableKind::Boolean)
            .unwrap_err();
        let text = error.to_string();
        assert!(
            text.contains("'x'") && text.contains("Real") && text.contains("Boolean"),
            "{text}"
        );
    }

    #[test]
    fn an_unknown_name_is_an_error_naming_it() {
        let index = VariableIndex::new(&description(vec![real("x", 0)]), &[]).unwrap();
        let text = index.get("y").unwrap_err().to_string();
        assert!(text.contains("'y'"), "{text}");
    }

    #[test]
    fn aliases_share_a_value_reference_but_duplicate_names_are_refused() {
        let index = VariableIndex::new(&description(vec![real("x", 1), real("x_alias", 1)]), &[]);
        assert!(index.is_ok());
        let duplicate = VariableIndex::new(&description(vec![real("x", 1), real("x", 2)]), &[]);
        assert!(matches!(duplicate, Err(LoadError::DuplicateVariableName { name }) if name == "x"));
    }

    #[test]
    fn a_variable_without_a_type_element_is_refused() {
        let untyped = ScalarVariable {
            name: "u".into(),
            ..Default::default()
        };
        let result = VariableIndex::new(&description(vec![untyped]), &[]);
        assert!(matches!(result, Err(LoadError::UntypedVariable { name }) if name == "u"));
    }
}
