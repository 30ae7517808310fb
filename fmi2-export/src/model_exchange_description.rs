//! The model description of a model that also offers Model Exchange: the Co-Simulation one
//! plus `<ModelExchange>`, `numberOfEventIndicators`, the `derivative` attribute of each
//! state derivative, `ModelStructure/Derivatives` (in state-vector order) and the states
//! and derivatives among the InitialUnknowns (FMI 2.0 §2.2.8), and the states among the
//! dependencies of outputs and derivatives (`ContinuousModel::state_dependencies`).
use crate::check::check_table;
use crate::description::model_description;
use crate::variable::variables;
use fmi_model::{ContinuousModel, Dependencies, Model};
use model_description as md;

/// The 0-based scalar index of element `element` of the declaration `name`.
fn scalar_index<M: Model>(name: &str, element: usize) -> usize {
    let declarations = M::declarations();
    variables::<M>()
        .iter()
        .position(|v| declarations[v.declaration].name == name && v.element() == element)
        .unwrap_or_else(|| {
            panic!(
                "{}: STATE_DERIVATIVES names {name}[{element}], which is not declared",
                M::MODEL_IDENTIFIER
            )
        })
}

fn element_count<M: Model>(name: &str) -> usize {
    M::declarations()
        .iter()
        .find(|d| d.name == name)
        .map_or(0, |d| d.shape().len())
}

/// The 1-based indices of the continuous states the unknown at `index` (1-based) depends on
/// ([`ContinuousModel::state_dependencies`]).
fn state_indices<M: ContinuousModel>(index: u32) -> Vec<u32> {
    let table = variables::<M>();
    let unknown = &table[index as usize - 1];
    let name = M::declarations()[unknown.declaration].name;
    let states: Vec<&str> = match M::state_dependencies(name) {
        Some(states) => states.to_vec(),
        None => M::STATE_DERIVATIVES.iter().map(|(s, _)| *s).collect(),
    };
    let mut indices = Vec::new();
    for state in states {
        assert!(
            M::STATE_DERIVATIVES.iter().any(|(s, _)| *s == state),
            "{}: state_dependencies({name}) names {state}, which is no continuous state",
            M::MODEL_IDENTIFIER
        );
        indices.extend(
            (0..element_count::<M>(state))
                .filter(|&e| M::depends_on_element(name, unknown.element(), state, e))
                .map(|e| scalar_index::<M>(state, e) as u32 + 1),
        );
    }
    indices
}

/// Whether the scalar at `index` (1-based) depends on the scalar at `known` by
/// [`ContinuousModel::depends_on_element`].
fn element_dependency<M: ContinuousModel>(index: u32, known: u32) -> bool {
    let table = variables::<M>();
    let declarations = M::declarations();
    let (unknown, known) = (&table[index as usize - 1], &table[known as usize - 1]);
    M::depends_on_element(
        declarations[unknown.declaration].name,
        unknown.element(),
        declarations[known.declaration].name,
        known.element(),
    )
}

/// `listed` (the output's input indices, those its elements depend on) with the states the
/// output depends on, sorted.
fn with_states<M: ContinuousModel>(index: u32, listed: &str) -> String {
    let mut indices: Vec<u32> = listed
        .split_whitespace()
        .filter_map(|i| i.parse().ok())
        .filter(|&input| element_dependency::<M>(index, input))
        .chain(state_indices::<M>(index))
        .collect();
    joined(&mut indices)
}

/// The states and inputs the state derivative at `index` (1-based) depends on, sorted.
fn derivative_dependencies<M: ContinuousModel>(index: u32) -> String {
    let table = variables::<M>();
    let name = M::declarations()[table[index as usize - 1].declaration].name;
    let declarations = M::declarations();
    let inputs = table
        .iter()
        .enumerate()
        .filter(|(_, v)| v.causality == fmi_model::Causality::Input)
        .filter(|(_, input)| {
            let input_name = declarations[input.declaration].name;
            match M::derivative_input_dependencies(name) {
                Dependencies::AllInputs => true,
                Dependencies::NoInputs => false,
                Dependencies::Inputs(names) => names.contains(&input_name),
                Dependencies::SameElementOf(of) => {
                    of == input_name && input.element() == table[index as usize - 1].element()
                }
            }
        })
        .map(|(i, _)| i as u32 + 1)
        .filter(|&input| element_dependency::<M>(index, input));
    let mut indices: Vec<u32> = inputs.chain(state_indices::<M>(index)).collect();
    joined(&mut indices)
}

fn joined(indices: &mut Vec<u32>) -> String {
    indices.sort_unstable();
    indices.dedup();
    indices
        .iter()
        .map(u32::to_string)
        .collect::<Vec<_>>()
        .join(" ")
}

/// The states among the dependencies of the outputs, and the derivatives' lists.
fn declare_state_dependencies<M: ContinuousModel>(
    description: &mut md::ModelDescription,
    derivatives: &mut [md::Unknown],
) {
    for derivative in derivatives.iter_mut() {
        derivative.dependencies = Some(derivative_dependencies::<M>(derivative.index));
    }
    if let Some(outputs) = description.model_structure.outputs.as_mut() {
        for output in &mut outputs.unknowns {
            output.dependencies = Some(with_states::<M>(
                output.index,
                output.dependencies.as_deref().unwrap_or_default(),
            ));
        }
    }
}

/// The model description with Model Exchange.
///
/// # Panics
/// If `STATE_DERIVATIVES` names an undeclared variable or pairs vectors of different
/// lengths: a packaging-time error in the model's own table.
pub fn model_description_me<M: ContinuousModel>() -> md::ModelDescription {
    let mut description = model_description::<M>();
    let mut derivatives = Vec::new();
    let mut unknowns: Vec<u32> = description
        .model_structure
        .initial_unknowns
        .as_ref()
        .map(|list| list.unknowns.iter().map(|u| u.index).collect())
        .unwrap_or_default();
    for (state, derivative) in M::STATE_DERIVATIVES {
        let n = element_count::<M>(state);
        assert!(
            n > 0 && n == element_count::<M>(derivative),
            "{}: state {state} and derivative {derivative} differ in length",
            M::MODEL_IDENTIFIER
        );
        for element in 0..n {
            let s = scalar_index::<M>(state, element);
            let d = scalar_index::<M>(derivative, element);
            let real = description.model_variables.variables[d]
                .real
                .as_mut()
                .expect("a derivative is a Real");
            real.derivative = Some(s as u32 + 1);
            derivatives.push(md::Unknown {
                index: d as u32 + 1,
                ..md::Unknown::default()
            });
            unknowns.extend([s as u32 + 1, d as u32 + 1]);
        }
    }
    unknowns.sort_unstable();
    unknowns.dedup();
    if M::DECLARES_STATE_DEPENDENCIES {
        declare_state_dependencies::<M>(&mut description, &mut derivatives);
    }
    description.model_structure.derivatives = Some(md::UnknownList {
        unknowns: derivatives,
    });
    description.model_structure.initial_unknowns = Some(md::UnknownList {
        unknowns: unknowns
            .into_iter()
            .map(|index| md::Unknown {
                index,
                ..md::Unknown::default()
            })
            .collect(),
    });
    description.number_of_event_indicators = Some(M::EVENT_INDICATORS as u32);
    description.model_exchange = Some(md::ModelExchange {
        model_identifier: M::MODEL_IDENTIFIER.into(),
        needs_execution_tool: Some(false),
        completed_integrator_step_not_needed: Some(true),
        can_be_instantiated_only_once_per_process: Some(false),
        can_not_use_memory_management_functions: Some(true),
        can_get_and_set_fmu_state: Some(true),
        can_serialize_fmu_state: Some(true),
        provides_directional_derivative: Some(M::PROVIDES_DIRECTIONAL_DERIVATIVES),
    });
    description
}

/// [`model_description_me`] as `modelDescription.xml`.
///
/// # Panics
/// As [`crate::model_description_xml`].
pub fn model_description_xml_me<M: ContinuousModel>() -> String {
    if let Err(e) = check_table::<M>() {
        panic!("{e}");
    }
    model_description_me::<M>().to_xml().unwrap_or_else(|e| {
        panic!(
            "cannot write the model description of {}: {e}",
            M::MODEL_IDENTIFIER
        )
    })
}
