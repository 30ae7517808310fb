//! `modelDescription.xml` and the GUID, both produced from the variable table.
use crate::check::check_table;
use crate::model::{Dependencies, Model};
use crate::variable::effective_initial;
use crate::variable::{variables, Access, Causality, EnumType, Initial, Variability, Variable};
use crate::version::CATEGORIES;
use fmi_export::base_unit;
use model_description as md;
use std::collections::BTreeSet;
use std::fmt::Write;
use uuid::Uuid;

/// The UUID v5 of the interface: modelIdentifier and, per variable in table order, name,
/// value reference, type, causality and variability (plus enumeration items, since they
/// define what an Integer value means). Descriptions, units, start values and bounds are
/// not interface: changing them keeps the GUID, so saved FMU states stay loadable.
pub fn interface_uuid<M: Model>() -> Uuid {
    let namespace = Uuid::new_v5(
        &Uuid::NAMESPACE_URL,
        b"urn:lander-fmi:fmi2-export:interface",
    );
    let mut text = format!("modelIdentifier={}\n", M::MODEL_IDENTIFIER);
    for var in variables::<M>() {
        let type_name = match &var.access {
            Access::Real { .. } => "Real".to_string(),
            Access::Integer { .. } => "Integer".to_string(),
            Access::Boolean { .. } => "Boolean".to_string(),
            Access::String { .. } => "String".to_string(),
            Access::Enumeration {
                as_integer: true, ..
            } => "Integer".to_string(),
            Access::Enumeration { ty, .. } => {
                let items: Vec<String> = ty
                    .items
                    .iter()
                    .map(|i| format!("{}={}", i.name, i.value))
                    .collect();
                format!("Enumeration {} [{}]", ty.name, items.join(","))
            }
        };
        let _ = writeln!(
            text,
            "{}\t{}\t{type_name}\t{:?}\t{:?}",
            var.name(),
            var.value_reference,
            var.causality,
            var.variability
        );
    }
    Uuid::new_v5(&namespace, text.as_bytes())
}

/// The `guid` attribute: `{xxxxxxxx-xxxx-5xxx-xxxx-xxxxxxxxxxxx}`.
pub fn guid<M: Model>() -> String {
    format!("{{{}}}", interface_uuid::<M>())
}

/// The model description, as a struct.
pub fn model_description<M: Model>() -> md::ModelDescription {
    let table = variables::<M>();
    let e = M::DEFAULT_EXPERIMENT;
    md::ModelDescription {
        fmi_version: "2.0".into(),
        model_name: M::MODEL_NAME.into(),
        guid: guid::<M>(),
        description: Some(M::DESCRIPTION.into()),
        author: Some(fmi_export::provenance::AUTHOR.into()),
        version: Some(M::VERSION.into()),
        copyright: Some(fmi_export::provenance::COPYRIGHT.into()),
        license: Some(fmi_export::provenance::LICENSE.into()),
        generation_tool: Some(format!(
            "lander-fmi fmi2-export {}",
            env!("CARGO_PKG_VERSION")
        )),
        generation_date_and_time: fmi_export::provenance::generation_date_and_time(),
        variable_naming_convention: Some("structured".into()),
        co_simulation: Some(md::CoSimulation {
            model_identifier: M::MODEL_IDENTIFIER.into(),
            needs_execution_tool: Some(false),
            can_handle_variable_communication_step_size: Some(true),
            can_interpolate_inputs: Some(false),
            max_output_derivative_order: Some(0),
            can_run_asynchronuously: Some(false),
            can_be_instantiated_only_once_per_process: Some(false),
            can_not_use_memory_management_functions: Some(true),
            can_get_and_set_fmu_state: Some(true),
            can_serialize_fmu_state: Some(true),
            provides_directional_derivative: Some(M::PROVIDES_DIRECTIONAL_DERIVATIVES),
        }),
        unit_definitions: unit_definitions(&table),
        type_definitions: type_definitions::<M>(),
        log_categories: Some(md::LogCategories {
            categories: CATEGORIES
                .iter()
                .map(|c| md::Category {
                    name: c.name().to_string_lossy().into_owned(),
                    description: Some(c.description().into()),
                })
                .collect(),
        }),
        default_experiment: Some(md::DefaultExperiment {
            start_time: Some(e.start_time),
            stop_time: Some(e.stop_time),
            tolerance: e.tolerance,
            step_size: Some(e.step_size),
        }),
        model_variables: md::ModelVariables {
            variables: table.iter().map(scalar_variable).collect(),
        },
        model_structure: model_structure::<M>(),
        ..md::ModelDescription::default()
    }
}

/// The model description as `modelDescription.xml`.
///
/// # Panics
/// If the table fails [`check_table`] or the XML cannot be written: this runs in the
/// packaging tool and the drift tests, where a loud stop is the right answer to a table
/// that would give an invalid FMU.
pub fn model_description_xml<M: Model>() -> String {
    if let Err(e) = check_table::<M>() {
        panic!("{e}");
    }
    model_description::<M>().to_xml().unwrap_or_else(|e| {
        panic!(
            "cannot write the model description of {}: {e}",
            M::MODEL_IDENTIFIER
        )
    })
}

fn unit_definitions<M>(table: &[Variable<M>]) -> Option<md::UnitDefinitions> {
    let used: BTreeSet<&str> = table.iter().filter_map(|v| v.unit).collect();
    (!used.is_empty()).then(|| md::UnitDefinitions {
        units: used
            .into_iter()
            .map(|name| md::Unit {
                name: name.into(),
                base_unit: base_unit(name),
                display_units: fmi_export::display_unit(name)
                    .map(|(display, factor)| md::DisplayUnit {
                        name: display.into(),
                        factor: Some(factor),
                        offset: None,
                    })
                    .into_iter()
                    .collect(),
            })
            .collect(),
    })
}

/// The enumeration types the declarations use, each once, in order of first use. A type
/// exchanged as an Integer is written too, so that a tool can read its items' names.
fn enumeration_types<M: Model>() -> Vec<&'static EnumType> {
    let mut types: Vec<&'static EnumType> = Vec::new();
    for var in variables::<M>() {
        if let Access::Enumeration { ty, .. } = &var.access {
            if !types.iter().any(|t| t.name == ty.name) {
                types.push(ty);
            }
        }
    }
    types
}

fn type_definitions<M: Model>() -> Option<md::TypeDefinitions> {
    let types = enumeration_types::<M>();
    (!types.is_empty()).then(|| md::TypeDefinitions {
        simple_types: types
            .iter()
            .map(|t| md::SimpleType {
                name: t.name.into(),
                description: (!t.description.is_empty()).then(|| t.description.into()),
                enumeration: Some(md::EnumerationType {
                    quantity: None,
                    items: t
                        .items
                        .iter()
                        .map(|i| md::EnumerationItem {
                            name: i.name.into(),
                            value: i.value,
                            description: (!i.description.is_empty()).then(|| i.description.into()),
                        })
                        .collect(),
                }),
                ..md::SimpleType::default()
            })
            .collect(),
    })
}

fn scalar_variable<M: Model>(var: &Variable<M>) -> md::ScalarVariable {
    let description = var.description();
    let mut sv = md::ScalarVariable {
        name: var.name().into_owned(),
        value_reference: var.value_reference,
        description: (!description.is_empty()).then(|| description.into_owned()),
        causality: Some(causality(var.causality)),
        variability: Some(variability(var.variability)),
        initial: var.initial.map(initial),
        ..md::ScalarVariable::default()
    };
    match &var.access {
        Access::Real {
            start, min, max, ..
        } => {
            sv.real = Some(md::RealVariable {
                unit: var.unit.map(Into::into),
                display_unit: var
                    .unit
                    .and_then(fmi_export::display_unit)
                    .map(|(display, _)| display.into()),
                // FMI 2.0 bounds are inclusive: an exclusive bound is written as the nearest
                // value it admits, and said in words in the description.
                min: min.map(|m| m.fmi_min()),
                max: max.map(|m| m.fmi_max()),
                start: *start,
                ..md::RealVariable::default()
            })
        }
        Access::Integer {
            start, min, max, ..
        } => {
            sv.integer = Some(md::IntegerVariable {
                min: *min,
                max: *max,
                start: *start,
                ..md::IntegerVariable::default()
            })
        }
        Access::Enumeration {
            ty,
            start,
            as_integer: true,
            ..
        } => {
            sv.integer = Some(md::IntegerVariable {
                min: ty.min(),
                max: ty.max(),
                start: *start,
                ..md::IntegerVariable::default()
            })
        }
        Access::Enumeration { ty, start, .. } => {
            sv.enumeration = Some(md::EnumerationVariable {
                declared_type: ty.name.into(),
                start: *start,
                ..md::EnumerationVariable::default()
            })
        }
        Access::Boolean { start, .. } => {
            sv.boolean = Some(md::BooleanVariable {
                start: *start,
                ..md::BooleanVariable::default()
            })
        }
        Access::String { get, .. } => {
            let start = crate::variable::needs_start(var.causality, var.variability, var.initial)
                .then(|| get(&M::default()).to_string());
            sv.string = Some(md::StringVariable {
                start,
                ..md::StringVariable::default()
            })
        }
    }
    sv
}

/// Outputs: every output, with its direct-feedthrough inputs. InitialUnknowns (FMI 2.0
/// §2.2.8, co-simulation): outputs whose initial is approx or calculated, and every
/// calculated parameter, each with what it may depend on in initialization mode: its
/// direct-feedthrough inputs and the parameters with initial exact (all of them: a safe
/// superset, which never makes a master see a loop through an input that is not there).
fn model_structure<M: Model>() -> md::ModelStructure {
    let table = variables::<M>();
    let declarations = M::declarations();
    let index = |i: usize| i as u32 + 1;
    let inputs_of = |output: &Variable<M>| -> Vec<u32> {
        if output.causality != Causality::Output {
            return Vec::new();
        }
        let declared = declarations[output.declaration].name;
        table
            .iter()
            .enumerate()
            .filter(|(_, v)| v.causality == Causality::Input)
            .filter(|(_, input)| {
                let input_name = declarations[input.declaration].name;
                match M::output_dependencies(declared) {
                    Dependencies::AllInputs => true,
                    Dependencies::NoInputs => false,
                    Dependencies::Inputs(names) => names.contains(&input_name),
                    Dependencies::SameElementOf(name) => {
                        name == input_name && input.element() == output.element()
                    }
                }
            })
            .map(|(i, _)| index(i))
            .collect()
    };
    let exact_parameters: Vec<u32> = table
        .iter()
        .enumerate()
        .filter(|(_, v)| {
            v.causality == Causality::Parameter && effective_initial(v) == Some(Initial::Exact)
        })
        .map(|(i, _)| index(i))
        .collect();
    let listed = |mut indices: Vec<u32>| -> String {
        indices.sort_unstable();
        indices.dedup();
        let indices: Vec<String> = indices.iter().map(u32::to_string).collect();
        indices.join(" ")
    };
    let outputs: Vec<md::Unknown> = table
        .iter()
        .enumerate()
        .filter(|(_, v)| v.causality == Causality::Output)
        .map(|(i, v)| md::Unknown {
            index: index(i),
            dependencies: Some(listed(inputs_of(v))),
            dependencies_kind: None,
        })
        .collect();
    let initial_unknowns: Vec<md::Unknown> = table
        .iter()
        .enumerate()
        .filter(|(_, v)| match v.causality {
            Causality::Output => effective_initial(v) != Some(Initial::Exact),
            Causality::CalculatedParameter => true,
            _ => false,
        })
        .map(|(i, v)| md::Unknown {
            index: index(i),
            dependencies: Some(listed(
                inputs_of(v)
                    .into_iter()
                    .chain(exact_parameters.iter().copied())
                    .collect(),
            )),
            dependencies_kind: None,
        })
        .collect();
    md::ModelStructure {
        outputs: (!outputs.is_empty()).then_some(md::UnknownList { unknowns: outputs }),
        derivatives: None,
        initial_unknowns: (!initial_unknowns.is_empty()).then_some(md::UnknownList {
            unknowns: initial_unknowns,
        }),
    }
}

fn causality(c: Causality) -> md::Causality {
    match c {
        Causality::Parameter => md::Causality::Parameter,
        Causality::CalculatedParameter => md::Causality::CalculatedParameter,
        Causality::Input => md::Causality::Input,
        Causality::Output => md::Causality::Output,
        Causality::Local => md::Causality::Local,
        Causality::Independent => md::Causality::Independent,
    }
}

fn variability(v: Variability) -> md::Variability {
    match v {
        Variability::Constant => md::Variability::Constant,
        Variability::Fixed => md::Variability::Fixed,
        Variability::Tunable => md::Variability::Tunable,
        Variability::Discrete => md::Variability::Discrete,
        Variability::Continuous => md::Variability::Continuous,
    }
}

fn initial(i: Initial) -> md::Initial {
    match i {
        Initial::Exact => md::Initial::Exact,
        Initial::Approx => md::Initial::Approx,
        Initial::Calculated => md::Initial::Calculated,
    }
}
