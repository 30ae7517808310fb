//! The FMI 3.0 `modelDescription.xml` and the `instantiationToken`, both from the
//! declarations. A vector is one `<Float64>` with a `<Dimension start="n"/>`; an enumeration
//! is an `<Enumeration>` of an `<EnumerationType>`; `time` is the independent variable.
use crate::variables::{self, Type, TIME_VR};
use fmi_model::{
    Causality, ContinuousModel, Declaration, Dependencies, Initial, Kind, Model, Shape, Variability,
};
use std::collections::BTreeSet;
use std::fmt::Write;
use uuid::Uuid;

/// The UUID v5 of the interface: modelIdentifier and, per declaration, name, value
/// reference, type, shape, causality and variability (and enumeration items).
pub fn interface_uuid<M: Model>() -> Uuid {
    let namespace = Uuid::new_v5(
        &Uuid::NAMESPACE_URL,
        b"urn:lander-fmi:fmi3-export:interface",
    );
    let mut text = format!("modelIdentifier={}\n", M::MODEL_IDENTIFIER);
    for d in M::declarations() {
        let extra = match &d.kind {
            Kind::Enumeration { ty, .. } => ty.listing(),
            _ => String::new(),
        };
        let _ = writeln!(
            text,
            "{}\t{}\t{:?}\t{}\t{:?}\t{:?}\t{extra}",
            d.name,
            d.value_reference,
            Type::of(d),
            d.shape().len(),
            d.causality,
            d.variability
        );
    }
    Uuid::new_v5(&namespace, text.as_bytes())
}

/// The `instantiationToken`: `{xxxxxxxx-xxxx-5xxx-xxxx-xxxxxxxxxxxx}`.
pub fn instantiation_token<M: Model>() -> String {
    format!("{{{}}}", interface_uuid::<M>())
}

/// What Model Exchange adds to the description.
struct ModelExchange {
    state_derivatives: &'static [(&'static str, &'static str)],
    event_indicators: &'static [&'static str],
    /// [`ContinuousModel::DECLARES_STATE_DEPENDENCIES`].
    declared: bool,
    /// [`ContinuousModel::state_dependencies`].
    state_dependencies: fn(&str) -> Option<&'static [&'static str]>,
    /// [`ContinuousModel::derivative_input_dependencies`].
    derivative_inputs: fn(&str) -> Dependencies,
}

impl ModelExchange {
    /// The value references of the states `unknown` depends on.
    fn states<M: Model>(&self, unknown: &str) -> Vec<String> {
        let all: Vec<&str> = self.state_derivatives.iter().map(|(s, _)| *s).collect();
        let states = (self.state_dependencies)(unknown).map_or(all, <[&str]>::to_vec);
        states
            .iter()
            .map(|state| {
                assert!(
                    self.state_derivatives.iter().any(|(s, _)| s == state),
                    "{}: state_dependencies({unknown}) names {state}, which is no continuous \
                     state",
                    M::MODEL_IDENTIFIER
                );
                find::<M>(state).value_reference.to_string()
            })
            .collect()
    }
}

/// A dependency list: value references in ascending order, each once.
fn listed(vrs: impl IntoIterator<Item = String>) -> String {
    let mut vrs: Vec<u32> = vrs.into_iter().filter_map(|v| v.parse().ok()).collect();
    vrs.sort_unstable();
    vrs.dedup();
    vrs.iter().map(u32::to_string).collect::<Vec<_>>().join(" ")
}

/// The description of a Co-Simulation-only model.
///
/// # Panics
/// If the declarations cannot make a valid description (see [`variables::check`]): this
/// runs when packaging, where a loud stop is the right answer.
pub fn model_description_xml<M: Model>() -> String {
    write_description::<M>(None)
}

/// The description of a model with Co-Simulation and Model Exchange.
///
/// # Panics
/// As [`model_description_xml`], and if `STATE_DERIVATIVES` or `EVENT_INDICATOR_VARIABLES`
/// name an undeclared variable.
pub fn model_description_xml_me<M: ContinuousModel>() -> String {
    write_description::<M>(Some(ModelExchange {
        state_derivatives: M::STATE_DERIVATIVES,
        event_indicators: M::EVENT_INDICATOR_VARIABLES,
        declared: M::DECLARES_STATE_DEPENDENCIES,
        state_dependencies: M::state_dependencies,
        derivative_inputs: M::derivative_input_dependencies,
    }))
}

fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            c => out.push(c),
        }
    }
    out
}

/// `f64` as XML: the shortest text that reads back to the same bits.
fn real(v: f64) -> String {
    if v.is_infinite() {
        if v > 0.0 { "INF" } else { "-INF" }.into()
    } else {
        format!("{v:?}")
    }
}

fn find<M: Model>(name: &str) -> &'static Declaration<M> {
    M::declarations()
        .iter()
        .find(|d| d.name == name)
        .unwrap_or_else(|| panic!("{}: no declaration {name}", M::MODEL_IDENTIFIER))
}

fn causality(c: Causality) -> &'static str {
    match c {
        Causality::Parameter => "parameter",
        Causality::CalculatedParameter => "calculatedParameter",
        Causality::Input => "input",
        Causality::Output => "output",
        Causality::Local => "local",
        Causality::Independent => "independent",
    }
}

fn variability(v: Variability) -> &'static str {
    match v {
        Variability::Constant => "constant",
        Variability::Fixed => "fixed",
        Variability::Tunable => "tunable",
        Variability::Discrete => "discrete",
        Variability::Continuous => "continuous",
    }
}

fn initial_name(i: Initial) -> &'static str {
    match i {
        Initial::Exact => "exact",
        Initial::Approx => "approx",
        Initial::Calculated => "calculated",
    }
}

/// The FMI 3.0 default of `initial` (Table 22), as the FMI 2.0 one for our combinations.
fn effective_initial<M>(d: &Declaration<M>) -> Option<Initial> {
    d.initial.or(match (d.causality, d.variability) {
        (Causality::Parameter, _) => Some(Initial::Exact),
        (Causality::CalculatedParameter, _) => Some(Initial::Calculated),
        (_, Variability::Constant) => Some(Initial::Exact),
        (Causality::Output | Causality::Local, _) => Some(Initial::Calculated),
        _ => None,
    })
}

fn has_start<M>(d: &Declaration<M>) -> bool {
    d.causality == Causality::Input
        || matches!(effective_initial(d), Some(Initial::Exact | Initial::Approx))
}

/// Panics (at build time: the description is written by `cargo xtask fmus` and the tests,
/// never by the FMU) on a declaration table that no description may be written for, as the
/// FMI 2.0 writer refuses it.
fn write_description<M: Model>(me: Option<ModelExchange>) -> String {
    if let Err(problem) = fmi_export::check_units::<M>() {
        panic!("{}: {problem}", M::MODEL_IDENTIFIER);
    }
    let problems = variables::check::<M>();
    assert!(
        problems.is_empty(),
        "{}: {}",
        M::MODEL_IDENTIFIER,
        problems.join("; ")
    );
    let fresh = M::default();
    let id = M::MODEL_IDENTIFIER;
    let mut x = String::new();
    let _ = writeln!(x, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        x,
        r#"<fmiModelDescription fmiVersion="3.0" modelName="{}" instantiationToken="{}" description="{}" author="{}" version="{}" copyright="{}" license="{}" generationTool="lander-fmi fmi3-export {}"{} variableNamingConvention="structured">"#,
        escape(M::MODEL_NAME),
        instantiation_token::<M>(),
        escape(M::DESCRIPTION),
        escape(fmi_export::provenance::AUTHOR),
        escape(M::VERSION),
        escape(fmi_export::provenance::COPYRIGHT),
        escape(fmi_export::provenance::LICENSE),
        env!("CARGO_PKG_VERSION"),
        fmi_export::provenance::generation_date_and_time()
            .map(|t| format!(r#" generationDateAndTime="{t}""#))
            .unwrap_or_default()
    );
    // Absent, the attributes mean false: a model without derivatives keeps its description.
    let provides = if M::PROVIDES_DIRECTIONAL_DERIVATIVES {
        r#" providesDirectionalDerivatives="true" providesAdjointDerivatives="true""#
    } else {
        ""
    };
    if me.is_some() {
        let _ = writeln!(
            x,
            r#"  <ModelExchange modelIdentifier="{id}" needsCompletedIntegratorStep="false" canGetAndSetFMUState="true" canSerializeFMUState="true"{provides}/>"#
        );
    }
    let _ = writeln!(
        x,
        r#"  <CoSimulation modelIdentifier="{id}" canHandleVariableCommunicationStepSize="true" canGetAndSetFMUState="true" canSerializeFMUState="true"{provides} hasEventMode="true" mightReturnEarlyFromDoStep="true" canReturnEarlyAfterIntermediateUpdate="false" providesIntermediateUpdate="false"/>"#
    );
    write_units::<M>(&mut x);
    write_types::<M>(&mut x);
    x.push_str("  <LogCategories>\n");
    for c in crate::version::CATEGORIES {
        let _ = writeln!(
            x,
            r#"    <Category name="{}" description="{}"/>"#,
            c.name().to_string_lossy(),
            escape(c.description())
        );
    }
    x.push_str("  </LogCategories>\n");
    let e = M::DEFAULT_EXPERIMENT;
    let _ = writeln!(
        x,
        r#"  <DefaultExperiment startTime="{}" stopTime="{}" stepSize="{}"/>"#,
        real(e.start_time),
        real(e.stop_time),
        real(e.step_size)
    );
    x.push_str("  <ModelVariables>\n");
    let _ = writeln!(
        x,
        r#"    <Float64 name="time" valueReference="{TIME_VR}" causality="independent" variability="continuous" description="Simulation time"/>"#
    );
    let derivative_of = |name: &str| -> Option<u32> {
        me.as_ref()?
            .state_derivatives
            .iter()
            .find(|(_, der)| *der == name)
            .map(|(state, _)| find::<M>(state).value_reference)
    };
    for d in M::declarations() {
        write_variable(&mut x, d, &fresh, derivative_of(d.name));
    }
    x.push_str("  </ModelVariables>\n");
    write_structure::<M>(&mut x, me.as_ref());
    x.push_str("</fmiModelDescription>\n");
    x
}

fn write_units<M: Model>(x: &mut String) {
    let used: BTreeSet<&str> = M::declarations().iter().filter_map(|d| d.unit).collect();
    if used.is_empty() {
        return;
    }
    x.push_str("  <UnitDefinitions>\n");
    for name in used {
        let _ = write!(x, r#"    <Unit name="{}">"#, escape(name));
        if let Some(b) = fmi_export::base_unit(name) {
            let mut attributes = String::new();
            for (key, value) in [("kg", b.kg), ("m", b.m), ("s", b.s), ("rad", b.rad)] {
                if let Some(v) = value {
                    let _ = write!(attributes, r#" {key}="{v}""#);
                }
            }
            let _ = write!(x, "<BaseUnit{attributes}/>");
        }
        if let Some((display, factor)) = fmi_export::display_unit(name) {
            let _ = write!(
                x,
                r#"<DisplayUnit name="{}" factor="{factor:?}"/>"#,
                escape(display)
            );
        }
        x.push_str("</Unit>\n");
    }
    x.push_str("  </UnitDefinitions>\n");
}

/// Units reach a variable through a `Float64Type` named after its symbol (`declaredType`):
/// equivalent to a `unit` attribute on the variable, and the form every FMI 3.0 reader we
/// test accepts (the `fmi` crate's schema reader refuses `unit` on the variable itself).
fn write_types<M: Model>(x: &mut String) {
    let units: BTreeSet<&str> = M::declarations().iter().filter_map(|d| d.unit).collect();
    if !units.is_empty() {
        x.push_str("  <TypeDefinitions>\n");
    }
    for unit in &units {
        let display = fmi_export::display_unit(unit)
            .map(|(name, _)| format!(r#" displayUnit="{}""#, escape(name)))
            .unwrap_or_default();
        let _ = writeln!(
            x,
            r#"    <Float64Type name="{0}" unit="{0}"{display}/>"#,
            escape(unit)
        );
    }
    let mut written: Vec<&str> = Vec::new();
    for d in M::declarations() {
        // A type exchanged as an Integer is written too, so that a tool can read its items'
        // names.
        if let Kind::Enumeration { ty, .. } = &d.kind {
            if written.contains(&ty.name) {
                continue;
            }
            if written.is_empty() && units.is_empty() {
                x.push_str("  <TypeDefinitions>\n");
            }
            written.push(ty.name);
            let _ = writeln!(
                x,
                r#"    <EnumerationType name="{}" description="{}">"#,
                escape(ty.name),
                escape(ty.description)
            );
            for item in ty.items {
                let _ = writeln!(
                    x,
                    r#"      <Item name="{}" value="{}" description="{}"/>"#,
                    escape(item.name),
                    item.value,
                    escape(item.description)
                );
            }
            x.push_str("    </EnumerationType>\n");
        }
    }
    if !written.is_empty() || !units.is_empty() {
        x.push_str("  </TypeDefinitions>\n");
    }
}

fn write_variable<M>(x: &mut String, d: &Declaration<M>, fresh: &M, derivative: Option<u32>) {
    let element = match Type::of(d) {
        Type::Float64 => "Float64",
        Type::Int32 => "Int32",
        Type::Enumeration => "Enumeration",
        Type::Boolean => "Boolean",
        Type::String => "String",
    };
    let _ = write!(
        x,
        r#"    <{element} name="{}" valueReference="{}" description="{}" causality="{}" variability="{}""#,
        d.name,
        d.value_reference,
        escape(&d.described()),
        causality(d.causality),
        variability(d.variability)
    );
    if let Some(i) = d.initial {
        let _ = write!(x, r#" initial="{}""#, initial_name(i));
    }
    let start = has_start(d);
    let mut children = String::new();
    match &d.kind {
        Kind::Real {
            shape,
            min,
            max,
            get,
            ..
        } => {
            if let Some(unit) = d.unit {
                let _ = write!(x, r#" declaredType="{}""#, escape(unit));
            }
            // Inclusive, as FMI defines them: an exclusive bound is the nearest value it
            // admits, and said in words in the description.
            if let Some(m) = min {
                let _ = write!(x, r#" min="{}""#, real(m.fmi_min()));
            }
            if let Some(m) = max {
                let _ = write!(x, r#" max="{}""#, real(m.fmi_max()));
            }
            if let Some(state) = derivative {
                let _ = write!(x, r#" derivative="{state}""#);
            }
            if start {
                let values: Vec<String> = (0..shape.len()).map(|i| real(get(fresh, i))).collect();
                let _ = write!(x, r#" start="{}""#, values.join(" "));
            }
            if let Shape::Vector(n) = shape {
                let _ = write!(children, r#"<Dimension start="{n}"/>"#);
            }
        }
        Kind::Integer { min, max, get, .. } => {
            if let Some(m) = min {
                let _ = write!(x, r#" min="{m}""#);
            }
            if let Some(m) = max {
                let _ = write!(x, r#" max="{m}""#);
            }
            if start {
                let _ = write!(x, r#" start="{}""#, get(fresh));
            }
        }
        Kind::Enumeration {
            ty,
            get,
            as_integer,
            ..
        } => {
            if *as_integer {
                if let (Some(min), Some(max)) = (ty.min(), ty.max()) {
                    let _ = write!(x, r#" min="{min}" max="{max}""#);
                }
            } else {
                let _ = write!(x, r#" declaredType="{}""#, escape(ty.name));
            }
            if start {
                let _ = write!(x, r#" start="{}""#, get(fresh));
            }
        }
        Kind::Boolean { get, .. } => {
            if start {
                let _ = write!(x, r#" start="{}""#, get(fresh));
            }
        }
        Kind::String { get, .. } => {
            if start {
                let _ = write!(children, r#"<Start value="{}"/>"#, escape(get(fresh)));
            }
        }
    }
    if children.is_empty() {
        x.push_str("/>\n");
    } else {
        let _ = writeln!(x, ">{children}</{element}>");
    }
}

fn write_structure<M: Model>(x: &mut String, me: Option<&ModelExchange>) {
    let declarations = M::declarations();
    let inputs: Vec<&Declaration<M>> = declarations
        .iter()
        .filter(|d| d.causality == Causality::Input)
        .collect();
    let vr_of = |name: &str| find::<M>(name).value_reference.to_string();
    x.push_str("  <ModelStructure>\n");
    for d in declarations
        .iter()
        .filter(|d| d.causality == Causality::Output)
    {
        let dependencies = match M::output_dependencies(d.name) {
            Dependencies::AllInputs => None,
            Dependencies::NoInputs => Some(String::new()),
            Dependencies::Inputs(names) => {
                Some(names.iter().map(|n| vr_of(n)).collect::<Vec<_>>().join(" "))
            }
            // FMI 3.0 would need elementIndices to say "the same element"; the whole input
            // array is the (coarser, still correct) statement.
            Dependencies::SameElementOf(name) => Some(vr_of(name)),
        };
        // Under Model Exchange the states are knowns too (FMI 3.0 §2.4.8): an output lists
        // the ones it depends on, its inputs kept as declared.
        let dependencies = match (me.filter(|me| me.declared), dependencies) {
            (Some(me), Some(list)) => Some(listed(
                list.split_whitespace()
                    .map(str::to_string)
                    .chain(me.states::<M>(d.name)),
            )),
            (Some(me), None) => Some(listed(
                inputs
                    .iter()
                    .map(|i| i.value_reference.to_string())
                    .chain(me.states::<M>(d.name)),
            )),
            (None, dependencies) => dependencies,
        };
        match dependencies {
            Some(list) => {
                let _ = writeln!(
                    x,
                    r#"    <Output valueReference="{}" dependencies="{list}"/>"#,
                    d.value_reference
                );
            }
            None if inputs.is_empty() => {
                let _ = writeln!(
                    x,
                    r#"    <Output valueReference="{}" dependencies=""/>"#,
                    d.value_reference
                );
            }
            None => {
                let _ = writeln!(x, r#"    <Output valueReference="{}"/>"#, d.value_reference);
            }
        }
    }
    let mut initial_unknowns: BTreeSet<u32> = declarations
        .iter()
        .filter(|d| match d.causality {
            Causality::Output => effective_initial(d) != Some(Initial::Exact),
            Causality::CalculatedParameter => true,
            _ => false,
        })
        .map(|d| d.value_reference)
        .collect();
    if let Some(me) = me {
        for (state, derivative) in me.state_derivatives {
            let inputs_of = inputs
                .iter()
                .filter(|i| match (me.derivative_inputs)(derivative) {
                    Dependencies::AllInputs => true,
                    Dependencies::NoInputs => false,
                    Dependencies::Inputs(names) => names.contains(&i.name),
                    Dependencies::SameElementOf(name) => name == i.name,
                });
            let list = listed(
                inputs_of
                    .map(|i| i.value_reference.to_string())
                    .chain(me.states::<M>(derivative)),
            );
            if me.declared {
                let _ = writeln!(
                    x,
                    r#"    <ContinuousStateDerivative valueReference="{}" dependencies="{list}"/>"#,
                    vr_of(derivative)
                );
            } else {
                let _ = writeln!(
                    x,
                    r#"    <ContinuousStateDerivative valueReference="{}"/>"#,
                    vr_of(derivative)
                );
            }
            initial_unknowns.insert(find::<M>(state).value_reference);
            initial_unknowns.insert(find::<M>(derivative).value_reference);
        }
    }
    // In declaration order, as the standard asks of every list.
    for d in declarations {
        if initial_unknowns.contains(&d.value_reference) {
            let _ = writeln!(
                x,
                r#"    <InitialUnknown valueReference="{}"/>"#,
                d.value_reference
            );
        }
    }
    if let Some(me) = me {
        for name in me.event_indicators {
            let _ = writeln!(
                x,
                r#"    <EventIndicator valueReference="{}"/>"#,
                vr_of(name)
            );
        }
    }
    x.push_str("  </ModelStructure>\n");
}
