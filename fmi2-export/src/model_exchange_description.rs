//! The model description of a model that also offers Model Exchange: the Co-Simulation one
//! plus `<ModelExchange>`, `numberOfEventIndicators`, the `derivative` attribute of each
//! state derivative, `ModelStructure/Derivatives` (in state-vector order) and the states
//! and derivatives among the InitialUnknowns (FMI 2.0 §2.2.8).
use crate::check::check_table;
use crate::description::model_description;
use crate::variable::variables;
use fmi_model::{ContinuousModel, Model};
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
        provides_directional_derivative: Some(false),
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
