//! SSP 1.0 `SystemStructure.ssd`: read into a [`SystemDescription`] and written from one. SSP
//! 2.0 is read by the same reader and written by the same renderer
//! (`ssd_write.rs`); what only 2.0 has (FMI 3.0 types, array connectors, list values) is
//! in [`super::ssp2`].
//!
//! What we read: one `ssd:System` of FMU components (`source` relative to the SSD), their
//! declared connectors, inline parameter bindings (`ssd:ParameterValues/ssv:ParameterSet`),
//! component-to-component connections, and `ssd:DefaultExperiment`. SSP 1.0 has no place for
//! the communication step or the exchange ordering, so we carry them in an `ssc:Annotation` of
//! type [`ANNOTATION_TYPE`] (other tools ignore it; fmpy's `simulate_ssp` takes the step as an
//! argument and always runs Jacobi).
//!
//! What we write for other tools:
//! - Every component's parameter set has the same name, [`PARAMETER_SET`]. Tools that group
//!   parameter sets by name across components (Ecos applies one named set to the whole
//!   system) then apply all of them with one choice; per-component names made Ecos apply none.
//! - The system carries OMSimulator's `org.openmodelica` annotation (a fixed-step master with
//!   our step), without which OMSimulator's importer cannot tell what kind of system it reads.
//!   SSP 1.0 allows this: `ssd:System` may end with `ssd:Annotations`, each `ssc:Annotation`
//!   has a required `type` and any content from another namespace, which other tools skip.
use super::{
    Connection, DeclaredConnector, InstanceDesc, Ordering, ParamValue, SystemDescription,
    SystemError,
};
use serde::Deserialize;
use std::path::Path;

use super::ssd_write::{render, Body, Written, WrittenConnector};
pub use super::ssd_write::{ANNOTATION_TYPE, PARAMETER_SET};

#[derive(Deserialize)]
struct Ssd {
    #[serde(rename = "@name")]
    name: String,
    #[serde(rename = "@version", default)]
    version: Option<String>,
    #[serde(rename = "ssd:System")]
    system: System,
    #[serde(rename = "ssd:DefaultExperiment", default)]
    default_experiment: Option<DefaultExperiment>,
}

#[derive(Deserialize)]
struct System {
    #[serde(rename = "ssd:Elements", default)]
    elements: Option<Elements>,
    #[serde(rename = "ssd:Connections", default)]
    connections: Option<Connections>,
}

#[derive(Deserialize)]
struct Elements {
    #[serde(rename = "ssd:Component", default)]
    components: Vec<Component>,
}

#[derive(Deserialize)]
struct Component {
    #[serde(rename = "@name")]
    name: String,
    #[serde(rename = "@source")]
    source: String,
    #[serde(rename = "ssd:Connectors", default)]
    connectors: Option<Connectors>,
    #[serde(rename = "ssd:ParameterBindings", default)]
    bindings: Option<ParameterBindings>,
}

#[derive(Deserialize)]
struct Connectors {
    #[serde(rename = "ssd:Connector", default)]
    connectors: Vec<SsdConnector>,
}

#[derive(Deserialize)]
struct SsdConnector {
    #[serde(rename = "@name")]
    name: String,
    #[serde(rename = "@kind")]
    kind: String,
    #[serde(rename = "ssc:Real", default)]
    real: Option<Empty>,
    #[serde(rename = "ssc:Integer", default)]
    integer: Option<Empty>,
    #[serde(rename = "ssc:Boolean", default)]
    boolean: Option<Empty>,
    #[serde(rename = "ssc:String", default)]
    string: Option<Empty>,
    #[serde(rename = "ssc:Enumeration", default)]
    enumeration: Option<Empty>,
    #[serde(rename = "ssc:Binary", default)]
    binary: Option<Empty>,
    #[serde(rename = "ssc:Float64", default)]
    float64: Option<Empty>,
    #[serde(rename = "ssc:Float32", default)]
    float32: Option<Empty>,
    #[serde(rename = "ssc:Int8", default)]
    int8: Option<Empty>,
    #[serde(rename = "ssc:UInt8", default)]
    uint8: Option<Empty>,
    #[serde(rename = "ssc:Int16", default)]
    int16: Option<Empty>,
    #[serde(rename = "ssc:UInt16", default)]
    uint16: Option<Empty>,
    #[serde(rename = "ssc:Int32", default)]
    int32: Option<Empty>,
    #[serde(rename = "ssc:UInt32", default)]
    uint32: Option<Empty>,
    #[serde(rename = "ssc:Int64", default)]
    int64: Option<Empty>,
    #[serde(rename = "ssc:UInt64", default)]
    uint64: Option<Empty>,
    /// SSP 2.0: an array connector, one element per dimension.
    #[serde(rename = "ssc:Dimension", default)]
    dimensions: Vec<Dimension>,
}

impl SsdConnector {
    fn type_name(&self) -> Option<String> {
        [
            (&self.real, "Real"),
            (&self.integer, "Integer"),
            (&self.boolean, "Boolean"),
            (&self.string, "String"),
            (&self.enumeration, "Enumeration"),
            (&self.binary, "Binary"),
            (&self.float64, "Float64"),
            (&self.float32, "Float32"),
            (&self.int8, "Int8"),
            (&self.uint8, "UInt8"),
            (&self.int16, "Int16"),
            (&self.uint16, "UInt16"),
            (&self.int32, "Int32"),
            (&self.uint32, "UInt32"),
            (&self.int64, "Int64"),
            (&self.uint64, "UInt64"),
        ]
        .into_iter()
        .find(|(given, _)| given.is_some())
        .map(|(_, name)| name.to_owned())
    }
}

/// `ssc:Dimension`: a fixed `size`, or a `sizeConnector` we do not read.
#[derive(Deserialize)]
struct Dimension {
    #[serde(rename = "@size", default)]
    size: Option<u64>,
}

#[derive(Deserialize)]
struct Empty {}

#[derive(Deserialize)]
struct ParameterBindings {
    #[serde(rename = "ssd:ParameterBinding", default)]
    bindings: Vec<ParameterBinding>,
}

#[derive(Deserialize)]
struct ParameterBinding {
    #[serde(rename = "@source", default)]
    source: Option<String>,
    #[serde(rename = "ssd:ParameterValues", default)]
    values: Option<ParameterValues>,
}

#[derive(Deserialize)]
struct ParameterValues {
    #[serde(rename = "ssv:ParameterSet")]
    set: ParameterSet,
}

#[derive(Deserialize)]
struct ParameterSet {
    #[serde(rename = "ssv:Parameters", default)]
    parameters: Option<Parameters>,
}

#[derive(Deserialize)]
struct Parameters {
    #[serde(rename = "ssv:Parameter", default)]
    parameters: Vec<Parameter>,
}

/// One `ssv:Parameter`: its value under the element of its type (SSP 1.0's four, SSP 2.0's
/// FMI 3.0 types), a list for an array with its `ssc:Dimension`s.
#[derive(Deserialize)]
struct Parameter {
    #[serde(rename = "@name")]
    name: String,
    #[serde(rename = "ssv:Real", default)]
    real: Option<Value>,
    #[serde(rename = "ssv:Integer", default)]
    integer: Option<Value>,
    #[serde(rename = "ssv:Boolean", default)]
    boolean: Option<Value>,
    #[serde(rename = "ssv:String", default)]
    string: Option<Value>,
    #[serde(rename = "ssv:Float64", default)]
    float64: Option<Value>,
    #[serde(rename = "ssv:Float32", default)]
    float32: Option<Value>,
    #[serde(rename = "ssv:Int8", default)]
    int8: Option<Value>,
    #[serde(rename = "ssv:UInt8", default)]
    uint8: Option<Value>,
    #[serde(rename = "ssv:Int16", default)]
    int16: Option<Value>,
    #[serde(rename = "ssv:UInt16", default)]
    uint16: Option<Value>,
    #[serde(rename = "ssv:Int32", default)]
    int32: Option<Value>,
    #[serde(rename = "ssv:UInt32", default)]
    uint32: Option<Value>,
    #[serde(rename = "ssv:Int64", default)]
    int64: Option<Value>,
    #[serde(rename = "ssv:UInt64", default)]
    uint64: Option<Value>,
    #[serde(rename = "ssc:Dimension", default)]
    dimensions: Vec<Dimension>,
}

impl Parameter {
    /// The type element given and its value text.
    fn typed(&self) -> Option<(&'static str, &str)> {
        [
            (&self.real, "Real"),
            (&self.integer, "Integer"),
            (&self.boolean, "Boolean"),
            (&self.string, "String"),
            (&self.float64, "Float64"),
            (&self.float32, "Float32"),
            (&self.int8, "Int8"),
            (&self.uint8, "UInt8"),
            (&self.int16, "Int16"),
            (&self.uint16, "UInt16"),
            (&self.int32, "Int32"),
            (&self.uint32, "UInt32"),
            (&self.int64, "Int64"),
            (&self.uint64, "UInt64"),
        ]
        .into_iter()
        .find_map(|(given, name)| given.as_ref().map(|v| (name, v.value.as_str())))
    }
}

#[derive(Deserialize)]
struct Value {
    #[serde(rename = "@value")]
    value: String,
}

#[derive(Deserialize)]
struct Connections {
    #[serde(rename = "ssd:Connection", default)]
    connections: Vec<SsdConnection>,
}

#[derive(Deserialize)]
struct SsdConnection {
    #[serde(rename = "@startElement", default)]
    start_element: Option<String>,
    #[serde(rename = "@startConnector")]
    start_connector: String,
    #[serde(rename = "@endElement", default)]
    end_element: Option<String>,
    #[serde(rename = "@endConnector")]
    end_connector: String,
    /// SSP 2.0: the one element of an array connector a connection is restricted to.
    #[serde(rename = "@startIndices", default)]
    start_indices: Option<String>,
    #[serde(rename = "@endIndices", default)]
    end_indices: Option<String>,
}

#[derive(Deserialize)]
struct DefaultExperiment {
    #[serde(rename = "@startTime", default)]
    start_time: Option<f64>,
    #[serde(rename = "@stopTime", default)]
    stop_time: Option<f64>,
    #[serde(rename = "ssd:Annotations", default)]
    annotations: Option<Annotations>,
}

#[derive(Deserialize)]
struct Annotations {
    #[serde(rename = "ssc:Annotation", default)]
    annotations: Vec<Annotation>,
}

#[derive(Deserialize)]
struct Annotation {
    #[serde(rename = "@type")]
    kind: String,
    #[serde(rename = "Master", default)]
    master: Option<MasterSettings>,
}

#[derive(Deserialize)]
struct MasterSettings {
    #[serde(rename = "@stepSize", default)]
    step_size: Option<f64>,
    #[serde(rename = "@ordering", default)]
    ordering: Option<String>,
}

/// Parses an SSD; `origin` names the file in errors. FMU sources stay relative to the SSD.
pub fn parse(text: &str, origin: &Path) -> Result<SystemDescription, SystemError> {
    let syntax = |message: String| SystemError::Syntax {
        path: origin.to_owned(),
        message,
    };
    // Before any parsing: an SSD's DTD could declare entities that expand without bound.
    model_description::refuse_declarations(text.as_bytes()).map_err(|e| syntax(e.to_string()))?;
    let ssd: Ssd = serde_xml_rs::from_str(text).map_err(|e| syntax(e.to_string()))?;
    if let Some(version) = ssd
        .version
        .as_deref()
        // SSP 1.0's schema admits any 1.x ("1.0-beta"); 2.x is SSP 2.0's.
        .filter(|v| !(v.starts_with("1.") || v.starts_with("2.")))
    {
        return Err(syntax(format!(
            "ssd:SystemStructureDescription version '{version}': SSP 1.x and 2.x are read"
        )));
    }
    let mut instances = Vec::new();
    for component in ssd
        .system
        .elements
        .map(|e| e.components)
        .unwrap_or_default()
    {
        let mut parameters = Vec::new();
        for binding in component.bindings.map(|b| b.bindings).unwrap_or_default() {
            if let Some(source) = binding.source {
                return Err(syntax(format!(
                    "component '{}': external parameter file '{source}' is not supported; \
                     bind parameters inline",
                    component.name
                )));
            }
            let list = binding
                .values
                .and_then(|v| v.set.parameters)
                .map(|p| p.parameters)
                .unwrap_or_default();
            for parameter in list {
                let at = |problem: String| {
                    syntax(format!(
                        "component '{}': parameter '{}': {problem}",
                        component.name, parameter.name
                    ))
                };
                let Some((type_name, text)) = parameter.typed() else {
                    return Err(at("no ssv:Real, ssv:Integer, ssv:Boolean, ssv:String nor \
                         SSP 2.0 value element (ssv:Float64, ssv:Int32, ...)"
                        .into()));
                };
                let sizes = sizes(&parameter.dimensions).map_err(at)?;
                let values =
                    super::ssp2::values(&parameter.name, type_name, text, &sizes).map_err(at)?;
                parameters.extend(values);
            }
        }
        let mut connectors = None;
        if let Some(list) = component.connectors.map(|c| c.connectors) {
            let mut declared = Vec::with_capacity(list.len());
            for c in list {
                let dimensions = sizes(&c.dimensions).map_err(|problem| {
                    syntax(format!(
                        "component '{}': connector '{}': {problem}",
                        component.name, c.name
                    ))
                })?;
                declared.push(DeclaredConnector {
                    type_name: c.type_name(),
                    name: c.name,
                    kind: c.kind,
                    dimensions,
                });
            }
            connectors = Some(declared);
        }
        instances.push(InstanceDesc {
            name: component.name,
            fmu: component.source.into(),
            parameters,
            connectors,
            // SSP selects no FMI interface for a component: it runs as Co-Simulation, or as
            // Model Exchange when that is the only interface its FMU declares.
            model_exchange: None,
            interface_named: false,
        });
    }
    let mut connections = Vec::new();
    for c in ssd
        .system
        .connections
        .map(|c| c.connections)
        .unwrap_or_default()
    {
        let (Some(start), Some(end)) = (c.start_element, c.end_element) else {
            return Err(syntax(format!(
                "connection {} -> {}: connections to the system's own connectors are not \
                 supported; connect components directly",
                c.start_connector, c.end_connector
            )));
        };
        // Read as the whole arrays they would be a different system: refused, not ignored.
        if let Some((attribute, indices)) = [
            ("startIndices", &c.start_indices),
            ("endIndices", &c.end_indices),
        ]
        .into_iter()
        .find_map(|(attribute, given)| given.as_ref().map(|i| (attribute, i)))
        {
            return Err(syntax(format!(
                "connection {start}.{} -> {end}.{}: {attribute}=\"{indices}\" (a connection \
                 of array elements) is not supported; connect whole arrays",
                c.start_connector, c.end_connector
            )));
        }
        connections.push(Connection {
            from: format!("{start}.{}", c.start_connector),
            to: format!("{end}.{}", c.end_connector),
        });
    }
    let experiment = ssd.default_experiment;
    let master = experiment
        .as_ref()
        .and_then(|e| e.annotations.as_ref())
        .and_then(|a| a.annotations.iter().find(|a| a.kind == ANNOTATION_TYPE))
        .and_then(|a| a.master.as_ref());
    let ordering = match master.and_then(|m| m.ordering.as_deref()) {
        None | Some("gauss-seidel") => Ordering::GaussSeidel,
        Some("jacobi") => Ordering::Jacobi,
        Some(other) => {
            return Err(syntax(format!(
                "annotation {ANNOTATION_TYPE}: unknown ordering '{other}' (gauss-seidel or jacobi)"
            )))
        }
    };
    let system = SystemDescription {
        name: ssd.name,
        start_time: experiment
            .as_ref()
            .and_then(|e| e.start_time)
            .unwrap_or(0.0),
        stop_time: experiment
            .as_ref()
            .and_then(|e| e.stop_time)
            .ok_or_else(|| syntax("ssd:DefaultExperiment with a stopTime is required".into()))?,
        step_size: master.and_then(|m| m.step_size).unwrap_or(0.01),
        ordering,
        instances,
        connections,
        record: None,
        limits: Default::default(),
        allow_non_finite: Vec::new(),
        events: Vec::new(),
        inputs: None,
        package: None,
    };
    system.validate()?;
    Ok(system)
}

/// The fixed sizes of `ssc:Dimension`s; a size given by a connector is not read.
fn sizes(dimensions: &[Dimension]) -> Result<Vec<u64>, String> {
    dimensions
        .iter()
        .map(|d| {
            d.size.ok_or_else(|| {
                "an ssc:Dimension without a size (sizeConnector) is not supported".to_owned()
            })
        })
        .collect()
}

/// Reads an SSD file.
pub fn read(path: &Path) -> Result<SystemDescription, SystemError> {
    let text = std::fs::read_to_string(path).map_err(|source| SystemError::Io {
        path: path.to_owned(),
        source,
    })?;
    parse(&text, path)
}

/// A connector of a component as the SSD lists it (after vector expansion).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ConnectorDecl {
    pub instance: String,
    pub name: String,
    /// "input" or "output".
    pub kind: &'static str,
    /// "Real", "Integer", "Boolean" or "String".
    pub type_name: &'static str,
}

/// Writes an SSD for `system`, with `source` of each component = `resources/<file name>`.
/// `connectors` and `connections` are the expanded (scalar) ones, as resolved against the
/// FMUs, so that every tool sees explicit connectors with their types.
pub fn write(
    system: &SystemDescription,
    connectors: &[ConnectorDecl],
    connections: &[(String, String)],
) -> String {
    let parameters = system
        .instances
        .iter()
        .map(|instance| {
            instance
                .parameters
                .iter()
                .map(|(name, value)| {
                    let (type_name, value) = match value {
                        ParamValue::Real(v) => ("Real", format!("{v:?}")),
                        ParamValue::Integer(v) => ("Integer", v.to_string()),
                        ParamValue::Boolean(v) => ("Boolean", v.to_string()),
                        ParamValue::String(v) => ("String", v.clone()),
                    };
                    Written {
                        name: name.clone(),
                        type_name,
                        value,
                        dimensions: Vec::new(),
                    }
                })
                .collect()
        })
        .collect();
    let body = Body {
        version: "1.0",
        connectors: connectors
            .iter()
            .map(|c| WrittenConnector {
                instance: c.instance.clone(),
                name: c.name.clone(),
                kind: c.kind,
                type_name: c.type_name,
                dimensions: Vec::new(),
            })
            .collect(),
        parameters,
        connections: connections.to_vec(),
    };
    render(system, &body)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> SystemDescription {
        SystemDescription {
            name: "demo <&>".into(),
            start_time: 0.0,
            stop_time: 1.5,
            step_size: 0.01,
            ordering: Ordering::Jacobi,
            instances: vec![
                InstanceDesc {
                    name: "a".into(),
                    fmu: "some/dir/A.fmu".into(),
                    parameters: vec![
                        ("k".into(), ParamValue::Real(0.1)),
                        ("n".into(), ParamValue::Integer(-3)),
                        ("on".into(), ParamValue::Boolean(true)),
                        ("label".into(), ParamValue::String("x\"y".into())),
                    ],
                    connectors: None,
                    model_exchange: None,
                    interface_named: false,
                },
                InstanceDesc {
                    name: "b".into(),
                    fmu: "B.fmu".into(),
                    parameters: vec![],
                    connectors: None,
                    model_exchange: None,
                    interface_named: false,
                },
            ],
            connections: vec![Connection {
                from: "a.y[1]".into(),
                to: "b.u[1]".into(),
            }],
            record: None,
            limits: Default::default(),
            allow_non_finite: Vec::new(),
            events: Vec::new(),
            inputs: None,
            package: None,
        }
    }

    fn declared(name: &str, kind: &str) -> Option<Vec<DeclaredConnector>> {
        Some(vec![DeclaredConnector {
            name: name.into(),
            kind: kind.into(),
            type_name: Some("Real".into()),
            dimensions: Vec::new(),
        }])
    }

    #[test]
    fn written_ssd_reads_back_to_the_same_system() {
        let system = sample();
        let connectors = vec![
            ConnectorDecl {
                instance: "a".into(),
                name: "y[1]".into(),
                kind: "output",
                type_name: "Real",
            },
            ConnectorDecl {
                instance: "b".into(),
                name: "u[1]".into(),
                kind: "input",
                type_name: "Real",
            },
        ];
        let text = write(&system, &connectors, &[("a.y[1]".into(), "b.u[1]".into())]);
        let back = parse(&text, Path::new("x.ssd")).unwrap();
        let mut expected = system;
        expected.instances[0].fmu = "resources/A.fmu".into();
        expected.instances[1].fmu = "resources/B.fmu".into();
        expected.instances[0].connectors = declared("y[1]", "output");
        expected.instances[1].connectors = declared("u[1]", "input");
        assert_eq!(back, expected);
    }

    #[test]
    fn every_parameter_set_has_the_one_shared_name_and_omsimulator_finds_its_master() {
        let mut system = sample();
        system.instances[1]
            .parameters
            .push(("k".into(), ParamValue::Real(1.0)));
        let text = write(&system, &[], &[]);
        let names: Vec<&str> = text
            .match_indices("<ssv:ParameterSet ")
            .map(|(at, _)| {
                let rest = &text[at..];
                let start = rest.find(" name=\"").unwrap() + 7;
                let end = start + rest[start..].find('"').unwrap();
                &rest[start..end]
            })
            .collect();
        assert_eq!(names, [PARAMETER_SET, PARAMETER_SET]);
        // OMSimulator's annotation sits in the system's Annotations, the last child SSP 1.0
        // allows there, and names the step.
        let system_end = text.find("</ssd:System>").unwrap();
        let annotation = text
            .find(r#"<ssc:Annotation type="org.openmodelica">"#)
            .unwrap();
        assert!(
            annotation < system_end && annotation > text.find("</ssd:Connections>").unwrap_or(0)
        );
        assert!(text[annotation..system_end].contains(r#"stepSize="0.01""#));
        // and our own reader ignores it.
        assert_eq!(parse(&text, Path::new("x.ssd")).unwrap().step_size, 0.01);
    }

    #[test]
    fn a_missing_stop_time_is_refused() {
        let text = write(&sample(), &[], &[]).replace(r#" stopTime="1.5""#, "");
        let error = parse(&text, Path::new("x.ssd")).unwrap_err().to_string();
        assert!(error.contains("stopTime"), "{error}");
    }

    #[test]
    fn a_doctype_is_refused_before_any_entity_is_expanded() {
        let text = write(&sample(), &[], &[])
            .replacen(
                "?>\n",
                "?>\n<!DOCTYPE ssd:SystemStructureDescription [<!ENTITY n \"expanded\">]>\n",
                1,
            )
            .replacen(r#"name="demo &lt;&amp;&gt;""#, r#"name="&n;""#, 1);
        let error = parse(&text, Path::new("x.ssd")).unwrap_err().to_string();
        assert!(error.starts_with("x.ssd: line 2: <!DOCTYPE"), "{error}");
    }

    #[test]
    fn an_external_parameter_file_is_refused_by_name() {
        let text = write(&sample(), &[], &[]).replace(
            "<ssd:ParameterBinding>",
            r#"<ssd:ParameterBinding source="p.ssv">"#,
        );
        let error = parse(&text, Path::new("x.ssd")).unwrap_err().to_string();
        assert!(error.contains("p.ssv"), "{error}");
    }
}
