//! FMI 3.0 model descriptions, read only: what a Co-Simulation master needs (the header,
//! `<CoSimulation>`, the type definitions' units and enumeration items, every variable with
//! its dimensions and start values, the `ModelStructure` outputs). The FMI 2.0 types of this
//! crate stay FMI 2.0; an importer maps this one onto its own view.
//!
//! Read with an event parser rather than serde: FMI 3.0 lists its variables as one element
//! per type (`<Float64>`, `<Int32>`, ...) in declaration order, and a problem is reported
//! with its line, as for FMI 2.0 ([`crate::Error::Invalid`]).
use crate::{Causality, Error, Initial, Variability};
use std::path::Path;
use xml::{reader::XmlEvent, ParserConfig};

/// The type element of an FMI 3.0 variable.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Fmi3Type {
    Float32,
    Float64,
    Int8,
    UInt8,
    Int16,
    UInt16,
    Int32,
    UInt32,
    Int64,
    UInt64,
    Boolean,
    String,
    Binary,
    Enumeration,
    Clock,
}

impl Fmi3Type {
    fn from_element(name: &str) -> Option<Self> {
        Some(match name {
            "Float32" => Self::Float32,
            "Float64" => Self::Float64,
            "Int8" => Self::Int8,
            "UInt8" => Self::UInt8,
            "Int16" => Self::Int16,
            "UInt16" => Self::UInt16,
            "Int32" => Self::Int32,
            "UInt32" => Self::UInt32,
            "Int64" => Self::Int64,
            "UInt64" => Self::UInt64,
            "Boolean" => Self::Boolean,
            "String" => Self::String,
            "Binary" => Self::Binary,
            "Enumeration" => Self::Enumeration,
            "Clock" => Self::Clock,
            _ => return None,
        })
    }

    /// The element name, as in the XML.
    pub fn name(self) -> &'static str {
        match self {
            Self::Float32 => "Float32",
            Self::Float64 => "Float64",
            Self::Int8 => "Int8",
            Self::UInt8 => "UInt8",
            Self::Int16 => "Int16",
            Self::UInt16 => "UInt16",
            Self::Int32 => "Int32",
            Self::UInt32 => "UInt32",
            Self::Int64 => "Int64",
            Self::UInt64 => "UInt64",
            Self::Boolean => "Boolean",
            Self::String => "String",
            Self::Binary => "Binary",
            Self::Enumeration => "Enumeration",
            Self::Clock => "Clock",
        }
    }

    fn is_float(self) -> bool {
        matches!(self, Self::Float32 | Self::Float64)
    }
}

/// `<CoSimulation>`: the flags default to false when absent, as the schema says.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Fmi3CoSimulation {
    pub model_identifier: String,
    pub needs_execution_tool: bool,
    pub can_be_instantiated_only_once_per_process: bool,
    pub can_get_and_set_fmu_state: bool,
    pub can_serialize_fmu_state: bool,
    pub can_handle_variable_communication_step_size: bool,
    pub fixed_internal_step_size: Option<f64>,
    pub might_return_early_from_do_step: bool,
    pub can_return_early_after_intermediate_update: bool,
    pub has_event_mode: bool,
    pub provides_intermediate_update: bool,
    pub provides_directional_derivatives: bool,
    pub provides_adjoint_derivatives: bool,
}

/// `<ModelExchange>`: the flags a master reads beyond its identifier, false when absent.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Fmi3ModelExchange {
    pub model_identifier: String,
    pub provides_directional_derivatives: bool,
    pub provides_adjoint_derivatives: bool,
}

/// `<Dimension start="3"/>` or `<Dimension valueReference="7"/>` (a structural parameter).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Fmi3Dimension {
    pub start: Option<u64>,
    pub value_reference: Option<u32>,
}

/// One variable element of `<ModelVariables>`.
#[derive(Debug, Clone, PartialEq)]
pub struct Fmi3Variable {
    pub name: String,
    pub value_reference: u32,
    pub kind: Fmi3Type,
    pub description: Option<String>,
    /// As written; `structuralParameter` is `None` here and flagged in `structural`.
    pub causality: Option<Causality>,
    pub structural: bool,
    pub variability: Option<Variability>,
    pub initial: Option<Initial>,
    pub declared_type: Option<String>,
    pub unit: Option<String>,
    /// The `start` attribute split at white space (a String's `<Start value>` elements, one
    /// each); empty when none is given.
    pub start: Vec<String>,
    pub dimensions: Vec<Fmi3Dimension>,
    /// `clocks`: the value references of the clocks this variable belongs to.
    pub clocks: Option<String>,
    /// `<Alias>` children: other names of this variable.
    pub aliases: Vec<Fmi3Alias>,
    /// `derivative`: the value reference of the state this variable is the derivative of.
    pub derivative: Option<u32>,
}

/// `<Alias name="h_ft" description="..." displayUnit="ft"/>`: another name of a variable,
/// the same value under it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Fmi3Alias {
    pub name: String,
    pub description: Option<String>,
    pub display_unit: Option<String>,
}

impl Fmi3Variable {
    /// FMI 3.0 defaults: causality `local`.
    pub fn causality_or_default(&self) -> Causality {
        self.causality.unwrap_or(Causality::Local)
    }

    /// FMI 3.0 defaults: `continuous` for floats, `discrete` for every other type.
    pub fn variability_or_default(&self) -> Variability {
        self.variability.unwrap_or(if self.kind.is_float() {
            Variability::Continuous
        } else {
            Variability::Discrete
        })
    }
}

/// `<Output valueReference="5" dependencies="1 2"/>` (and the other unknowns).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Fmi3Unknown {
    pub value_reference: u32,
    /// Value references; `None` = depends on everything, empty = on nothing.
    pub dependencies: Option<Vec<u32>>,
}

/// A type definition: its name, element (`Float64Type` as `Float64`), unit, and the items of
/// an `EnumerationType` (name, value).
#[derive(Debug, Clone, PartialEq)]
pub struct Fmi3TypeDefinition {
    pub name: String,
    pub kind: Option<Fmi3Type>,
    pub unit: Option<String>,
    pub items: Vec<(String, i64)>,
}

/// `<fmiModelDescription fmiVersion="3.0">`.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Fmi3ModelDescription {
    pub fmi_version: String,
    pub model_name: String,
    pub instantiation_token: String,
    pub description: Option<String>,
    pub author: Option<String>,
    pub version: Option<String>,
    pub copyright: Option<String>,
    pub license: Option<String>,
    pub generation_tool: Option<String>,
    pub generation_date_and_time: Option<String>,
    pub variable_naming_convention: Option<String>,
    pub co_simulation: Option<Fmi3CoSimulation>,
    /// The `modelIdentifier` of `<ModelExchange>` and `<ScheduledExecution>`, if declared.
    pub model_exchange: Option<String>,
    /// The flags of `<ModelExchange>`, if declared.
    pub model_exchange_flags: Option<Fmi3ModelExchange>,
    pub scheduled_execution: Option<String>,
    pub default_start_time: Option<f64>,
    pub default_stop_time: Option<f64>,
    pub default_tolerance: Option<f64>,
    pub default_step_size: Option<f64>,
    pub type_definitions: Vec<Fmi3TypeDefinition>,
    pub variables: Vec<Fmi3Variable>,
    pub outputs: Vec<Fmi3Unknown>,
    /// `<ContinuousStateDerivative>`s, in the order of the continuous state vector.
    pub continuous_state_derivatives: Vec<Fmi3Unknown>,
    pub initial_unknowns: Vec<Fmi3Unknown>,
}

/// The `fmiVersion` attribute of a model description's root, without reading the rest:
/// which reader a file needs.
pub fn fmi_version_of(bytes: &[u8]) -> Option<String> {
    // The root's attributes may reference entities: a file with declarations is left to the
    // reader, which refuses it.
    crate::refuse_declarations(bytes).ok()?;
    let mut reader = ParserConfig::new().create_reader(bytes);
    loop {
        match reader.next().ok()? {
            XmlEvent::StartElement { attributes, .. } => {
                return attributes
                    .iter()
                    .find(|a| a.name.local_name == "fmiVersion")
                    .map(|a| a.value.clone());
            }
            XmlEvent::EndDocument => return None,
            _ => {}
        }
    }
}

impl Fmi3ModelDescription {
    pub fn from_file(path: impl AsRef<Path>) -> Result<Self, Error> {
        let path = path.as_ref();
        let bytes = std::fs::read(path).map_err(|source| Error::Io {
            path: path.to_owned(),
            source,
        })?;
        Self::from_bytes(&bytes)
    }

    pub fn from_xml(xml: &str) -> Result<Self, Error> {
        Self::from_bytes(xml.as_bytes())
    }

    pub fn from_bytes(bytes: &[u8]) -> Result<Self, Error> {
        crate::refuse_declarations(bytes)?;
        let config = ParserConfig::new()
            .trim_whitespace(true)
            .ignore_comments(true);
        let mut reader = config.create_reader(bytes);
        let mut description = Fmi3ModelDescription::default();
        // Names of the open elements, root first.
        let mut stack: Vec<String> = Vec::new();
        loop {
            let event = reader.next().map_err(|e| Error::malformed(&e, &stack))?;
            match event {
                XmlEvent::StartElement {
                    name, attributes, ..
                } => {
                    let line = xml::common::Position::position(&reader).row + 1;
                    let local = name.local_name;
                    let attrs: Vec<(String, String)> = attributes
                        .into_iter()
                        .filter(|a| a.name.prefix.is_none())
                        .map(|a| (a.name.local_name, a.value))
                        .collect();
                    let at = Attributes {
                        line,
                        element: &local,
                        attrs: &attrs,
                    };
                    let parent: Vec<&str> = stack.iter().map(String::as_str).collect();
                    description.element(&parent, &local, &at)?;
                    stack.push(local);
                }
                XmlEvent::EndElement { .. } => {
                    stack.pop();
                }
                XmlEvent::EndDocument => break,
                _ => {}
            }
        }
        if description.fmi_version.is_empty() {
            return Err(Error::Invalid {
                line: 1,
                element: "fmiModelDescription".into(),
                attribute: Some("fmiVersion".into()),
                problem: "required attribute missing".into(),
            });
        }
        Ok(description)
    }

    fn element(&mut self, parent: &[&str], name: &str, at: &Attributes) -> Result<(), Error> {
        match (parent, name) {
            ([], "fmiModelDescription") => {
                self.fmi_version = at.required("fmiVersion")?.to_owned();
                self.model_name = at.required("modelName")?.to_owned();
                self.instantiation_token = at.required("instantiationToken")?.to_owned();
                self.description = at.get("description").map(str::to_owned);
                self.author = at.get("author").map(str::to_owned);
                self.version = at.get("version").map(str::to_owned);
                self.copyright = at.get("copyright").map(str::to_owned);
                self.license = at.get("license").map(str::to_owned);
                self.generation_tool = at.get("generationTool").map(str::to_owned);
                self.generation_date_and_time = at.get("generationDateAndTime").map(str::to_owned);
                self.variable_naming_convention =
                    at.get("variableNamingConvention").map(str::to_owned);
            }
            ([], other) => {
                return Err(Error::WrongRoot {
                    found: other.to_owned(),
                })
            }
            ([_], "CoSimulation") => {
                self.co_simulation = Some(Fmi3CoSimulation {
                    model_identifier: at.required("modelIdentifier")?.to_owned(),
                    needs_execution_tool: at.flag("needsExecutionTool")?,
                    can_be_instantiated_only_once_per_process: at
                        .flag("canBeInstantiatedOnlyOncePerProcess")?,
                    can_get_and_set_fmu_state: at.flag("canGetAndSetFMUState")?,
                    can_serialize_fmu_state: at.flag("canSerializeFMUState")?,
                    can_handle_variable_communication_step_size: at
                        .flag("canHandleVariableCommunicationStepSize")?,
                    fixed_internal_step_size: at.float("fixedInternalStepSize")?,
                    might_return_early_from_do_step: at.flag("mightReturnEarlyFromDoStep")?,
                    can_return_early_after_intermediate_update: at
                        .flag("canReturnEarlyAfterIntermediateUpdate")?,
                    has_event_mode: at.flag("hasEventMode")?,
                    provides_intermediate_update: at.flag("providesIntermediateUpdate")?,
                    provides_directional_derivatives: at.flag("providesDirectionalDerivatives")?,
                    provides_adjoint_derivatives: at.flag("providesAdjointDerivatives")?,
                });
            }
            ([_], "ModelExchange") => {
                let model_identifier = at.required("modelIdentifier")?.to_owned();
                self.model_exchange_flags = Some(Fmi3ModelExchange {
                    model_identifier: model_identifier.clone(),
                    provides_directional_derivatives: at.flag("providesDirectionalDerivatives")?,
                    provides_adjoint_derivatives: at.flag("providesAdjointDerivatives")?,
                });
                self.model_exchange = Some(model_identifier);
            }
            ([_], "ScheduledExecution") => {
                self.scheduled_execution = Some(at.required("modelIdentifier")?.to_owned());
            }
            ([_], "DefaultExperiment") => {
                self.default_start_time = at.float("startTime")?;
                self.default_stop_time = at.float("stopTime")?;
                self.default_tolerance = at.float("tolerance")?;
                self.default_step_size = at.float("stepSize")?;
            }
            ([_, "TypeDefinitions"], type_name) => {
                self.type_definitions.push(Fmi3TypeDefinition {
                    name: at.required("name")?.to_owned(),
                    kind: type_name
                        .strip_suffix("Type")
                        .and_then(Fmi3Type::from_element),
                    unit: at.get("unit").map(str::to_owned),
                    items: Vec::new(),
                });
            }
            ([_, "TypeDefinitions", "EnumerationType"], "Item") => {
                let value = at.parse::<i64>("value", "an integer")?.unwrap_or(0);
                let item = (at.required("name")?.to_owned(), value);
                if let Some(definition) = self.type_definitions.last_mut() {
                    definition.items.push(item);
                }
            }
            ([_, "ModelVariables"], type_name) => {
                let Some(kind) = Fmi3Type::from_element(type_name) else {
                    return Err(at.invalid(
                        None,
                        format!("<{type_name}> is not an FMI 3.0 variable type"),
                    ));
                };
                let causality_text = at.get("causality");
                let structural = causality_text == Some("structuralParameter");
                let causality = match causality_text {
                    None | Some("structuralParameter") => None,
                    Some(text) => Some(parse_enum::<Causality>(at, "causality", text)?),
                };
                let variability = at
                    .get("variability")
                    .map(|text| parse_enum::<Variability>(at, "variability", text))
                    .transpose()?;
                let initial = at
                    .get("initial")
                    .map(|text| parse_enum::<Initial>(at, "initial", text))
                    .transpose()?;
                self.variables.push(Fmi3Variable {
                    name: at.required("name")?.to_owned(),
                    value_reference: at
                        .parse::<u32>("valueReference", "an unsigned integer")?
                        .ok_or_else(|| {
                            at.invalid(Some("valueReference"), "required attribute missing".into())
                        })?,
                    kind,
                    description: at.get("description").map(str::to_owned),
                    causality,
                    structural,
                    variability,
                    initial,
                    declared_type: at.get("declaredType").map(str::to_owned),
                    unit: at.get("unit").map(str::to_owned),
                    start: at
                        .get("start")
                        .map(|s| s.split_whitespace().map(str::to_owned).collect())
                        .unwrap_or_default(),
                    dimensions: Vec::new(),
                    clocks: at.get("clocks").map(str::to_owned),
                    aliases: Vec::new(),
                    derivative: at.parse::<u32>("derivative", "an unsigned integer")?,
                });
            }
            ([_, "ModelVariables", _], "Dimension") => {
                let dimension = Fmi3Dimension {
                    start: at.parse::<u64>("start", "an unsigned integer")?,
                    value_reference: at.parse::<u32>("valueReference", "an unsigned integer")?,
                };
                if let Some(variable) = self.variables.last_mut() {
                    variable.dimensions.push(dimension);
                }
            }
            ([_, "ModelVariables", _], "Alias") => {
                let alias = Fmi3Alias {
                    name: at.required("name")?.to_owned(),
                    description: at.get("description").map(str::to_owned),
                    display_unit: at.get("displayUnit").map(str::to_owned),
                };
                if let Some(variable) = self.variables.last_mut() {
                    variable.aliases.push(alias);
                }
            }
            ([_, "ModelVariables", _], "Start") => {
                if let Some(variable) = self.variables.last_mut() {
                    variable
                        .start
                        .push(at.get("value").unwrap_or_default().to_owned());
                }
            }
            (
                [_, "ModelStructure"],
                unknown @ ("Output" | "ContinuousStateDerivative" | "InitialUnknown"),
            ) => {
                let value_reference = at
                    .parse::<u32>("valueReference", "an unsigned integer")?
                    .ok_or_else(|| {
                        at.invalid(Some("valueReference"), "required attribute missing".into())
                    })?;
                let dependencies = at
                    .get("dependencies")
                    .map(|list| {
                        list.split_whitespace()
                            .map(|vr| {
                                vr.parse::<u32>().map_err(|e| {
                                    at.invalid(
                                        Some("dependencies"),
                                        format!("{vr:?} is not an unsigned integer: {e}"),
                                    )
                                })
                            })
                            .collect::<Result<Vec<_>, _>>()
                    })
                    .transpose()?;
                let entry = Fmi3Unknown {
                    value_reference,
                    dependencies,
                };
                match unknown {
                    "Output" => self.outputs.push(entry),
                    "ContinuousStateDerivative" => self.continuous_state_derivatives.push(entry),
                    _ => self.initial_unknowns.push(entry),
                }
            }
            _ => {}
        }
        Ok(())
    }

    /// The variable with this value reference.
    pub fn variable_by_reference(&self, value_reference: u32) -> Option<&Fmi3Variable> {
        self.variables
            .iter()
            .find(|v| v.value_reference == value_reference)
    }

    pub fn type_definition(&self, name: &str) -> Option<&Fmi3TypeDefinition> {
        self.type_definitions.iter().find(|t| t.name == name)
    }
}

fn parse_enum<T: serde::de::DeserializeOwned>(
    at: &Attributes,
    attribute: &str,
    text: &str,
) -> Result<T, Error> {
    use serde::de::IntoDeserializer;
    let deserializer: serde::de::value::StrDeserializer<'_, serde::de::value::Error> =
        text.into_deserializer();
    T::deserialize(deserializer).map_err(|_| {
        at.invalid(
            Some(attribute),
            format!("{text:?} is not a valid {attribute}"),
        )
    })
}

struct Attributes<'a> {
    line: u64,
    element: &'a str,
    attrs: &'a [(String, String)],
}

impl Attributes<'_> {
    fn get(&self, name: &str) -> Option<&str> {
        self.attrs
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_str())
    }

    fn invalid(&self, attribute: Option<&str>, problem: String) -> Error {
        let element = match self.get("name") {
            Some(name) => format!("{} '{name}'", self.element),
            None => self.element.to_owned(),
        };
        Error::Invalid {
            line: self.line,
            element,
            attribute: attribute.map(str::to_owned),
            problem,
        }
    }

    fn required(&self, name: &str) -> Result<&str, Error> {
        self.get(name).ok_or_else(|| {
            self.invalid(
                Some(name),
                "required attribute missing (read as FMI 3.0)".into(),
            )
        })
    }

    fn parse<T: std::str::FromStr>(&self, name: &str, what: &str) -> Result<Option<T>, Error>
    where
        T::Err: std::fmt::Display,
    {
        self.get(name)
            .map(|text| {
                text.trim()
                    .parse::<T>()
                    .map_err(|e| self.invalid(Some(name), format!("{text:?} is not {what}: {e}")))
            })
            .transpose()
    }

    fn float(&self, name: &str) -> Result<Option<f64>, Error> {
        self.parse::<f64>(name, "a number")
    }

    fn flag(&self, name: &str) -> Result<bool, Error> {
        match self.get(name) {
            None => Ok(false),
            Some("true" | "1") => Ok(true),
            Some("false" | "0") => Ok(false),
            Some(other) => Err(self.invalid(Some(name), format!("{other:?} is not a boolean"))),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SAMPLE: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="3.0" modelName="M" instantiationToken="{tok}" version="1.2" author="A" generationTool="T" generationDateAndTime="2026-01-02T03:04:05Z">
  <CoSimulation modelIdentifier="M" canHandleVariableCommunicationStepSize="true" hasEventMode="true" mightReturnEarlyFromDoStep="true"/>
  <TypeDefinitions>
    <Float64Type name="m" unit="m"/>
    <EnumerationType name="E"><Item name="a" value="1"/><Item name="b" value="2"/></EnumerationType>
  </TypeDefinitions>
  <ModelVariables>
    <Float64 name="r" valueReference="1" causality="input" declaredType="m" start="0 800 0"><Dimension start="3"/><Alias name="r_alias" description="the same r"/></Float64>
    <Int32 name="n" valueReference="4" causality="output"/>
    <Enumeration name="e" valueReference="5" causality="parameter" variability="fixed" declaredType="E" start="2"/>
    <String name="s" valueReference="6" causality="parameter" variability="fixed"><Start value="hello world"/></String>
  </ModelVariables>
  <ModelStructure>
    <Output valueReference="4" dependencies="1"/>
    <InitialUnknown valueReference="4"/>
  </ModelStructure>
</fmiModelDescription>"#;

    #[test]
    fn a_co_simulation_description_reads_with_arrays_flags_and_dependencies() {
        let md = Fmi3ModelDescription::from_xml(SAMPLE).unwrap();
        assert_eq!(md.fmi_version, "3.0");
        assert_eq!(md.instantiation_token, "{tok}");
        // What a report shows of where the FMU came from.
        assert_eq!(md.version.as_deref(), Some("1.2"));
        assert_eq!(md.author.as_deref(), Some("A"));
        assert_eq!(md.generation_tool.as_deref(), Some("T"));
        assert_eq!(
            md.generation_date_and_time.as_deref(),
            Some("2026-01-02T03:04:05Z")
        );
        assert_eq!(md.license, None);
        let cs = md.co_simulation.as_ref().unwrap();
        assert!(cs.has_event_mode && cs.might_return_early_from_do_step);
        assert!(!cs.provides_intermediate_update);
        let r = &md.variables[0];
        assert_eq!(r.kind, Fmi3Type::Float64);
        assert_eq!(r.start, ["0", "800", "0"]);
        assert_eq!(r.dimensions[0].start, Some(3));
        assert_eq!(r.aliases[0].name, "r_alias");
        assert_eq!(r.aliases[0].description.as_deref(), Some("the same r"));
        assert!(md.variables[1].aliases.is_empty());
        assert_eq!(r.variability_or_default(), Variability::Continuous);
        assert_eq!(
            md.variables[1].variability_or_default(),
            Variability::Discrete
        );
        assert_eq!(md.variables[3].start, ["hello world"]);
        assert_eq!(md.outputs[0].dependencies.as_deref(), Some(&[1][..]));
        assert_eq!(md.initial_unknowns[0].dependencies, None);
        assert_eq!(md.type_definition("E").unwrap().items.len(), 2);
        assert_eq!(fmi_version_of(SAMPLE.as_bytes()).as_deref(), Some("3.0"));
    }

    #[test]
    fn derivative_capabilities_and_state_derivatives_are_read() {
        // GIVEN the Reference-FMUs VanDerPol's declarations in short
        let xml = r#"<fmiModelDescription fmiVersion="3.0" modelName="V" instantiationToken="t">
  <ModelExchange modelIdentifier="V" providesDirectionalDerivatives="true" providesAdjointDerivatives="true"/>
  <CoSimulation modelIdentifier="V" providesDirectionalDerivatives="true"/>
  <ModelVariables>
    <Float64 name="x0" valueReference="1" causality="output"/>
    <Float64 name="der(x0)" valueReference="2" derivative="1"/>
  </ModelVariables>
  <ModelStructure>
    <Output valueReference="1" dependencies=""/>
    <ContinuousStateDerivative valueReference="2" dependencies="1"/>
  </ModelStructure>
</fmiModelDescription>"#;
        let md = Fmi3ModelDescription::from_xml(xml).unwrap();
        let me = md.model_exchange_flags.as_ref().unwrap();
        assert!(me.provides_directional_derivatives && me.provides_adjoint_derivatives);
        let cs = md.co_simulation.as_ref().unwrap();
        assert!(cs.provides_directional_derivatives && !cs.provides_adjoint_derivatives);
        assert_eq!(md.variables[1].derivative, Some(1));
        assert_eq!(md.variables[0].derivative, None);
        assert_eq!(md.continuous_state_derivatives.len(), 1);
        assert_eq!(
            md.continuous_state_derivatives[0].dependencies.as_deref(),
            Some(&[1][..])
        );
        assert_eq!(md.outputs[0].dependencies.as_deref(), Some(&[][..]));
        // AND the sample without the flags reads them as false
        let sample = Fmi3ModelDescription::from_xml(SAMPLE).unwrap();
        assert!(
            !sample
                .co_simulation
                .unwrap()
                .provides_directional_derivatives
        );
    }

    #[test]
    fn a_bad_attribute_is_reported_with_its_line_and_variable() {
        let bad = SAMPLE.replace(
            r#"valueReference="4" causality="output""#,
            r#"valueReference="x4" causality="output""#,
        );
        let text = Fmi3ModelDescription::from_xml(&bad)
            .unwrap_err()
            .to_string();
        assert!(
            text.contains("Int32 'n'") && text.contains("valueReference"),
            "{text}"
        );
    }
}
