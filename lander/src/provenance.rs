//! What a paper-style run keeps of itself for its report: the scenario flown, its timing and
//! parameters, and the FMUs it loaded (`provenance.toml`).
use anyhow::Context;
use std::path::{Path, PathBuf};

/// What a `harness paper` directory keeps of the run for its report (and for `harness report
/// DIR` later): the scenario, its parameters and the FMUs flown.
pub const PROVENANCE_FILE: &str = "provenance.toml";

/// The scenario a paper-style run flew and the FMUs it loaded.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Provenance {
    /// The scenario's name (its `name`).
    pub scenario: String,
    pub start_time_s: f64,
    pub stop_time_s: f64,
    pub step_size_s: f64,
    /// How the master exchanges values (`gauss-seidel`, `jacobi`).
    pub ordering: String,
    /// The laws flown, each overriding `gnc.control_law`, in the order of the table.
    #[serde(default)]
    pub laws: Vec<String>,
    #[serde(default)]
    pub instance: Vec<InstanceProvenance>,
    /// The scenario's events (`[[event]]`), in its order.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub event: Vec<EventProvenance>,
}

/// A scenario event: what it sets, when it is due and the communication point it applies at.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct EventProvenance {
    pub name: String,
    pub time_s: f64,
    /// `instance.variable = value`.
    pub set: String,
    /// The communication point the master applies it at (`cosim::system::event`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub applied_at_s: Option<f64>,
}

impl EventProvenance {
    /// What became of the event in a flight that ended with `end`.
    pub fn outcome(&self, end: &cosim::master::RunEnd) -> String {
        cosim::master::event_outcome(&self.name, &self.set, self.time_s, self.applied_at_s, end)
    }
}

/// One FMU instance: what it is and the values the scenario gives it.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct InstanceProvenance {
    pub name: String,
    /// The `.fmu` as the scenario names it.
    pub fmu: String,
    pub model_name: String,
    pub guid: String,
    pub fmi_version: String,
    /// The model's own version (`version` in modelDescription.xml), when it gives one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub version: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub generation_tool: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub generation_date: Option<String>,
    /// The values the scenario sets, in its order.
    #[serde(default)]
    pub parameter: Vec<Parameter>,
}

/// A parameter or start value a scenario sets, as text.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Parameter {
    pub name: String,
    pub value: String,
}

impl Provenance {
    /// The scenario and FMUs of a loaded simulation (its parameters as they stand now).
    pub fn of(simulation: &cosim::supervise::Runner) -> Self {
        let system = simulation.system();
        let value = |v: &cosim::system::ParamValue| match v {
            cosim::system::ParamValue::Real(x) => format!("{x}"),
            cosim::system::ParamValue::Integer(i) => format!("{i}"),
            cosim::system::ParamValue::Boolean(b) => format!("{b}"),
            cosim::system::ParamValue::String(t) => format!("{t:?}"),
        };
        Self {
            scenario: system.name.clone(),
            start_time_s: system.start_time,
            stop_time_s: system.stop_time,
            step_size_s: system.step_size,
            ordering: match system.ordering {
                cosim::system::Ordering::GaussSeidel => "gauss-seidel".into(),
                cosim::system::Ordering::Jacobi => "jacobi".into(),
            },
            laws: Vec::new(),
            instance: system
                .instances
                .iter()
                .enumerate()
                .map(|(index, instance)| {
                    let (_, md) = simulation.description(index);
                    InstanceProvenance {
                        name: instance.name.clone(),
                        fmu: instance.fmu.display().to_string(),
                        model_name: md.model_name.clone(),
                        guid: md.guid.clone(),
                        fmi_version: md.fmi_version.clone(),
                        version: md.version.clone(),
                        generation_tool: md.generation_tool.clone(),
                        generation_date: md.generation_date_and_time.clone(),
                        parameter: instance
                            .parameters
                            .iter()
                            .map(|(n, v)| Parameter {
                                name: n.clone(),
                                value: value(v),
                            })
                            .collect(),
                    }
                })
                .collect(),
            event: system
                .events
                .iter()
                .map(|event| EventProvenance {
                    name: event.name.clone(),
                    time_s: event.time_s,
                    set: event.describe(),
                    applied_at_s: cosim::system::event::application_time(system, event.time_s),
                })
                .collect(),
        }
    }

    /// Writes `provenance.toml` into `dir`.
    pub fn write(&self, dir: &Path) -> anyhow::Result<PathBuf> {
        let path = dir.join(PROVENANCE_FILE);
        let text = format!(
            "# The scenario and FMUs `harness paper` flew (shown by report.html).\n{}",
            toml::to_string_pretty(self)?
        );
        std::fs::write(&path, text).with_context(|| format!("writing {}", path.display()))?;
        Ok(path)
    }

    pub fn read(path: &Path) -> anyhow::Result<Self> {
        let text =
            std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
        toml::from_str(&text).with_context(|| format!("parsing {}", path.display()))
    }
}
