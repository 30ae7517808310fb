//! Runs that outlive their FMUs. A [`Runner`] holds a system either here (in process) or in
//! a supervised worker process: the same program started with [`WORKER_FLAG`], which owns the
//! FMUs while the parent orchestrates, records and judges. FMU code that crashes, calls
//! `exit` or `abort`, exhausts memory or never returns ends the worker, not the parent,
//! which tells how, in which call of which instance and at what time (the worker's black
//! box, `fmi_import::blackbox`), after handing on every row recorded before.
//!
//! A program becomes able to supervise by calling [`serve_if_worker`] first in `main` (a
//! worker never returns from it) and [`set_default`] with the program's own path.
mod parent;
mod protocol;
mod shared;
mod worker;

pub use crate::abnormal::{signal_name, Abnormal, How};
pub use crate::limits::Limits;
pub use parent::Supervised;

use crate::master::{
    Checkpoints, Conventions, EventCounts, MasterError, Recorder, RunEnd, Simulation,
};
use crate::system::{ParamValue, SystemDescription};
use fmi_import::FmiVersion;
use model_description::ModelDescription;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// The argument that makes a program a worker: `<program> --cosim-worker <dir>`.
pub const WORKER_FLAG: &str = "--cosim-worker";
const BLACK_BOX: &str = "black-box";
const RING: &str = "rows";

/// Where runs go: into a worker of `program` under `limits`, or this process.
#[derive(Debug, Clone, PartialEq)]
pub enum Execution {
    InProcess,
    Supervised { program: PathBuf, limits: Limits },
}

static DEFAULT: Mutex<Execution> = Mutex::new(Execution::InProcess);

/// How [`Runner::new`] runs from now on in this process (in process until set).
pub fn set_default(execution: Execution) {
    *DEFAULT.lock().unwrap_or_else(|e| e.into_inner()) = execution;
}

pub fn default_execution() -> Execution {
    DEFAULT.lock().unwrap_or_else(|e| e.into_inner()).clone()
}

/// When this process was started as a worker (`<program> --cosim-worker <dir>`), serves its
/// parent and exits; otherwise returns at once.
pub fn serve_if_worker() {
    let mut args = std::env::args_os().skip(1);
    if args.next().is_some_and(|flag| flag == WORKER_FLAG) {
        let Some(dir) = args.next() else {
            eprintln!("{WORKER_FLAG} needs the worker's directory");
            std::process::exit(2);
        };
        std::process::exit(worker::serve(Path::new(&dir)));
    }
}

/// A system ready to run, here or in a supervised worker, behind one API: what
/// [`Simulation`] offers a caller that flies and records.
pub enum Runner {
    InProcess(Box<Simulation>),
    Supervised(Box<Supervised>),
}

impl Runner {
    /// Loads and resolves `system` as [`Simulation::new`] does, where the process's
    /// [`default_execution`] says, with the system's own limits under the default's.
    pub fn new(system: SystemDescription, fmu_dir: &Path) -> Result<Self, MasterError> {
        Self::with(system, fmu_dir, default_execution())
    }

    pub fn with(
        mut system: SystemDescription,
        fmu_dir: &Path,
        execution: Execution,
    ) -> Result<Self, MasterError> {
        // An FMU found in a further FMU directory goes to a worker as its absolute path: a
        // worker knows only `fmu_dir`.
        for instance in &mut system.instances {
            if !instance.fmu.is_absolute() && !fmu_dir.join(&instance.fmu).exists() {
                let found = crate::master::fmu_path(fmu_dir, &instance.fmu);
                if found.exists() {
                    instance.fmu = std::path::absolute(&found).unwrap_or(found);
                }
            }
        }
        match execution {
            Execution::InProcess => Ok(Runner::InProcess(Box::new(Simulation::new(
                system, fmu_dir,
            )?))),
            Execution::Supervised { program, limits } => {
                let limits = limits.or(system.limits);
                Ok(Runner::Supervised(Box::new(Supervised::new(
                    system, fmu_dir, program, limits,
                )?)))
            }
        }
    }

    pub fn is_supervised(&self) -> bool {
        matches!(self, Runner::Supervised(_))
    }

    pub fn system(&self) -> &SystemDescription {
        match self {
            Runner::InProcess(s) => s.system(),
            Runner::Supervised(s) => s.system(),
        }
    }

    /// Each instance's FMI version and model description (for FMI 3.0 its scalar view).
    pub fn description(&self, instance: usize) -> (FmiVersion, &ModelDescription) {
        match self {
            Runner::InProcess(s) => {
                let fmu = &s.fmus()[instance];
                (fmu.fmi_version(), fmu.model_description())
            }
            Runner::Supervised(s) => {
                let (version, description) = &s.descriptions()[instance];
                (*version, description)
            }
        }
    }

    pub fn column_names(&self) -> &[String] {
        match self {
            Runner::InProcess(s) => s.column_names(),
            Runner::Supervised(s) => s.column_names(),
        }
    }

    pub fn column_units(&self) -> &[String] {
        match self {
            Runner::InProcess(s) => s.column_units(),
            Runner::Supervised(s) => s.column_units(),
        }
    }

    /// The type of each recorded column (see [`crate::results::ColumnType`]).
    pub fn column_types(&self) -> Vec<crate::results::ColumnType> {
        match self {
            Runner::InProcess(s) => s.column_types(),
            Runner::Supervised(s) => s.column_types(),
        }
    }

    pub fn final_column_names(&self) -> &[String] {
        match self {
            Runner::InProcess(s) => s.final_column_names(),
            Runner::Supervised(s) => s.final_column_names(),
        }
    }

    pub fn final_values(&self) -> &[f64] {
        match self {
            Runner::InProcess(s) => s.final_values(),
            Runner::Supervised(s) => s.final_values(),
        }
    }

    pub fn set_parameter(
        &mut self,
        instance: &str,
        variable: &str,
        value: ParamValue,
    ) -> Result<(), MasterError> {
        match self {
            Runner::InProcess(s) => s.set_parameter(instance, variable, value),
            Runner::Supervised(s) => s.set_parameter(instance, variable, value),
        }
    }

    /// Changes a scenario event for the following runs (a campaign's drawn fault time).
    pub fn change_event(
        &mut self,
        name: &str,
        change: &crate::system::event::Change,
    ) -> Result<(), MasterError> {
        match self {
            Runner::InProcess(s) => s.change_event(name, change),
            Runner::Supervised(s) => s.change_event(name, change),
        }
    }

    pub fn set_final_columns(&mut self, names: &[String]) -> Result<(), MasterError> {
        match self {
            Runner::InProcess(s) => s.set_final_columns(names),
            Runner::Supervised(s) => s.set_final_columns(names),
        }
    }

    pub fn set_conventions(&mut self, conventions: Conventions) {
        match self {
            Runner::InProcess(s) => s.set_conventions(conventions),
            Runner::Supervised(s) => s.set_conventions(conventions),
        }
    }

    /// Continue a saved run, or save this one, in the next runs (`master/saved.rs`);
    /// refused now when an FMU cannot or the saved run does not fit.
    pub fn set_checkpoints(&mut self, checkpoints: Checkpoints) -> Result<(), MasterError> {
        match self {
            Runner::InProcess(s) => s.set_checkpoints(checkpoints),
            Runner::Supervised(s) => s.set_checkpoints(checkpoints),
        }
    }

    /// The communication point the last run saved at, if it did.
    pub fn saved_at(&self) -> Option<f64> {
        match self {
            Runner::InProcess(s) => s.saved_at(),
            Runner::Supervised(s) => s.saved_at(),
        }
    }

    pub fn run(&mut self, recorder: &mut dyn Recorder) -> Result<RunEnd, MasterError> {
        match self {
            Runner::InProcess(s) => s.run(recorder),
            Runner::Supervised(s) => s.run(recorder),
        }
    }

    /// Each Model Exchange instance's events in the last run, in instance order.
    pub fn model_exchange_events(&self) -> Vec<(String, EventCounts)> {
        match self {
            Runner::InProcess(s) => s
                .model_exchange_events()
                .into_iter()
                .map(|(name, events)| (name.to_owned(), events))
                .collect(),
            Runner::Supervised(s) => s.model_exchange_events().to_vec(),
        }
    }

    /// What the worker wrote to stderr since the last call (empty in process, where it went
    /// straight to this process's stderr).
    pub fn take_stderr(&self) -> String {
        match self {
            Runner::InProcess(_) => String::new(),
            Runner::Supervised(s) => s.take_stderr(),
        }
    }
}
