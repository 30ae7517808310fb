//! Partial derivatives of an FMU: whether it declares that it computes them (checked before
//! any derivative function is called), and the structure its model description declares (the
//! continuous states and which states and inputs each derivative and output depends on), which
//! a master uses for sparsity. Version-neutral: an FMI 3.0 description is read through its
//! scalar view (`fmi3/view.rs`), so every value reference here is the one gets and sets use.
use crate::model_exchange::Interface;
use crate::version::FmiVersion;
use model_description::ModelDescription;

/// One unknown of `ModelStructure` and the knowns it depends on.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Dependencies {
    /// Value reference of the derivative or output.
    pub unknown: u32,
    /// Value references it depends on; `None` when the description leaves them out, which
    /// the standard reads as "on every known".
    pub knowns: Option<Vec<u32>>,
}

impl Dependencies {
    /// Whether `known` may change `unknown` (true when the list is not declared).
    pub fn depends_on(&self, known: u32) -> bool {
        self.knowns
            .as_ref()
            .is_none_or(|list| list.contains(&known))
    }
}

/// The structure a model description declares for derivatives.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Structure {
    /// The continuous states' value references, in the order of the state vector.
    pub states: Vec<u32>,
    /// Per state, its derivative and what it depends on (`derivatives[i]` is `der(states[i])`).
    pub derivatives: Vec<Dependencies>,
    /// The outputs and what each depends on.
    pub outputs: Vec<Dependencies>,
}

/// The structure of `description`; the error names the entry that does not resolve.
pub fn structure(description: &ModelDescription) -> Result<Structure, String> {
    let variables = &description.model_variables.variables;
    let model = &description.model_name;
    let at = |index: u32, list: &str| {
        variables
            .get((index as usize).wrapping_sub(1))
            .ok_or_else(|| {
                format!(
                    "model '{model}': ModelStructure/{list} names variable index {index}, \
                     beyond its {} variables",
                    variables.len()
                )
            })
    };
    let read = |list: &Option<model_description::UnknownList>,
                name: &str|
     -> Result<Vec<Dependencies>, String> {
        let Some(list) = list else {
            return Ok(Vec::new());
        };
        list.unknowns
            .iter()
            .map(|unknown| {
                let knowns = match &unknown.dependencies {
                    None => None,
                    Some(text) => Some(
                        text.split_whitespace()
                            .map(|index| {
                                let index = index.parse::<u32>().map_err(|_| {
                                    format!(
                                        "model '{model}': ModelStructure/{name} dependency \
                                         {index:?} is not an index"
                                    )
                                })?;
                                Ok(at(index, name)?.value_reference)
                            })
                            .collect::<Result<Vec<_>, String>>()?,
                    ),
                };
                Ok(Dependencies {
                    unknown: at(unknown.index, name)?.value_reference,
                    knowns,
                })
            })
            .collect()
    };
    let structure = &description.model_structure;
    let derivatives = read(&structure.derivatives, "Derivatives")?;
    let states = structure
        .derivatives
        .iter()
        .flat_map(|list| &list.unknowns)
        .map(|unknown| {
            let derivative = at(unknown.index, "Derivatives")?;
            let state = derivative
                .real
                .as_ref()
                .and_then(|real| real.derivative)
                .ok_or_else(|| {
                    format!(
                        "model '{model}': '{}' is listed as a state derivative but names no \
                         state (its derivative attribute)",
                        derivative.name
                    )
                })?;
            Ok(at(state, "Derivatives")?.value_reference)
        })
        .collect::<Result<Vec<_>, String>>()?;
    Ok(Structure {
        states,
        derivatives,
        outputs: read(&structure.outputs, "Outputs")?,
    })
}

/// Why directional (or, with `adjoint`, adjoint) derivatives of an instance of `interface`
/// cannot be asked for, from the capability flags; `None` when they can. Both standards
/// default the flags to false, and an FMU that does not declare one need not implement the
/// function: it is not called.
pub fn refusal(
    description: &ModelDescription,
    fmi3: Option<&model_description::fmi3::Fmi3ModelDescription>,
    interface: Interface,
    adjoint: bool,
) -> Option<String> {
    let version = if fmi3.is_some() {
        FmiVersion::Fmi3
    } else {
        FmiVersion::Fmi2
    };
    let element = match interface {
        Interface::CoSimulation => "CoSimulation",
        Interface::ModelExchange => "ModelExchange",
    };
    let model = &description.model_name;
    if adjoint {
        let Some(fmi3) = fmi3 else {
            return Some(format!(
                "model '{model}' is an FMI 2.0 FMU; adjoint derivatives are FMI 3.0's"
            ));
        };
        let declared = match interface {
            Interface::CoSimulation => fmi3
                .co_simulation
                .as_ref()
                .is_some_and(|cs| cs.provides_adjoint_derivatives),
            Interface::ModelExchange => fmi3
                .model_exchange_flags
                .as_ref()
                .is_some_and(|me| me.provides_adjoint_derivatives),
        };
        return (!declared).then(|| {
            format!(
                "model '{model}' does not declare providesAdjointDerivatives=\"true\" in its \
                 <{element}> element"
            )
        });
    }
    let declared = match interface {
        Interface::CoSimulation => description
            .co_simulation
            .as_ref()
            .and_then(|cs| cs.provides_directional_derivative),
        Interface::ModelExchange => description
            .model_exchange
            .as_ref()
            .and_then(|me| me.provides_directional_derivative),
    };
    let flag = match version {
        FmiVersion::Fmi2 => "providesDirectionalDerivative",
        FmiVersion::Fmi3 => "providesDirectionalDerivatives",
    };
    (declared != Some(true)).then(|| {
        format!("model '{model}' does not declare {flag}=\"true\" in its <{element}> element")
    })
}
