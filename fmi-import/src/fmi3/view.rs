//! An FMI 3.0 model description seen as FMI 2.0 scalars, so that everything above the loader
//! (name resolution, feedthrough, recording, `harness vars`) reads one kind of description.
//!
//! An array variable `r_nue` of dimension 3 becomes the scalars `r_nue[1]`, `r_nue[2]`,
//! `r_nue[3]` (1-based, row-major with `[i,j]` for more dimensions): the names the FMI 2.0
//! twin of the FMU declares (`variableNamingConvention="structured"`), so one scenario names
//! both. Each scalar's `valueReference` in the view is its position in the view, an *element
//! reference*; [`Element`] maps it back to the FMI 3.0 value reference and the element's
//! place in its array.
//!
//! Structural parameters (FMI 3.0, Configuration Mode) size arrays: a `<Dimension
//! valueReference=...>` takes its extent from the value of the variable it names. The view is
//! therefore built for one *configuration*: the values of the structural parameters, their
//! start values unless the caller gives others ([`scalar_view`]'s `configuration`, by name).
//! A loaded FMU holds the view of its start values; `Fmu::configured` builds another view
//! for other values, over the same binary, and each instance made from it applies those
//! values in Configuration Mode right after instantiation (and after a reset), so the arrays
//! the FMU holds have the extents the view shows, and `x[1]..x[n]` follow the `n` set.
//!
//! An array's start values in the file are for the structural parameters' start values.
//! For another extent they say nothing the view could use, so its elements have no start
//! value there; and since a set writes an array whole (`instance.rs`), a set of some of its
//! elements writes the others as 0 until they are set too: such an array is best set whole.
use crate::error::LoadError;
use crate::word;
use model_description::fmi3::{Fmi3ModelDescription, Fmi3Type, Fmi3Variable};
use model_description::{
    BooleanVariable, CoSimulation, DefaultExperiment, EnumerationItem, EnumerationType,
    EnumerationVariable, IntegerVariable, ModelDescription, ModelExchange, ModelStructure,
    ModelVariables, RealVariable, ScalarVariable, SimpleType, StringVariable, TypeDefinitions,
    Unknown, UnknownList,
};
use std::collections::HashMap;

/// One scalar of the view: element `index` of the FMI 3.0 variable `value_reference`, whose
/// elements are the view's scalars `first..first + len`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Element {
    pub(crate) value_reference: u32,
    pub(crate) kind: Fmi3Type,
    pub(crate) index: usize,
    pub(crate) first: usize,
    pub(crate) len: usize,
}

/// Start values per element, by exchange type (the slot of the other types unused): the
/// values an array keeps for the elements a set does not name.
#[derive(Debug, Clone, Default)]
pub(crate) struct Starts {
    pub(crate) float64: Vec<f64>,
    pub(crate) int: Vec<i64>,
    pub(crate) boolean: Vec<bool>,
    pub(crate) string: Vec<String>,
    /// The word types (see [`crate::word`]).
    pub(crate) words: Vec<u64>,
    pub(crate) binary: Vec<Vec<u8>>,
}

#[derive(Debug)]
pub(crate) struct View {
    pub(crate) description: ModelDescription,
    pub(crate) elements: Vec<Element>,
    pub(crate) starts: Starts,
    /// The FMI 3.0 type of each of `description`'s variables, in order (aliases included).
    pub(crate) types: Vec<Fmi3Type>,
    /// The start value of each, as the file (or the configuration) writes it: exact where
    /// the FMI 2.0 element cannot hold it (an Int64 beyond 32 bits, a Binary).
    pub(crate) start_texts: Vec<Option<String>>,
    /// Element references of the structural parameters the configuration gives a value,
    /// which an instance sets in Configuration Mode; empty for the start values.
    pub(crate) configured: Vec<u32>,
}

/// Refuses what this harness cannot drive, naming the model and the reason, then builds the
/// view of `configuration`: values (as text, as a scenario gives them) of structural
/// parameters by name; those not named keep their start values.
pub(crate) fn scalar_view(
    md: &Fmi3ModelDescription,
    configuration: &[(String, String)],
) -> Result<View, LoadError> {
    let refuse = |reason: String| LoadError::UnsupportedFmi3 {
        model_name: md.model_name.clone(),
        reason,
    };
    if md.co_simulation.is_none() && md.model_exchange.is_none() {
        let has = match &md.scheduled_execution {
            Some(_) => "only <ScheduledExecution>",
            None => "no interface element",
        };
        return Err(refuse(format!(
            "it has neither <CoSimulation> nor <ModelExchange> ({has}); the harness runs \
             those two interfaces"
        )));
    }
    for variable in &md.variables {
        if variable.kind == Fmi3Type::Clock {
            return Err(refuse(format!(
                "it declares the clock '{}'; the harness does not drive clocks \
                 (clocked Co-Simulation or Scheduled Execution)",
                variable.name
            )));
        }
        if variable.clocks.is_some() {
            return Err(refuse(format!(
                "variable '{}' belongs to clocks ({}); the harness does not drive clocks",
                variable.name,
                variable.clocks.as_deref().unwrap_or_default()
            )));
        }
    }
    let sizes = extents(md, configuration)?;
    for variable in &md.variables {
        shape(variable, &sizes).map_err(&refuse)?;
    }

    let mut elements = Vec::new();
    let mut scalars = Vec::new();
    let mut types = Vec::new();
    let mut start_texts = Vec::new();
    let mut configured = Vec::new();
    let mut starts = Starts::default();
    // FMI 3.0 value reference -> the view's scalars of that variable.
    let mut by_reference: HashMap<u32, std::ops::Range<usize>> = HashMap::new();
    for variable in &md.variables {
        let shape = shape(variable, &sizes).expect("checked above");
        let len = shape.iter().product::<usize>();
        let first = elements.len();
        let given = configuration
            .iter()
            .find(|(name, _)| *name == variable.name)
            .map(|(_, value)| value.as_str());
        for index in 0..len {
            let name = element_name(&variable.name, &shape, index);
            let start = given.or_else(|| start_token(variable, index, len));
            if given.is_some() {
                configured.push(elements.len() as u32);
            }
            push_start(&mut starts, variable.kind, start);
            types.push(variable.kind);
            start_texts.push(start.map(str::to_owned));
            scalars.push(scalar(md, variable, name, elements.len() as u32, start));
            elements.push(Element {
                value_reference: variable.value_reference,
                kind: variable.kind,
                index,
                first,
                len,
            });
        }
        by_reference.insert(variable.value_reference, first..first + len);
    }
    // A derivative's elements name their state's elements (1-based positions, as FMI 2.0's
    // `derivative` attribute), so the state vector reads the same in both versions.
    for variable in &md.variables {
        let (Some(state), Some(range)) = (
            variable
                .derivative
                .and_then(|vr| by_reference.get(&vr).cloned()),
            by_reference.get(&variable.value_reference),
        ) else {
            continue;
        };
        for (element, state_element) in range.clone().zip(state) {
            if let Some(real) = scalars[element].real.as_mut() {
                real.derivative = Some(state_element as u32 + 1);
            }
        }
    }
    // An alias is another name of the same value: its scalars carry the element references
    // of the variable's own, so every get, set and connection by it reaches that variable.
    // They follow all others, so that a scalar's element reference stays its position.
    for variable in &md.variables {
        let Some(range) = by_reference.get(&variable.value_reference) else {
            continue;
        };
        let shape = shape(variable, &sizes).expect("checked above");
        for alias in &variable.aliases {
            for (index, element) in range.clone().enumerate() {
                let name = element_name(&alias.name, &shape, index);
                let mut aliased = scalars[element].clone();
                aliased.name = name;
                if alias.description.is_some() {
                    aliased.description = alias.description.clone();
                }
                scalars.push(aliased);
                types.push(variable.kind);
                start_texts.push(start_texts[element].clone());
            }
        }
    }
    if let Some((name, _)) = configuration
        .iter()
        .find(|(name, _)| !md.variables.iter().any(|v| v.structural && v.name == *name))
    {
        return Err(refuse(format!(
            "'{name}' is given in Configuration Mode but is not a structural parameter"
        )));
    }

    let indices = |range: &std::ops::Range<usize>| range.clone().map(|i| (i + 1).to_string());
    let unknowns = |list: &[model_description::fmi3::Fmi3Unknown]| -> Vec<Unknown> {
        list.iter()
            .filter_map(|unknown| Some((unknown, by_reference.get(&unknown.value_reference)?)))
            .flat_map(|(unknown, range)| {
                let dependencies = unknown.dependencies.as_ref().map(|vrs| {
                    vrs.iter()
                        .filter_map(|vr| by_reference.get(vr))
                        .flat_map(indices)
                        .collect::<Vec<_>>()
                        .join(" ")
                });
                range.clone().map(move |i| Unknown {
                    index: i as u32 + 1,
                    dependencies: dependencies.clone(),
                    dependencies_kind: None,
                })
            })
            .collect()
    };
    let outputs = unknowns(&md.outputs);
    let derivatives = unknowns(&md.continuous_state_derivatives);

    let enumerations: Vec<SimpleType> = md
        .type_definitions
        .iter()
        .filter(|t| t.kind == Some(Fmi3Type::Enumeration))
        .map(|t| SimpleType {
            name: t.name.clone(),
            enumeration: Some(EnumerationType {
                quantity: None,
                items: t
                    .items
                    .iter()
                    .filter_map(|(name, value)| {
                        Some(EnumerationItem {
                            name: name.clone(),
                            value: i32::try_from(*value).ok()?,
                            description: None,
                        })
                    })
                    .collect(),
            }),
            ..Default::default()
        })
        .collect();

    let description = ModelDescription {
        fmi_version: md.fmi_version.clone(),
        model_name: md.model_name.clone(),
        guid: md.instantiation_token.clone(),
        description: md.description.clone(),
        author: md.author.clone(),
        version: md.version.clone(),
        copyright: md.copyright.clone(),
        license: md.license.clone(),
        generation_tool: md.generation_tool.clone(),
        generation_date_and_time: md.generation_date_and_time.clone(),
        variable_naming_convention: md.variable_naming_convention.clone(),
        model_exchange: md.model_exchange.as_ref().map(|id| ModelExchange {
            model_identifier: id.clone(),
            provides_directional_derivative: md
                .model_exchange_flags
                .as_ref()
                .map(|me| me.provides_directional_derivatives),
            ..Default::default()
        }),
        co_simulation: md.co_simulation.as_ref().map(|co_simulation| CoSimulation {
            model_identifier: co_simulation.model_identifier.clone(),
            can_handle_variable_communication_step_size: Some(
                co_simulation.can_handle_variable_communication_step_size,
            ),
            can_get_and_set_fmu_state: Some(co_simulation.can_get_and_set_fmu_state),
            can_serialize_fmu_state: Some(co_simulation.can_serialize_fmu_state),
            provides_directional_derivative: Some(co_simulation.provides_directional_derivatives),
            ..Default::default()
        }),
        type_definitions: (!enumerations.is_empty()).then_some(TypeDefinitions {
            simple_types: enumerations,
        }),
        default_experiment: Some(DefaultExperiment {
            start_time: md.default_start_time,
            stop_time: md.default_stop_time,
            tolerance: md.default_tolerance,
            step_size: md.default_step_size,
        }),
        model_variables: ModelVariables { variables: scalars },
        model_structure: ModelStructure {
            outputs: Some(UnknownList { unknowns: outputs }),
            derivatives: (!derivatives.is_empty()).then_some(UnknownList {
                unknowns: derivatives,
            }),
            ..Default::default()
        },
        ..Default::default()
    };
    Ok(View {
        description,
        elements,
        starts,
        types,
        start_texts,
        configured,
    })
}

/// The value of every variable a `<Dimension valueReference>` names, by value reference:
/// its value in `configuration` or its start value, checked to be a non-negative integer.
fn extents(
    md: &Fmi3ModelDescription,
    configuration: &[(String, String)],
) -> Result<HashMap<u32, usize>, LoadError> {
    let refuse = |reason: String| LoadError::UnsupportedFmi3 {
        model_name: md.model_name.clone(),
        reason,
    };
    for (name, value) in configuration {
        let variable = md
            .variables
            .iter()
            .find(|v| v.name == *name)
            .ok_or_else(|| refuse(format!("it has no structural parameter '{name}'")))?;
        check_value(variable, value).map_err(|reason| {
            refuse(format!(
                "structural parameter '{name}' ({}) cannot be {value}: {reason}",
                variable.kind.name()
            ))
        })?;
    }
    let mut sizes = HashMap::new();
    for variable in &md.variables {
        for vr in variable.dimensions.iter().filter_map(|d| d.value_reference) {
            if sizes.contains_key(&vr) {
                continue;
            }
            let Some(source) = md.variable_by_reference(vr) else {
                return Err(refuse(format!(
                    "array '{}' takes a dimension from value reference {vr}, which no \
                     variable has",
                    variable.name
                )));
            };
            let given = configuration
                .iter()
                .find(|(name, _)| *name == source.name)
                .map(|(_, value)| value.as_str());
            let text = given.or(source.start.first().map(String::as_str));
            let extent = text
                .and_then(|t| t.trim().parse::<u64>().ok())
                .and_then(|n| usize::try_from(n).ok())
                .ok_or_else(|| {
                    refuse(format!(
                        "array '{}' takes a dimension from '{}', whose value {} is not a \
                         non-negative integer",
                        variable.name,
                        source.name,
                        text.unwrap_or("(no start value)")
                    ))
                })?;
            sizes.insert(vr, extent);
        }
    }
    Ok(sizes)
}

/// Whether `text` is a value of `variable`'s type.
pub(crate) fn check_value(variable: &Fmi3Variable, text: &str) -> Result<(), String> {
    match variable.kind {
        kind if word::is_word(kind) => word::parse(kind, text).map(drop),
        Fmi3Type::Int32 | Fmi3Type::Enumeration => text
            .trim()
            .parse::<i32>()
            .map(drop)
            .map_err(|_| format!("{text} is not a 32-bit integer")),
        Fmi3Type::Float64 => text
            .trim()
            .parse::<f64>()
            .map(drop)
            .map_err(|_| format!("{text} is not a number")),
        Fmi3Type::Boolean => match text.trim() {
            "true" | "false" | "1" | "0" => Ok(()),
            other => Err(format!("{other} is not a Boolean")),
        },
        Fmi3Type::Binary => word::from_hex(text).map(drop),
        _ => Ok(()),
    }
}

/// `r_nue` + shape [3] + 1 -> `r_nue[2]`; a scalar keeps its name; `[i,j]` beyond one
/// dimension, the last index fastest (FMI 3.0 stores arrays row-major).
pub fn element_name(name: &str, shape: &[usize], index: usize) -> String {
    if shape.is_empty() {
        return name.to_owned();
    }
    let mut rest = index;
    let mut parts = vec![0; shape.len()];
    for (part, &extent) in parts.iter_mut().zip(shape).rev() {
        *part = rest % extent + 1;
        rest /= extent;
    }
    let list: Vec<String> = parts.iter().map(usize::to_string).collect();
    format!("{name}[{}]", list.join(","))
}

/// The start token of element `index`: its own, or the one token given for all; none when
/// the tokens are for another extent (an array sized by a structural parameter set to
/// another value: which token belongs to which element is then the FMU's to say).
fn start_token(variable: &Fmi3Variable, index: usize, len: usize) -> Option<&str> {
    match variable.start.len() {
        0 => None,
        1 if len > 1 => Some(variable.start[0].as_str()),
        n if n != len => None,
        _ => variable.start.get(index).map(String::as_str),
    }
}

fn push_start(starts: &mut Starts, kind: Fmi3Type, start: Option<&str>) {
    starts.words.push(if word::is_word(kind) {
        start.and_then(|s| word::parse(kind, s).ok()).unwrap_or(0)
    } else {
        0
    });
    starts.binary.push(if kind == Fmi3Type::Binary {
        start
            .and_then(|s| word::from_hex(s).ok())
            .unwrap_or_default()
    } else {
        Vec::new()
    });
    starts
        .float64
        .push(start.and_then(|s| s.parse().ok()).unwrap_or(0.0));
    starts
        .int
        .push(start.and_then(|s| s.parse().ok()).unwrap_or(0));
    starts.boolean.push(matches!(start, Some("true" | "1")));
    starts.string.push(if kind == Fmi3Type::String {
        start.unwrap_or_default().to_owned()
    } else {
        String::new()
    });
}

/// The extent of each of `variable`'s dimensions: fixed (`start`), or the value of the
/// variable a `valueReference` names (`sizes`, from [`extents`]).
fn shape(variable: &Fmi3Variable, sizes: &HashMap<u32, usize>) -> Result<Vec<usize>, String> {
    variable
        .dimensions
        .iter()
        .map(|d| match (d.start, d.value_reference) {
            (Some(start), _) => usize::try_from(start).map_err(|e| e.to_string()),
            (None, Some(vr)) => sizes
                .get(&vr)
                .copied()
                .ok_or_else(|| format!("no extent for value reference {vr}")),
            (None, None) => Err(format!(
                "array '{}' has a <Dimension> with neither start nor valueReference",
                variable.name
            )),
        })
        .collect()
}

fn scalar(
    md: &Fmi3ModelDescription,
    variable: &Fmi3Variable,
    name: String,
    value_reference: u32,
    start: Option<&str>,
) -> ScalarVariable {
    let mut scalar = ScalarVariable {
        name,
        value_reference,
        description: variable.description.clone(),
        // A structural parameter is set like a parameter (in Configuration Mode).
        causality: Some(if variable.structural {
            model_description::Causality::Parameter
        } else {
            variable.causality_or_default()
        }),
        variability: Some(variable.variability_or_default()),
        initial: variable.initial,
        ..Default::default()
    };
    let unit = variable.unit.clone().or_else(|| {
        variable
            .declared_type
            .as_deref()
            .and_then(|t| md.type_definition(t))
            .and_then(|t| t.unit.clone())
    });
    match variable.kind {
        Fmi3Type::Float64 => {
            scalar.real = Some(RealVariable {
                unit,
                start: start.and_then(|s| s.parse().ok()),
                ..Default::default()
            })
        }
        Fmi3Type::Float32 => {
            scalar.real = Some(RealVariable {
                unit,
                start: start.and_then(|s| s.parse().ok()),
                ..Default::default()
            })
        }
        // The integers of every width: the FMI 2.0 Integer element, the type itself in
        // `View::types`; a start beyond 32 bits is left out of the element (it stays exact
        // in `Starts`).
        Fmi3Type::Int8
        | Fmi3Type::UInt8
        | Fmi3Type::Int16
        | Fmi3Type::UInt16
        | Fmi3Type::Int32
        | Fmi3Type::UInt32
        | Fmi3Type::Int64
        | Fmi3Type::UInt64 => {
            scalar.integer = Some(IntegerVariable {
                start: start.and_then(|s| s.parse().ok()),
                ..Default::default()
            })
        }
        Fmi3Type::Enumeration => {
            scalar.enumeration = Some(EnumerationVariable {
                declared_type: variable.declared_type.clone().unwrap_or_default(),
                start: start.and_then(|s| s.parse().ok()),
                ..Default::default()
            })
        }
        Fmi3Type::Boolean => {
            scalar.boolean = Some(BooleanVariable {
                start: start.map(|s| s == "true" || s == "1"),
                ..Default::default()
            })
        }
        _ => {
            scalar.string = Some(StringVariable {
                start: start.map(str::to_owned),
                ..Default::default()
            })
        }
    }
    scalar
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_dimension_follows_the_structural_parameter_it_names() {
        let xml = MD
            .replace(
                r#"<Int32 name="n" valueReference="40" causality="parameter" variability="fixed" start="4"/>"#,
                r#"<UInt64 name="n" valueReference="40" causality="structuralParameter" variability="fixed" start="4"/>"#,
            )
            .replace(r#"<Dimension start="2"/>"#, r#"<Dimension valueReference="40"/>"#);
        let md = Fmi3ModelDescription::from_xml(&xml).unwrap();
        let count = |view: &View| {
            view.description
                .model_variables
                .variables
                .iter()
                .filter(|v| v.name.starts_with("y["))
                .count()
        };
        let start = scalar_view(&md, &[]).unwrap();
        assert_eq!(count(&start), 4);
        assert!(start.configured.is_empty());
        let set = scalar_view(&md, &[("n".into(), "6".into())]).unwrap();
        assert_eq!(count(&set), 6);
        // n itself is the one element set in Configuration Mode, with the value given.
        assert_eq!(set.configured.len(), 1);
        assert_eq!(set.starts.words[set.configured[0] as usize], 6);
        let zero = scalar_view(&md, &[("n".into(), "0".into())]).unwrap();
        assert_eq!(count(&zero), 0);
        // u's three start values are not y's: with y of 6 they are no start of its elements.
        let xml = xml.replace(
            r#"<Dimension start="3"/></Float64>"#,
            r#"<Dimension valueReference="40"/></Float64>"#,
        );
        let md = Fmi3ModelDescription::from_xml(&xml).unwrap();
        let start = scalar_view(&md, &[]).unwrap();
        assert!(start.description.model_variables.variables[..3]
            .iter()
            .all(|v| v.real.as_ref().unwrap().start.is_none()));
    }

    #[test]
    fn element_names_are_one_based_and_row_major() {
        assert_eq!(element_name("x", &[], 0), "x");
        assert_eq!(element_name("r", &[3], 1), "r[2]");
        assert_eq!(element_name("m", &[2, 3], 4), "m[2,2]");
    }

    const MD: &str = r#"<fmiModelDescription fmiVersion="3.0" modelName="M" instantiationToken="t">
  <CoSimulation modelIdentifier="M"/>
  <ModelVariables>
    <Float64 name="u" valueReference="10" causality="input" start="1 2 3"><Dimension start="3"/></Float64>
    <Float64 name="y" valueReference="20" causality="output"><Dimension start="2"/></Float64>
    <Float32 name="f" valueReference="30" causality="output"/>
    <Int32 name="n" valueReference="40" causality="parameter" variability="fixed" start="4"/>
  </ModelVariables>
  <ModelStructure>
    <Output valueReference="20" dependencies="10"/>
    <Output valueReference="30"/>
  </ModelStructure>
</fmiModelDescription>"#;

    #[test]
    fn arrays_become_scalars_with_element_references_and_dependencies() {
        let md = Fmi3ModelDescription::from_xml(MD).unwrap();
        let view = scalar_view(&md, &[]).unwrap();
        let names: Vec<_> = view
            .description
            .model_variables
            .variables
            .iter()
            .map(|v| v.name.as_str())
            .collect();
        assert_eq!(names, ["u[1]", "u[2]", "u[3]", "y[1]", "y[2]", "f", "n"]);
        assert_eq!(view.types[5], Fmi3Type::Float32);
        assert_eq!(view.elements[4].value_reference, 20);
        assert_eq!((view.elements[4].index, view.elements[4].first), (1, 3));
        assert_eq!(view.starts.float64[..3], [1.0, 2.0, 3.0]);
        let outputs = &view
            .description
            .model_structure
            .outputs
            .as_ref()
            .unwrap()
            .unknowns;
        assert_eq!(outputs.len(), 3, "Float32 in");
        assert_eq!(outputs[1].index, 5);
        assert_eq!(outputs[1].dependencies.as_deref(), Some("1 2 3"));
    }

    #[test]
    fn an_alias_names_the_same_elements_after_every_variable() {
        let xml = MD.replace(
            r#"causality="output"><Dimension start="2"/></Float64>"#,
            r#"causality="output"><Dimension start="2"/><Alias name="y_alias" description="y again"/></Float64>"#,
        );
        let md = Fmi3ModelDescription::from_xml(&xml).unwrap();
        let view = scalar_view(&md, &[]).unwrap();
        let variables = &view.description.model_variables.variables;
        let named = |name: &str| variables.iter().find(|v| v.name == name).unwrap();
        assert_eq!(variables.len(), 9);
        for i in 1..=2 {
            let (base, alias) = (named(&format!("y[{i}]")), named(&format!("y_alias[{i}]")));
            assert_eq!(alias.value_reference, base.value_reference);
            assert_eq!(alias.causality, base.causality);
            assert_eq!(alias.description.as_deref(), Some("y again"));
        }
        // The variables' own scalars keep their element references as positions.
        for (position, element) in view.elements.iter().enumerate() {
            assert_eq!(variables[position].value_reference, position as u32);
            assert!(element.index < element.len);
        }
        assert_eq!(view.elements.len(), 7);
    }

    #[test]
    fn clocks_scheduled_execution_only_and_unknown_dimensions_are_refused() {
        let cases = [
            (
                MD.replace(
                    r#"<CoSimulation modelIdentifier="M"/>"#,
                    r#"<ScheduledExecution modelIdentifier="M"/>"#,
                ),
                "only <ScheduledExecution>",
            ),
            (
                MD.replace(
                    "<ModelVariables>",
                    r#"<ModelVariables><Clock name="tick" valueReference="99" causality="input"/>"#,
                ),
                "clock 'tick'",
            ),
            (
                MD.replace(
                    r#"<Dimension start="2"/>"#,
                    r#"<Dimension valueReference="41"/>"#,
                ),
                "dimension from value reference 41, which no variable has",
            ),
        ];
        for (xml, expected) in cases {
            let md = Fmi3ModelDescription::from_xml(&xml).unwrap();
            let text = scalar_view(&md, &[]).unwrap_err().to_string();
            assert!(text.contains("'M'") && text.contains(expected), "{text}");
        }
    }
}
