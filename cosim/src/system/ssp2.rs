//! What only SSP 2.0 has: FMI 3.0 components whose connectors carry the FMI 3.0 type of their
//! variable (`ssc:Float64`, `ssc:Int32`, ...) and, for an array, its `ssc:Dimension`s, one
//! connector per variable; parameter values of an array as one row-major list.
//!
//! The rest of an SSD (elements, bindings, connections, experiment, our master annotation) is
//! SSP 1.0's, read in [`super::ssp`] and written by `ssd_write.rs`. The system description
//! keeps the importer's scalar view (`r0_nue[2]`): a list value read here becomes one
//! parameter per element, and a scenario's element values are written back as the whole
//! array, completed from the FMU's start values.
use super::ssd_write::{render, Body, Written, WrittenConnector};
use super::{split_path, DeclaredConnector, ParamValue, SystemDescription, SystemError};
use fmi_import::Fmu;
use model_description::fmi3::{Fmi3ModelDescription, Fmi3Type, Fmi3Variable};

/// The parameters one `ssv:Parameter` stands for: itself when it has no dimensions, else one
/// per element (`r0_nue[1]`.., the importer's names), from the list in row-major order.
pub(super) fn values(
    name: &str,
    type_name: &str,
    text: &str,
    sizes: &[u64],
) -> Result<Vec<(String, ParamValue)>, String> {
    if type_name == "String" {
        if !sizes.is_empty() {
            return Err("a String array is not supported".into());
        }
        return Ok(vec![(name.to_owned(), ParamValue::String(text.to_owned()))]);
    }
    let tokens: Vec<&str> = text.split_whitespace().collect();
    let count: u64 = sizes.iter().product();
    if tokens.len() as u64 != count {
        return Err(if sizes.is_empty() {
            format!(
                "value '{text}' is a list of {} values: an array needs its ssc:Dimension \
                 elements",
                tokens.len()
            )
        } else {
            format!(
                "value '{text}' has {} values, its dimensions {sizes:?} need {count}",
                tokens.len()
            )
        });
    }
    let shape: Vec<usize> = sizes.iter().map(|&n| n as usize).collect();
    tokens
        .iter()
        .enumerate()
        .map(|(k, token)| {
            let value = typed(type_name, token)
                .ok_or_else(|| format!("'{token}' is not a valid {type_name} value"))?;
            Ok((fmi_import::element_name(name, &shape, k), value))
        })
        .collect()
}

fn typed(type_name: &str, token: &str) -> Option<ParamValue> {
    match type_name {
        "Real" | "Float64" | "Float32" => token.parse().ok().map(ParamValue::Real),
        "Boolean" => match token {
            "true" | "1" => Some(ParamValue::Boolean(true)),
            "false" | "0" => Some(ParamValue::Boolean(false)),
            _ => None,
        },
        _ => token.parse().ok().map(ParamValue::Integer),
    }
}

/// Checks a declared connector that names a whole variable of an FMI 3.0 FMU: kind,
/// FMI 3.0 type and dimensions as the variable's; an array or FMI 3.0 type declared for an
/// FMI 2.0 FMU. `None` where the scalar check applies: an SSP 1.0 connector of an FMI 2.0
/// FMU, an element (`r_nue[1]`), or a scalar declared with an SSP 1.0 type.
pub fn connector_problems(
    fmu: &Fmu,
    instance: &str,
    connector: &DeclaredConnector,
) -> Option<Vec<String>> {
    let Some(md) = fmu.fmi3_description() else {
        let fmi3_type = connector.type_name.as_deref().filter(|t| {
            ![
                "Real",
                "Integer",
                "Boolean",
                "String",
                "Enumeration",
                "Binary",
            ]
            .contains(t)
        });
        if connector.dimensions.is_empty() && fmi3_type.is_none() {
            return None;
        }
        // Said once per connector, not as "no such variable": the SSD is right, the FMU found
        // for it is the FMI 2.0 twin.
        return Some(vec![format!(
            "component '{instance}': connector '{}' ({} {:?}) is SSP 2.0's, of an FMI 3.0 \
             variable, but model '{}' is an FMI 2.0 FMU (is the FMU directory the FMI 3.0 \
             one, e.g. target/fmu/fmi3?)",
            connector.name,
            connector.type_name.as_deref().unwrap_or("untyped"),
            connector.dimensions,
            fmu.model_name()
        )]);
    };
    let variable = whole(md, &connector.name)?;
    let legacy = fmu
        .variable(&connector.name)
        .ok()
        .map(|v| format!("{:?}", v.kind));
    if connector.dimensions.is_empty()
        && variable.dimensions.is_empty()
        && (connector.type_name.is_none() || connector.type_name == legacy)
    {
        return None;
    }
    let mut problems = Vec::new();
    let causality = variable.causality_or_default();
    if connector.causality().is_some_and(|c| c != causality) {
        problems.push(format!(
            "component '{instance}': connector '{}' is declared {} but the FMU's variable has \
             causality {causality:?}",
            connector.name, connector.kind
        ));
    }
    if let Some(type_name) = &connector.type_name {
        // SSP 2.0 keeps SSP 1.0's Real (an IEEE 754 double) and Integer (32-bit signed).
        let same = match (type_name.as_str(), variable.kind) {
            ("Real", Fmi3Type::Float64) | ("Integer", Fmi3Type::Int32) => true,
            (name, kind) => name == kind.name(),
        };
        if !same {
            problems.push(format!(
                "component '{instance}': connector '{}' is declared {type_name} but the FMU's \
                 variable is {}",
                connector.name,
                variable.kind.name()
            ));
        }
    }
    let shape: Vec<u64> = variable
        .dimensions
        .iter()
        .map(|d| d.start.unwrap_or(0))
        .collect();
    if connector.dimensions != shape {
        problems.push(format!(
            "component '{instance}': connector '{}' is declared with dimensions {:?} but the \
             FMU's variable has {shape:?}",
            connector.name, connector.dimensions
        ));
    }
    Some(problems)
}

fn whole<'a>(md: &'a Fmi3ModelDescription, name: &str) -> Option<&'a Fmi3Variable> {
    md.variables.iter().find(|v| v.name == name)
}

/// The fixed extent of each dimension of `variable`, or why it has none.
fn shape(variable: &Fmi3Variable) -> Result<Vec<u64>, String> {
    variable
        .dimensions
        .iter()
        .map(|d| {
            d.start.ok_or_else(|| {
                format!(
                    "'{}' has a dimension set by a structural parameter",
                    variable.name
                )
            })
        })
        .collect()
}

/// The `ssc:`/`ssv:` element of an FMI 3.0 type, where SSP 2.0 writes its values as FMI 3.0
/// does (enumerations are item names there, clocks and binaries have no list form).
fn written_type(variable: &Fmi3Variable) -> Result<&'static str, String> {
    match variable.kind {
        Fmi3Type::Enumeration | Fmi3Type::Binary | Fmi3Type::Clock => Err(format!(
            "'{}' is a {}, which this writer does not write",
            variable.name,
            variable.kind.name()
        )),
        kind => Ok(kind.name()),
    }
}

fn is_float(kind: Fmi3Type) -> bool {
    matches!(kind, Fmi3Type::Float64 | Fmi3Type::Float32)
}

/// One value of `variable` as SSV 2.0 writes it (floats in Rust's shortest round-trip form,
/// so that reading it back gives the same bits).
fn text(variable: &Fmi3Variable, value: &ParamValue) -> Result<String, String> {
    let refused = || {
        format!(
            "'{}' is a {}, the value {value:?} is not",
            variable.name,
            variable.kind.name()
        )
    };
    Ok(match (value, variable.kind) {
        (ParamValue::Real(x), kind) if is_float(kind) => format!("{x:?}"),
        (ParamValue::Integer(i), kind) if is_float(kind) => format!("{:?}", *i as f64),
        (ParamValue::Integer(i), Fmi3Type::Boolean)
        | (ParamValue::Integer(i), Fmi3Type::String) => return Err(format!("{} ({i})", refused())),
        (ParamValue::Integer(i), _) => i.to_string(),
        (ParamValue::Boolean(b), Fmi3Type::Boolean) => b.to_string(),
        (ParamValue::String(s), Fmi3Type::String) => s.clone(),
        _ => return Err(refused()),
    })
}

/// A start token of the FMU in the form [`text`] writes.
fn start_text(variable: &Fmi3Variable, token: &str) -> Option<String> {
    let value = typed(variable.kind.name(), token).or_else(|| {
        (variable.kind == Fmi3Type::String).then(|| ParamValue::String(token.to_owned()))
    })?;
    text(variable, &value).ok()
}

/// `r0_nue[2]` -> (`r0_nue`, [2]); `m[1,3]` -> (`m`, [1, 3]).
fn element(name: &str) -> Option<(&str, Vec<usize>)> {
    let (base, rest) = name.split_once('[')?;
    let indices = rest.strip_suffix(']')?;
    let indices = indices
        .split(',')
        .map(|i| i.trim().parse().ok())
        .collect::<Option<Vec<usize>>>()?;
    Some((base, indices))
}

/// Row-major position of 1-based `indices` in `shape`.
fn flat(indices: &[usize], shape: &[u64]) -> Option<usize> {
    if indices.len() != shape.len() {
        return None;
    }
    indices.iter().zip(shape).try_fold(0, |at, (&i, &n)| {
        (1..=n as usize)
            .contains(&i)
            .then_some(at * n as usize + i - 1)
    })
}

/// An instance's parameters as whole variables, in the order the scenario first names them.
fn parameters(
    instance: &super::InstanceDesc,
    md: &Fmi3ModelDescription,
    problems: &mut Vec<String>,
) -> Vec<Written> {
    struct Whole<'a> {
        variable: &'a Fmi3Variable,
        shape: Vec<u64>,
        values: Vec<Option<String>>,
    }
    let mut wholes: Vec<Whole> = Vec::new();
    for (name, value) in &instance.parameters {
        let mut problem = |p: String| {
            problems.push(format!(
                "component '{}': parameter '{name}': {p}",
                instance.name
            ))
        };
        let (variable, indices) = match whole(md, name) {
            Some(v) => (v, None),
            None => match element(name).and_then(|(b, i)| Some((whole(md, b)?, Some(i)))) {
                Some(found) => found,
                None => {
                    problem(format!("not a variable of model '{}'", md.model_name));
                    continue;
                }
            },
        };
        let shape = match shape(variable).and_then(|s| written_type(variable).map(|_| s)) {
            Ok(shape) => shape,
            Err(p) => {
                problem(p);
                continue;
            }
        };
        if variable.kind == Fmi3Type::String && !shape.is_empty() {
            problem("a String array is not written".into());
            continue;
        }
        let text = match text(variable, value) {
            Ok(text) => text,
            Err(p) => {
                problem(p);
                continue;
            }
        };
        let at = match wholes.iter().position(|w| w.variable.name == variable.name) {
            Some(at) => at,
            None => {
                let count = shape.iter().product::<u64>() as usize;
                let start = |k: usize| {
                    let token = match variable.start.len() {
                        1 => variable.start.first(),
                        _ => variable.start.get(k),
                    };
                    token.and_then(|t| start_text(variable, t))
                };
                wholes.push(Whole {
                    variable,
                    values: (0..count).map(start).collect(),
                    shape,
                });
                wholes.len() - 1
            }
        };
        let target = &mut wholes[at];
        match indices {
            // As the master: an array's value is given element by element.
            None if !target.shape.is_empty() => problem(format!(
                "an array of dimensions {:?}: set its elements, e.g. '{}[1]'",
                target.shape, variable.name
            )),
            None => target.values[0] = Some(text),
            Some(indices) => match flat(&indices, &target.shape) {
                Some(k) => target.values[k] = Some(text),
                None => problem(format!(
                    "no such element: '{}' has dimensions {:?}",
                    variable.name, target.shape
                )),
            },
        }
    }
    wholes
        .into_iter()
        .filter_map(|w| {
            let missing: Vec<usize> = (0..w.values.len())
                .filter(|&k| w.values[k].is_none())
                .collect();
            if !missing.is_empty() {
                problems.push(format!(
                    "component '{}': parameter '{}': elements {missing:?} (from 0) are not set \
                     and the FMU gives them no start value",
                    instance.name, w.variable.name
                ));
                return None;
            }
            Some(Written {
                name: w.variable.name.clone(),
                type_name: w.variable.kind.name(),
                value: w.values.into_iter().flatten().collect::<Vec<_>>().join(" "),
                dimensions: w.shape,
            })
        })
        .collect()
}

/// Writes an SSP 2.0 SSD of `system`, whose instances are the FMI 3.0 `fmus` (in instance
/// order), each component's `source` `resources/<file name>`: a connector per connected
/// variable with its FMI 3.0 type and dimensions, the connections as the scenario names them
/// (whole variables), each parameter a whole variable.
pub fn write(system: &SystemDescription, fmus: &[Fmu]) -> Result<String, SystemError> {
    let mut problems = Vec::new();
    let mut descriptions = Vec::with_capacity(fmus.len());
    for (instance, fmu) in system.instances.iter().zip(fmus) {
        match fmu.fmi3_description() {
            Some(md) => descriptions.push(md),
            None => problems.push(format!(
                "component '{}': {} is not an FMI 3.0 FMU, which an SSP 2.0 component here is",
                instance.name,
                instance.fmu.display()
            )),
        }
    }
    let invalid = |problems: Vec<String>| SystemError::Invalid {
        system: system.name.clone(),
        message: problems.join("\n  "),
    };
    if !problems.is_empty() {
        return Err(invalid(problems));
    }
    let mut connectors: Vec<WrittenConnector> = Vec::new();
    let mut connections = Vec::new();
    for connection in &system.connections {
        for (end, kind) in [(&connection.from, "output"), (&connection.to, "input")] {
            let found = split_path(end).and_then(|(instance, name)| {
                let at = system.instances.iter().position(|i| i.name == instance)?;
                Some((instance, whole(descriptions[at], name)?))
            });
            let Some((instance, variable)) = found else {
                problems.push(format!(
                    "connection {} -> {}: '{end}' is not a whole variable of an FMI 3.0 \
                     component (SSP 2.0 connects an array as one connector)",
                    connection.from, connection.to
                ));
                continue;
            };
            let shape = match shape(variable).and_then(|s| written_type(variable).map(|_| s)) {
                Ok(shape) => shape,
                Err(p) => {
                    problems.push(format!(
                        "connection {} -> {}: {p}",
                        connection.from, connection.to
                    ));
                    continue;
                }
            };
            if !connectors
                .iter()
                .any(|c| c.instance == instance && c.name == variable.name && c.kind == kind)
            {
                connectors.push(WrittenConnector {
                    instance: instance.to_owned(),
                    name: variable.name.clone(),
                    kind,
                    type_name: variable.kind.name(),
                    dimensions: shape,
                });
            }
        }
        connections.push((connection.from.clone(), connection.to.clone()));
    }
    let parameters = system
        .instances
        .iter()
        .zip(&descriptions)
        .map(|(instance, md)| parameters(instance, md, &mut problems))
        .collect();
    if !problems.is_empty() {
        return Err(invalid(problems));
    }
    Ok(render(
        system,
        &Body {
            version: "2.0",
            connectors,
            parameters,
            connections,
        },
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_list_value_becomes_one_parameter_per_element_in_row_major_order() {
        let read = values("m", "Float64", " 1 2.5\n3 4 5 6 ", &[2, 3]).unwrap();
        let names: Vec<&str> = read.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(
            names,
            ["m[1,1]", "m[1,2]", "m[1,3]", "m[2,1]", "m[2,2]", "m[2,3]"]
        );
        assert_eq!(read[1].1, ParamValue::Real(2.5));
        assert_eq!(
            values("n", "Int32", "-3", &[]).unwrap(),
            [("n".to_owned(), ParamValue::Integer(-3))]
        );
        assert_eq!(
            values("on", "Boolean", "true 0", &[2]).unwrap()[1],
            ("on[2]".to_owned(), ParamValue::Boolean(false))
        );
    }

    #[test]
    fn a_list_that_does_not_fit_its_dimensions_is_refused_with_its_value() {
        let error = values("r", "Float64", "0 800", &[3]).unwrap_err();
        assert!(
            error.contains("'0 800'") && error.contains("need 3"),
            "{error}"
        );
        let error = values("r", "Float64", "0 800 0", &[]).unwrap_err();
        assert!(error.contains("ssc:Dimension"), "{error}");
        let error = values("r", "Float64", "0 x 0", &[3]).unwrap_err();
        assert!(error.contains("'x'"), "{error}");
    }

    #[test]
    fn element_indices_are_one_based_and_row_major() {
        assert_eq!(element("r0_nue[2]"), Some(("r0_nue", vec![2])));
        assert_eq!(element("m[1, 3]"), Some(("m", vec![1, 3])));
        assert_eq!(element("plain"), None);
        assert_eq!(flat(&[2], &[3]), Some(1));
        assert_eq!(flat(&[2, 1], &[2, 3]), Some(3));
        assert_eq!(flat(&[4], &[3]), None);
        assert_eq!(flat(&[1], &[2, 3]), None);
    }

    const SSD: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<ssd:SystemStructureDescription xmlns:ssc="http://ssp-standard.org/SSP1/SystemStructureCommon" xmlns:ssd="http://ssp-standard.org/SSP1/SystemStructureDescription" xmlns:ssv="http://ssp-standard.org/SSP1/SystemStructureParameterValues" version="2.0" name="s">
  <ssd:System name="s">
    <ssd:Elements>
      <ssd:Component name="plant" source="resources/P.fmu">
        <ssd:Connectors>
          <ssd:Connector name="r_nue" kind="output"><ssc:Float64/><ssc:Dimension size="3"/></ssd:Connector>
          <ssd:Connector name="n" kind="output"><ssc:Int32/></ssd:Connector>
        </ssd:Connectors>
        <ssd:ParameterBindings><ssd:ParameterBinding><ssd:ParameterValues>
          <ssv:ParameterSet version="2.0" name="initialValues"><ssv:Parameters>
            <ssv:Parameter name="r0_nue"><ssv:Float64 value="0 800 0.5"/><ssc:Dimension size="3"/></ssv:Parameter>
            <ssv:Parameter name="k"><ssv:Int32 value="7"/></ssv:Parameter>
          </ssv:Parameters></ssv:ParameterSet>
        </ssd:ParameterValues></ssd:ParameterBinding></ssd:ParameterBindings>
      </ssd:Component>
    </ssd:Elements>
  </ssd:System>
  <ssd:DefaultExperiment startTime="0" stopTime="2"/>
</ssd:SystemStructureDescription>
"#;

    #[test]
    fn an_ssp2_ssd_reads_typed_array_connectors_and_list_values() {
        let system = super::super::ssp::parse(SSD, std::path::Path::new("s.ssd")).unwrap();
        let plant = &system.instances[0];
        let connectors = plant.connectors.as_ref().unwrap();
        assert_eq!(connectors[0].name, "r_nue");
        assert_eq!(connectors[0].type_name.as_deref(), Some("Float64"));
        assert_eq!(connectors[0].dimensions, [3]);
        assert_eq!(connectors[1].type_name.as_deref(), Some("Int32"));
        assert!(connectors[1].dimensions.is_empty());
        assert_eq!(
            plant.parameters,
            [
                ("r0_nue[1]".to_owned(), ParamValue::Real(0.0)),
                ("r0_nue[2]".to_owned(), ParamValue::Real(800.0)),
                ("r0_nue[3]".to_owned(), ParamValue::Real(0.5)),
                ("k".to_owned(), ParamValue::Integer(7)),
            ]
        );
    }

    #[test]
    fn a_bad_list_or_version_is_refused_naming_file_component_parameter_and_value() {
        let parse = |text: &str| {
            super::super::ssp::parse(text, std::path::Path::new("s.ssd"))
                .unwrap_err()
                .to_string()
        };
        let error = parse(&SSD.replace(r#"value="0 800 0.5""#, r#"value="0 800""#));
        assert!(
            error.starts_with("s.ssd: component 'plant': parameter 'r0_nue': value '0 800'"),
            "{error}"
        );
        let error = parse(&SSD.replace(r#"value="7""#, r#"value="seven""#));
        assert!(
            error.contains("parameter 'k': 'seven' is not a valid Int32"),
            "{error}"
        );
        let error = parse(&SSD.replace(
            r#"<ssc:Dimension size="3"/></ssd:Connector>"#,
            "<ssc:Dimension/></ssd:Connector>",
        ));
        assert!(
            error.contains("connector 'r_nue'") && error.contains("sizeConnector"),
            "{error}"
        );
        let with_connection = SSD.replace(
            "    </ssd:Elements>\n",
            "    </ssd:Elements>\n    <ssd:Connections><ssd:Connection startElement=\"plant\" \
             startConnector=\"r_nue\" startIndices=\"2\" endElement=\"plant\" \
             endConnector=\"n\"/></ssd:Connections>\n",
        );
        let error = parse(&with_connection);
        assert!(
            error.contains("connection plant.r_nue -> plant.n: startIndices=\"2\""),
            "{error}"
        );
        let error = parse(&SSD.replace(r#"version="2.0" name="s""#, r#"version="3.0" name="s""#));
        assert!(error.contains("version '3.0'"), "{error}");
        // while every version SSP 1.0's schema admits still reads
        let beta = SSD.replace(
            r#"version="2.0" name="s""#,
            r#"version="1.0-beta" name="s""#,
        );
        assert!(super::super::ssp::parse(&beta, std::path::Path::new("s.ssd")).is_ok());
    }
}
