//! The FMI 2.0 model description schema (fmi2ModelDescription.xsd) as Rust types.
//! Optional attributes are `Option`s; unknown elements and attributes are ignored on read.
use serde::{Deserialize, Serialize};

/// `<fmiModelDescription>`: the root element.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(rename = "fmiModelDescription")]
pub struct ModelDescription {
    #[serde(rename = "@fmiVersion")]
    pub fmi_version: String,
    #[serde(rename = "@modelName")]
    pub model_name: String,
    #[serde(rename = "@guid")]
    pub guid: String,
    #[serde(
        rename = "@description",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub description: Option<String>,
    #[serde(rename = "@author", default, skip_serializing_if = "Option::is_none")]
    pub author: Option<String>,
    #[serde(rename = "@version", default, skip_serializing_if = "Option::is_none")]
    pub version: Option<String>,
    #[serde(
        rename = "@copyright",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub copyright: Option<String>,
    #[serde(rename = "@license", default, skip_serializing_if = "Option::is_none")]
    pub license: Option<String>,
    #[serde(
        rename = "@generationTool",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub generation_tool: Option<String>,
    #[serde(
        rename = "@generationDateAndTime",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub generation_date_and_time: Option<String>,
    /// "flat" (default) or "structured".
    #[serde(
        rename = "@variableNamingConvention",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub variable_naming_convention: Option<String>,
    #[serde(
        rename = "@numberOfEventIndicators",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub number_of_event_indicators: Option<u32>,

    #[serde(
        rename = "ModelExchange",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub model_exchange: Option<ModelExchange>,
    #[serde(
        rename = "CoSimulation",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub co_simulation: Option<CoSimulation>,
    #[serde(
        rename = "UnitDefinitions",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub unit_definitions: Option<UnitDefinitions>,
    #[serde(
        rename = "TypeDefinitions",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub type_definitions: Option<TypeDefinitions>,
    #[serde(
        rename = "LogCategories",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub log_categories: Option<LogCategories>,
    #[serde(
        rename = "DefaultExperiment",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub default_experiment: Option<DefaultExperiment>,
    #[serde(rename = "ModelVariables", default)]
    pub model_variables: ModelVariables,
    #[serde(rename = "ModelStructure", default)]
    pub model_structure: ModelStructure,
}

/// `<ModelExchange>` capability flags.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct ModelExchange {
    #[serde(rename = "@modelIdentifier")]
    pub model_identifier: String,
    #[serde(
        rename = "@needsExecutionTool",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub needs_execution_tool: Option<bool>,
    #[serde(
        rename = "@completedIntegratorStepNotNeeded",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub completed_integrator_step_not_needed: Option<bool>,
    #[serde(
        rename = "@canBeInstantiatedOnlyOncePerProcess",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub can_be_instantiated_only_once_per_process: Option<bool>,
    #[serde(
        rename = "@canNotUseMemoryManagementFunctions",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub can_not_use_memory_management_functions: Option<bool>,
    #[serde(
        rename = "@canGetAndSetFMUstate",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub can_get_and_set_fmu_state: Option<bool>,
    #[serde(
        rename = "@canSerializeFMUstate",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub can_serialize_fmu_state: Option<bool>,
    #[serde(
        rename = "@providesDirectionalDerivative",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub provides_directional_derivative: Option<bool>,
}

/// `<CoSimulation>` capability flags.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct CoSimulation {
    #[serde(rename = "@modelIdentifier")]
    pub model_identifier: String,
    #[serde(
        rename = "@needsExecutionTool",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub needs_execution_tool: Option<bool>,
    #[serde(
        rename = "@canHandleVariableCommunicationStepSize",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub can_handle_variable_communication_step_size: Option<bool>,
    #[serde(
        rename = "@canInterpolateInputs",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub can_interpolate_inputs: Option<bool>,
    #[serde(
        rename = "@maxOutputDerivativeOrder",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub max_output_derivative_order: Option<u32>,
    #[serde(
        rename = "@canRunAsynchronuously",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub can_run_asynchronuously: Option<bool>,
    #[serde(
        rename = "@canBeInstantiatedOnlyOncePerProcess",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub can_be_instantiated_only_once_per_process: Option<bool>,
    #[serde(
        rename = "@canNotUseMemoryManagementFunctions",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub can_not_use_memory_management_functions: Option<bool>,
    #[serde(
        rename = "@canGetAndSetFMUstate",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub can_get_and_set_fmu_state: Option<bool>,
    #[serde(
        rename = "@canSerializeFMUstate",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub can_serialize_fmu_state: Option<bool>,
    #[serde(
        rename = "@providesDirectionalDerivative",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub provides_directional_derivative: Option<bool>,
}

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct UnitDefinitions {
    #[serde(rename = "Unit", default)]
    pub units: Vec<Unit>,
}

/// `<Unit name="m/s"><BaseUnit m="1" s="-1"/></Unit>`
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct Unit {
    #[serde(rename = "@name")]
    pub name: String,
    #[serde(rename = "BaseUnit", default, skip_serializing_if = "Option::is_none")]
    pub base_unit: Option<BaseUnit>,
    #[serde(rename = "DisplayUnit", default, skip_serializing_if = "Vec::is_empty")]
    pub display_units: Vec<DisplayUnit>,
}

/// SI exponents of a unit, plus factor and offset; absent exponents are 0.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct BaseUnit {
    #[serde(rename = "@kg", default, skip_serializing_if = "Option::is_none")]
    pub kg: Option<i32>,
    #[serde(rename = "@m", default, skip_serializing_if = "Option::is_none")]
    pub m: Option<i32>,
    #[serde(rename = "@s", default, skip_serializing_if = "Option::is_none")]
    pub s: Option<i32>,
    #[serde(rename = "@A", default, skip_serializing_if = "Option::is_none")]
    pub a: Option<i32>,
    #[serde(rename = "@K", default, skip_serializing_if = "Option::is_none")]
    pub k: Option<i32>,
    #[serde(rename = "@mol", default, skip_serializing_if = "Option::is_none")]
    pub mol: Option<i32>,
    #[serde(rename = "@cd", default, skip_serializing_if = "Option::is_none")]
    pub cd: Option<i32>,
    #[serde(rename = "@rad", default, skip_serializing_if = "Option::is_none")]
    pub rad: Option<i32>,
    #[serde(
        rename = "@factor",
        default,
        skip_serializing_if = "Option::is_none",
        with = "crate::xsd::opt_f64"
    )]
    pub factor: Option<f64>,
    #[serde(
        rename = "@offset",
        default,
        skip_serializing_if = "Option::is_none",
        with = "crate::xsd::opt_f64"
    )]
    pub offset: Option<f64>,
}

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct DisplayUnit {
    #[serde(rename = "@name")]
    pub name: String,
    #[serde(
        rename = "@factor",
        default,
        skip_serializing_if = "Option::is_none",
        with = "crate::xsd::opt_f64"
    )]
    pub factor: Option<f64>,
    #[serde(
        rename = "@offset",
        default,
        skip_serializing_if = "Option::is_none",
        with = "crate::xsd::opt_f64"
    )]
    pub offset: Option<f64>,
}

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct TypeDefinitions {
    #[serde(rename = "SimpleType", default)]
    pub simple_types: Vec<SimpleType>,
}

/// `<SimpleType name=".."><Enumeration><Item name="a" value="1"/></Enumeration></SimpleType>`
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct SimpleType {
    #[serde(rename = "@name")]
    pub name: String,
    #[serde(
        rename = "@description",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub description: Option<String>,
    #[serde(rename = "Real", default, skip_serializing_if = "Option::is_none")]
    pub real: Option<RealType>,
    #[serde(rename = "Integer", default, skip_serializing_if = "Option::is_none")]
    pub integer: Option<IntegerType>,
    #[serde(rename = "Boolean", default, skip_serializing_if = "Option::is_none")]
    pub boolean: Option<Empty>,
    #[serde(rename = "String", default, skip_serializing_if = "Option::is_none")]
    pub string: Option<Empty>,
    #[serde(
        rename = "Enumeration",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub enumeration: Option<EnumerationType>,
}

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct Empty {}

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct RealType {
    #[serde(rename = "@quantity", default, skip_serializing_if = "Option::is_none")]
    pub quantity: Option<String>,
    #[serde(rename = "@unit", default, skip_serializing_if = "Option::is_none")]
    pub unit: Option<String>,
    #[serde(
        rename = "@min",
        default,
        skip_serializing_if = "Option::is_none",
        with = "crate::xsd::opt_f64"
    )]
    pub min: Option<f64>,
    #[serde(
        rename = "@max",
        default,
        skip_serializing_if = "Option::is_none",
        with = "crate::xsd::opt_f64"
    )]
    pub max: Option<f64>,
}

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct IntegerType {
    #[serde(rename = "@quantity", default, skip_serializing_if = "Option::is_none")]
    pub quantity: Option<String>,
    #[serde(rename = "@min", default, skip_serializing_if = "Option::is_none")]
    pub min: Option<i32>,
    #[serde(rename = "@max", default, skip_serializing_if = "Option::is_none")]
    pub max: Option<i32>,
}

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct EnumerationType {
    #[serde(rename = "@quantity", default, skip_serializing_if = "Option::is_none")]
    pub quantity: Option<String>,
    #[serde(rename = "Item", default)]
    pub items: Vec<EnumerationItem>,
}

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct EnumerationItem {
    #[serde(rename = "@name")]
    pub name: String,
    #[serde(rename = "@value")]
    pub value: i32,
    #[serde(
        rename = "@description",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub description: Option<String>,
}

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct LogCategories {
    #[serde(rename = "Category", default)]
    pub categories: Vec<Category>,
}

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct Category {
    #[serde(rename = "@name")]
    pub name: String,
    #[serde(
        rename = "@description",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub description: Option<String>,
}

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct DefaultExperiment {
    #[serde(
        rename = "@startTime",
        default,
        skip_serializing_if = "Option::is_none",
        with = "crate::xsd::opt_f64"
    )]
    pub start_time: Option<f64>,
    #[serde(
        rename = "@stopTime",
        default,
        skip_serializing_if = "Option::is_none",
        with = "crate::xsd::opt_f64"
    )]
    pub stop_time: Option<f64>,
    #[serde(
        rename = "@tolerance",
        default,
        skip_serializing_if = "Option::is_none",
        with = "crate::xsd::opt_f64"
    )]
    pub tolerance: Option<f64>,
    #[serde(
        rename = "@stepSize",
        default,
        skip_serializing_if = "Option::is_none",
        with = "crate::xsd::opt_f64"
    )]
    pub step_size: Option<f64>,
}

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct ModelVariables {
    #[serde(rename = "ScalarVariable", default)]
    pub variables: Vec<ScalarVariable>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub enum Causality {
    Parameter,
    CalculatedParameter,
    Input,
    Output,
    Local,
    Independent,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub enum Variability {
    Constant,
    Fixed,
    Tunable,
    Discrete,
    Continuous,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub enum Initial {
    Exact,
    Approx,
    Calculated,
}

/// `<ScalarVariable>`: exactly one of the type elements is present.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct ScalarVariable {
    #[serde(rename = "@name")]
    pub name: String,
    #[serde(rename = "@valueReference")]
    pub value_reference: u32,
    #[serde(
        rename = "@description",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub description: Option<String>,
    /// Absent means `local` (FMI 2.0 default).
    #[serde(
        rename = "@causality",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub causality: Option<Causality>,
    /// Absent means `continuous` (FMI 2.0 default).
    #[serde(
        rename = "@variability",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub variability: Option<Variability>,
    #[serde(rename = "@initial", default, skip_serializing_if = "Option::is_none")]
    pub initial: Option<Initial>,
    #[serde(
        rename = "@canHandleMultipleSetPerTimeInstant",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub can_handle_multiple_set_per_time_instant: Option<bool>,
    #[serde(rename = "Real", default, skip_serializing_if = "Option::is_none")]
    pub real: Option<RealVariable>,
    #[serde(rename = "Integer", default, skip_serializing_if = "Option::is_none")]
    pub integer: Option<IntegerVariable>,
    #[serde(rename = "Boolean", default, skip_serializing_if = "Option::is_none")]
    pub boolean: Option<BooleanVariable>,
    #[serde(rename = "String", default, skip_serializing_if = "Option::is_none")]
    pub string: Option<StringVariable>,
    #[serde(
        rename = "Enumeration",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub enumeration: Option<EnumerationVariable>,
}

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct RealVariable {
    #[serde(
        rename = "@declaredType",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub declared_type: Option<String>,
    #[serde(rename = "@quantity", default, skip_serializing_if = "Option::is_none")]
    pub quantity: Option<String>,
    #[serde(rename = "@unit", default, skip_serializing_if = "Option::is_none")]
    pub unit: Option<String>,
    #[serde(
        rename = "@displayUnit",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub display_unit: Option<String>,
    #[serde(
        rename = "@min",
        default,
        skip_serializing_if = "Option::is_none",
        with = "crate::xsd::opt_f64"
    )]
    pub min: Option<f64>,
    #[serde(
        rename = "@max",
        default,
        skip_serializing_if = "Option::is_none",
        with = "crate::xsd::opt_f64"
    )]
    pub max: Option<f64>,
    #[serde(
        rename = "@nominal",
        default,
        skip_serializing_if = "Option::is_none",
        with = "crate::xsd::opt_f64"
    )]
    pub nominal: Option<f64>,
    #[serde(
        rename = "@start",
        default,
        skip_serializing_if = "Option::is_none",
        with = "crate::xsd::opt_f64"
    )]
    pub start: Option<f64>,
    #[serde(
        rename = "@derivative",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub derivative: Option<u32>,
}

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct IntegerVariable {
    #[serde(
        rename = "@declaredType",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub declared_type: Option<String>,
    #[serde(rename = "@quantity", default, skip_serializing_if = "Option::is_none")]
    pub quantity: Option<String>,
    #[serde(rename = "@min", default, skip_serializing_if = "Option::is_none")]
    pub min: Option<i32>,
    #[serde(rename = "@max", default, skip_serializing_if = "Option::is_none")]
    pub max: Option<i32>,
    #[serde(rename = "@start", default, skip_serializing_if = "Option::is_none")]
    pub start: Option<i32>,
}

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct BooleanVariable {
    #[serde(
        rename = "@declaredType",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub declared_type: Option<String>,
    #[serde(rename = "@start", default, skip_serializing_if = "Option::is_none")]
    pub start: Option<bool>,
}

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct StringVariable {
    #[serde(
        rename = "@declaredType",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub declared_type: Option<String>,
    #[serde(rename = "@start", default, skip_serializing_if = "Option::is_none")]
    pub start: Option<String>,
}

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct EnumerationVariable {
    /// Required for enumerations: the `SimpleType` that lists the items.
    #[serde(rename = "@declaredType")]
    pub declared_type: String,
    #[serde(rename = "@quantity", default, skip_serializing_if = "Option::is_none")]
    pub quantity: Option<String>,
    #[serde(rename = "@min", default, skip_serializing_if = "Option::is_none")]
    pub min: Option<i32>,
    #[serde(rename = "@max", default, skip_serializing_if = "Option::is_none")]
    pub max: Option<i32>,
    #[serde(rename = "@start", default, skip_serializing_if = "Option::is_none")]
    pub start: Option<i32>,
}

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct ModelStructure {
    #[serde(rename = "Outputs", default, skip_serializing_if = "Option::is_none")]
    pub outputs: Option<UnknownList>,
    #[serde(
        rename = "Derivatives",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub derivatives: Option<UnknownList>,
    #[serde(
        rename = "InitialUnknowns",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub initial_unknowns: Option<UnknownList>,
}

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct UnknownList {
    #[serde(rename = "Unknown", default)]
    pub unknowns: Vec<Unknown>,
}

/// `<Unknown index="3" dependencies="1 2"/>`: `index` is 1-based into `ModelVariables`.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct Unknown {
    #[serde(rename = "@index")]
    pub index: u32,
    /// Space-separated 1-based indices; absent = depends on everything, empty = on nothing.
    #[serde(
        rename = "@dependencies",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub dependencies: Option<String>,
    #[serde(
        rename = "@dependenciesKind",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub dependencies_kind: Option<String>,
}
