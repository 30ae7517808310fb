//! A system of connected FMUs: instances with parameter values, connections output -> input
//! by variable name, the communication step and the exchange ordering. Read from a TOML
//! scenario file ([`toml_format`]) or an SSP 1.0 or 2.0 `SystemStructure.ssd` ([`ssp`], with
//! what only 2.0 has in [`ssp2`]), or made of one FMU alone ([`single`]); written back to SSD
//! so the shipped `.ssd` is generated from the TOML and never drifts.
pub mod campaign_table;
pub mod event;
pub mod fields;
pub mod input_table;
pub mod single;
mod solver;
mod ssd_write;
pub mod ssp;
pub mod ssp2;
pub mod toml_format;

pub use event::Event;
pub use input_table::InputTable;
pub use solver::{JacobianSource, SolverSettings};

use std::path::PathBuf;

/// How the master exchanges values at a communication point. See [`crate::master`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Ordering {
    /// Instances visited in order; each one's inputs are set from the freshest outputs of its
    /// sources, then its outputs are read, so a direct-feedthrough FMU (a sampled controller)
    /// acts on the state of the same communication point. The default.
    #[default]
    GaussSeidel,
    /// All inputs set from the outputs read after the previous step, all instances stepped,
    /// all outputs read: every connection has one step of delay (fmpy's `simulate_ssp`).
    Jacobi,
}

/// A start/parameter value as written in a scenario; typed against the model description
/// when the system is resolved.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum ParamValue {
    Real(f64),
    Integer(i64),
    Boolean(bool),
    String(String),
}

#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct InstanceDesc {
    /// Instance name, also the prefix of its columns in the results (`plant.r_nue[1]`).
    pub name: String,
    /// The `.fmu` file: absolute when it was found beside the scenario file, otherwise
    /// relative paths are resolved against the master's FMU directory.
    pub fmu: PathBuf,
    /// Parameter and start values, applied in this order before initialization.
    pub parameters: Vec<(String, ParamValue)>,
    /// The connectors an SSD declares for the component (`None` when the format has none,
    /// as TOML): connections must use them, and they must match the FMU's variables.
    pub connectors: Option<Vec<DeclaredConnector>>,
    /// Run the FMU through Model Exchange with this solver; `None`: Co-Simulation.
    pub model_exchange: Option<SolverSettings>,
    /// Whether the scenario named the interface. When it did not, an FMU that declares Model
    /// Exchange only runs through it with the default solver, as fmpy and fmusim choose.
    #[serde(default)]
    pub interface_named: bool,
}

/// A connector as an SSD declares it.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct DeclaredConnector {
    pub name: String,
    /// SSP kind: `input`, `output`, `parameter`, `calculatedParameter`, `inout`.
    pub kind: String,
    /// `Real`, `Integer`, `Boolean`, `String`, `Enumeration` or `Binary`, when given; in SSP
    /// 2.0 also the FMI 3.0 types (`Float64`, `Int32`, ...).
    pub type_name: Option<String>,
    /// SSP 2.0: the size of each dimension of an array connector; empty for a scalar.
    #[serde(default)]
    pub dimensions: Vec<u64>,
}

impl DeclaredConnector {
    /// The FMI causality an SSP connector kind stands for (`inout` stands for none).
    pub fn causality(&self) -> Option<model_description::Causality> {
        use model_description::Causality;
        match self.kind.as_str() {
            "input" => Some(Causality::Input),
            "output" => Some(Causality::Output),
            "parameter" => Some(Causality::Parameter),
            "calculatedParameter" => Some(Causality::CalculatedParameter),
            _ => None,
        }
    }
}

/// `from` and `to` are `instance.variable`; a variable may name a whole vector (`r_nue` for
/// `r_nue[1]`..`r_nue[n]`), expanded component by component when the system is resolved.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Connection {
    pub from: String,
    pub to: String,
}

#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SystemDescription {
    pub name: String,
    pub start_time: f64,
    pub stop_time: f64,
    pub step_size: f64,
    pub ordering: Ordering,
    /// In exchange order (see [`Ordering::GaussSeidel`]).
    pub instances: Vec<InstanceDesc>,
    pub connections: Vec<Connection>,
    /// Columns to record (`instance.variable`, vectors allowed); `None` = every output.
    pub record: Option<Vec<String>>,
    /// Timeouts and memory of a supervised run, as the scenario sets them.
    #[serde(default)]
    pub limits: crate::limits::Limits,
    /// Variables (`instance.variable`, vectors allowed) whose NaN or infinite values, returned
    /// with status OK, are only warned about (once per variable and run) instead of ending
    /// the run: for FMUs that mean "no value" by NaN. Defaulted so that a description from
    /// before the option reads.
    #[serde(default)]
    pub allow_non_finite: Vec<String>,
    /// Signals that drive inputs of the instances (`harness run --input`), instead of
    /// connections. Defaulted so that a description from before the option reads.
    #[serde(default)]
    pub inputs: Option<InputTable>,
    /// Values set during the run (`[[event]]`), in the order they are applied when several
    /// fall on one communication point. Defaulted so that a description from before the
    /// option reads.
    #[serde(default)]
    pub events: Vec<Event>,
    /// Keeps an unpacked `.ssp` on disk as long as the description refers to its FMUs. Not
    /// sent to a worker process: the parent keeps the directory while the worker reads it.
    #[serde(skip)]
    pub package: Option<PackageDir>,
}

/// The temporary directory an `.ssp` archive was unpacked into; removed when the last
/// description (or clone) that refers to it is dropped. Equal to every other: where a
/// package was unpacked is not part of what a system is.
#[derive(Debug, Clone)]
pub struct PackageDir(pub std::sync::Arc<tempfile::TempDir>);

impl PartialEq for PackageDir {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

/// A malformed system description; every variant names what is wrong and where.
#[derive(Debug, thiserror::Error)]
pub enum SystemError {
    #[error("cannot read {path}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{path}: {message}")]
    Syntax { path: PathBuf, message: String },
    #[error("system '{system}': {message}")]
    Invalid { system: String, message: String },
}

impl SystemDescription {
    /// What the step size does to the last step when the run is not a whole number of steps
    /// (172 s in steps of 0.03 s ends with a step of 0.01 s), for a warning.
    pub fn partial_last_step(&self) -> Option<String> {
        let span = self.stop_time - self.start_time;
        let steps = span / self.step_size;
        if !steps.is_finite() || (steps - steps.round()).abs() <= 1e-9 * steps.max(1.0) {
            return None;
        }
        let last = span - steps.floor() * self.step_size;
        Some(format!(
            "{span} s is not a whole number of steps of {} s ({steps:.3}): the last step is \
             {last:.6} s",
            self.step_size
        ))
    }

    /// Checks that do not need the FMUs: times, names, connection syntax. Every problem is
    /// reported, in one error.
    pub fn validate(&self) -> Result<(), SystemError> {
        let mut problems = Vec::new();
        if !(self.step_size.is_finite() && self.step_size > 0.0) {
            problems.push(format!(
                "step_size must be a positive number, got {}",
                self.step_size
            ));
        }
        if !(self.start_time.is_finite()
            && self.stop_time.is_finite()
            && self.stop_time > self.start_time)
        {
            problems.push(format!(
                "stop_time ({}) must be after start_time ({})",
                self.stop_time, self.start_time
            ));
        }
        if self.instances.is_empty() {
            problems.push("no instances".into());
        }
        for (i, instance) in self.instances.iter().enumerate() {
            if instance.name.is_empty() || instance.name.contains('.') {
                problems.push(format!(
                    "instance name '{}' must be non-empty and contain no '.'",
                    instance.name
                ));
            }
            if self.instances[..i].iter().any(|o| o.name == instance.name) {
                problems.push(format!("instance '{}' declared twice", instance.name));
            }
        }
        for connection in &self.connections {
            for end in [&connection.from, &connection.to] {
                let Some((instance, _)) = split_path(end) else {
                    problems.push(format!(
                        "connection end '{end}' is not of the form instance.variable"
                    ));
                    continue;
                };
                if !self.instances.iter().any(|i| i.name == instance) {
                    let names = self.instances.iter().map(|i| i.name.as_str());
                    problems.push(format!(
                        "connection end '{end}' names unknown instance '{instance}'{}",
                        crate::suggest::hint(instance, names)
                    ));
                }
            }
        }
        if problems.is_empty() {
            Ok(())
        } else {
            Err(SystemError::Invalid {
                system: self.name.clone(),
                message: problems.join("\n  "),
            })
        }
    }

    pub fn instance(&self, name: &str) -> Option<&InstanceDesc> {
        self.instances.iter().find(|i| i.name == name)
    }

    pub fn instance_mut(&mut self, name: &str) -> Option<&mut InstanceDesc> {
        self.instances.iter_mut().find(|i| i.name == name)
    }

    /// Sets (or overrides) a parameter value of an instance.
    pub fn set_parameter(&mut self, instance: &str, variable: &str, value: ParamValue) -> bool {
        let Some(desc) = self.instance_mut(instance) else {
            return false;
        };
        match desc
            .parameters
            .iter_mut()
            .find(|(name, _)| name == variable)
        {
            Some(slot) => slot.1 = value,
            None => desc.parameters.push((variable.to_owned(), value)),
        }
        true
    }
}

/// Splits `instance.variable` at the first dot (variable names may contain dots themselves).
pub fn split_path(path: &str) -> Option<(&str, &str)> {
    let (instance, variable) = path.split_once('.')?;
    (!instance.is_empty() && !variable.is_empty()).then_some((instance, variable))
}

#[cfg(test)]
mod partial_step_tests {
    #[test]
    fn a_run_that_is_not_a_whole_number_of_steps_is_noted_with_its_last_step() {
        let mut system = super::SystemDescription {
            name: "descent".into(),
            start_time: 0.0,
            stop_time: 172.0,
            step_size: 0.01,
            ordering: super::Ordering::GaussSeidel,
            instances: vec![],
            connections: vec![],
            record: None,
            limits: Default::default(),
            allow_non_finite: Vec::new(),
            inputs: None,
            events: Vec::new(),
            package: None,
        };
        assert_eq!(system.partial_last_step(), None);
        system.step_size = 0.03;
        let note = system.partial_last_step().unwrap();
        assert!(note.contains("the last step is 0.010000 s"), "{note}");
    }
}
