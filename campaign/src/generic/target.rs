//! What a swept or dispersed input sets: today a parameter `instance.variable` of the
//! scenario's FMUs. Every target is parsed and checked here alone, so that another kind (a
//! scenario event's time, say `event.NAME.time`) is one more variant and one more check.
use cosim::system::SystemDescription;
use model_description::{Causality, ModelDescription, Variability, VariableKind};

#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Target {
    /// A Real parameter of an instance, set before each run is initialised.
    Parameter { instance: String, variable: String },
}

impl Target {
    /// `instance.variable` (the variable's name may hold dots; the instance's does not).
    pub fn parse(text: &str) -> Result<Self, String> {
        match text.split_once('.') {
            Some((instance, variable)) if !instance.is_empty() && !variable.is_empty() => {
                Ok(Target::Parameter {
                    instance: instance.to_owned(),
                    variable: variable.to_owned(),
                })
            }
            _ => Err(format!(
                "parameter = \"{text}\" is not of the form \"instance.variable\""
            )),
        }
    }

    /// Why `system` (whose instance `i` is described by `describe(i)`) cannot take this
    /// target, if it cannot: an unknown instance or variable, or one a run cannot set.
    pub fn problem<'a>(
        &self,
        system: &SystemDescription,
        describe: impl Fn(usize) -> &'a ModelDescription,
    ) -> Option<String> {
        let Target::Parameter { instance, variable } = self;
        let Some(index) = system.instances.iter().position(|i| &i.name == instance) else {
            let known: Vec<&str> = system.instances.iter().map(|i| i.name.as_str()).collect();
            return Some(format!(
                "parameter = \"{instance}.{variable}\": the scenario has no instance \
                 '{instance}' (it has {})",
                known.join(", ")
            ));
        };
        let description = describe(index);
        let Some(declared) = description.variable(variable) else {
            return Some(format!(
                "parameter = \"{instance}.{variable}\": {} declares no variable '{variable}'",
                description.model_name
            ));
        };
        let causality = declared.causality_or_default();
        let variability = declared.variability_or_default();
        if causality != Causality::Parameter
            || !matches!(variability, Variability::Fixed | Variability::Tunable)
        {
            return Some(format!(
                "parameter = \"{instance}.{variable}\": '{variable}' has causality \
                 {causality:?} and variability {variability:?}; a campaign sets parameters \
                 (causality Parameter, variability Fixed or Tunable)"
            ));
        }
        if declared.kind() != Some(VariableKind::Real) {
            return Some(format!(
                "parameter = \"{instance}.{variable}\": '{variable}' is not a Real; a \
                 campaign draws and sweeps real numbers"
            ));
        }
        None
    }
}

impl std::fmt::Display for Target {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let Target::Parameter { instance, variable } = self;
        write!(f, "{instance}.{variable}")
    }
}
