//! A saved run: everything a run needs to go on from one communication point in another
//! process and end with the rows the uninterrupted run would have recorded, bit for bit;
//! its file (format in docs/saved-runs.md) and the checks of a continuation that need no
//! loaded FMU. How a [`super::Simulation`] saves and continues one: `checkpoint.rs`.
//!
//! What goes on from the point is the FMUs' states (serialized by each FMU through the
//! importer) and what the master holds between two points: the clock (step counter and, for
//! fmpy's convention, the running sum), every exchange buffer (the last values read from each
//! instance and the inputs last set on it) and which outputs were read since the last step.
//! Saved at the top of a communication point, before its exchange, so the continued run
//! starts with that point's exchange and records its row first.
//!
//! The header names the system, each instance's model, instantiation token (FMI 2.0 GUID)
//! and FMI version, the run's grid (start, step, ordering, conventions) and the scenario
//! events applied before the point (the FMU states hold their values), so that a file
//! continued with other FMUs, another system or other events before the point is refused,
//! naming what differs. Model Exchange instances are refused: their solver's state (step
//! size, history, the event search) is not saved.
use super::conventions::{Clock, Conventions};
use crate::system::{Ordering, SystemDescription};
use fmi_import::FmiVersion;
use model_description::ModelDescription;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The file's first bytes.
pub const MAGIC: &[u8; 16] = b"cosim saved run\n";
/// The format this build writes and reads; a file of another is refused with both numbers.
pub const FORMAT_VERSION: u32 = 2;
/// magic, format version (u32), payload length (u64), payload CRC-32 (u32).
const PREAMBLE: usize = MAGIC.len() + 4 + 8 + 4;

/// What to do about saved runs in the next run: continue one, save one, or both.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct Checkpoints {
    /// Continue from this saved run instead of starting at the start time.
    pub resume: Option<SavedRun>,
    /// Save the run here.
    pub save: Option<SaveRequest>,
}

/// Where and when to save a run.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct SaveRequest {
    pub path: PathBuf,
    /// The communication point to save at; `None`: at the stop time, after the last step.
    pub at: Option<f64>,
}

/// One instance as saved: who it is, and its state.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SavedInstance {
    pub name: String,
    pub model_name: String,
    /// FMI 2.0 `guid`, FMI 3.0 `instantiationToken`.
    pub token: String,
    /// "2.0" or "3.0".
    pub fmi_version: String,
    /// The FMU state as the importer serialized it.
    pub fmu_state: Vec<u8>,
    pub inputs: SavedIo,
    pub outputs: SavedIo,
    pub outputs_read: bool,
}

/// One side of an instance's exchange: value references (which fix the buffer's layout)
/// and values, per exchange type.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct SavedIo {
    pub real_vrs: Vec<u32>,
    pub real: Vec<f64>,
    pub integer_vrs: Vec<u32>,
    pub integer: Vec<i32>,
    pub boolean_vrs: Vec<u32>,
    pub boolean: Vec<i32>,
}

/// A run saved at one communication point.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SavedRun {
    pub system: String,
    pub start_time: f64,
    pub step_size: f64,
    /// The stop time of the run that saved it (the continued run may have another).
    pub stop_time: f64,
    pub ordering: String,
    pub conventions: String,
    /// The communication point saved.
    pub time: f64,
    /// The clock's step counter and running sum at that point.
    pub step: u64,
    pub accumulated: f64,
    /// What the run exchanged and recorded, which fixes the master's buffers: the
    /// connections (`from -> to`), the inputs of the input table, the recorded columns.
    pub exchange: Vec<String>,
    pub columns: Vec<String>,
    /// The scenario events applied before `time`, whose values the FMU states hold
    /// ([`crate::system::Event::label`]); a continuation must have the same.
    pub events_before: Vec<String>,
    pub instances: Vec<SavedInstance>,
    /// What a caller judging the run over its whole length kept of the rows before the
    /// saved point (the harness: its requirements' columns, see
    /// `requirements/continued.rs`); the master writes none.
    pub rows_before: Option<SavedRows>,
}

/// Rows of some columns, as [`super::Trajectory`] holds them.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct SavedRows {
    pub names: Vec<String>,
    pub times: Vec<f64>,
    /// Row-major.
    pub values: Vec<f64>,
}

/// Why a saved run could not be read or does not fit the run given.
#[derive(Debug, thiserror::Error)]
pub enum SavedError {
    #[error("cannot read the saved run {}: {reason}", path.display())]
    Read { path: PathBuf, reason: String },
    #[error("{} is not a saved run of this harness: {reason}", path.display())]
    Corrupt { path: PathBuf, reason: String },
}

/// What [`SavedRun::events_before`] holds for `system` saved at `time`.
pub(super) fn events_before(system: &SystemDescription, time: f64) -> Vec<String> {
    crate::system::event::applied_before(system, time)
        .into_iter()
        .map(crate::system::Event::label)
        .collect()
}

pub(super) fn version_text(version: FmiVersion) -> &'static str {
    match version {
        FmiVersion::Fmi2 => "2.0",
        FmiVersion::Fmi3 => "3.0",
    }
}

pub(super) fn ordering_text(ordering: Ordering) -> &'static str {
    match ordering {
        Ordering::GaussSeidel => "gauss-seidel",
        Ordering::Jacobi => "jacobi",
    }
}

impl SavedRun {
    /// The file's bytes: preamble, then the postcard payload.
    pub fn to_bytes(&self) -> Vec<u8> {
        let payload = postcard::to_stdvec(self).expect("a saved run always serializes");
        let mut bytes = Vec::with_capacity(PREAMBLE + payload.len());
        bytes.extend_from_slice(MAGIC);
        bytes.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
        bytes.extend_from_slice(&(payload.len() as u64).to_le_bytes());
        bytes.extend_from_slice(&crc32fast::hash(&payload).to_le_bytes());
        bytes.extend_from_slice(&payload);
        bytes
    }

    /// Parses `bytes` read from `path` (named in the errors).
    pub fn from_bytes(path: &Path, bytes: &[u8]) -> Result<Self, SavedError> {
        let corrupt = |reason: String| SavedError::Corrupt {
            path: path.to_owned(),
            reason,
        };
        if bytes.len() < PREAMBLE || !bytes.starts_with(MAGIC) {
            return Err(corrupt(format!(
                "it does not start with {:?} (written by `harness run --save-state`)",
                std::str::from_utf8(MAGIC).unwrap_or_default()
            )));
        }
        let field = |at: usize, len: usize| &bytes[MAGIC.len() + at..MAGIC.len() + at + len];
        let version = u32::from_le_bytes(field(0, 4).try_into().expect("4 bytes"));
        if version != FORMAT_VERSION {
            return Err(corrupt(format!(
                "format version {version}; this harness reads version {FORMAT_VERSION}"
            )));
        }
        let length = u64::from_le_bytes(field(4, 8).try_into().expect("8 bytes"));
        let crc = u32::from_le_bytes(field(12, 4).try_into().expect("4 bytes"));
        let payload = &bytes[PREAMBLE..];
        if payload.len() as u64 != length {
            return Err(corrupt(format!(
                "truncated or extended: {} bytes of state where its header says {length}",
                payload.len()
            )));
        }
        if crc32fast::hash(payload) != crc {
            return Err(corrupt(
                "its checksum does not match its contents (the file was changed or damaged)"
                    .to_owned(),
            ));
        }
        postcard::from_bytes(payload)
            .map_err(|e| corrupt(format!("its contents do not decode: {e}")))
    }

    pub fn read(path: &Path) -> Result<Self, SavedError> {
        let bytes = std::fs::read(path).map_err(|e| SavedError::Read {
            path: path.to_owned(),
            reason: e.to_string(),
        })?;
        Self::from_bytes(path, &bytes)
    }

    /// Writes the file whole or not at all (a temporary file renamed).
    pub fn write(&self, path: &Path) -> std::io::Result<()> {
        let mut temporary = path.as_os_str().to_owned();
        temporary.push(".partial");
        let temporary = PathBuf::from(temporary);
        std::fs::write(&temporary, self.to_bytes())?;
        std::fs::rename(&temporary, path)
    }

    /// `Ok` when this saved run can continue `system` as run with `conventions`, recording
    /// `columns`, with these FMUs (`describe(i)`: instance i's FMI version and
    /// description); else what differs.
    pub fn fits(
        &self,
        system: &SystemDescription,
        conventions: &Conventions,
        columns: &[String],
        describe: &dyn Fn(usize) -> (FmiVersion, ModelDescription),
    ) -> Result<(), String> {
        if self.system != system.name {
            return Err(format!(
                "it was saved from system '{}', not '{}'",
                self.system, system.name
            ));
        }
        let names: Vec<&str> = system.instances.iter().map(|i| i.name.as_str()).collect();
        let saved: Vec<&str> = self.instances.iter().map(|i| i.name.as_str()).collect();
        if names != saved {
            return Err(format!(
                "it holds instances {saved:?}; this system has {names:?}"
            ));
        }
        for (i, instance) in self.instances.iter().enumerate() {
            let (version, description) = describe(i);
            let here = (
                description.model_name.as_str(),
                description.guid.as_str(),
                version_text(version),
            );
            let there = (
                instance.model_name.as_str(),
                instance.token.as_str(),
                instance.fmi_version.as_str(),
            );
            if here != there {
                return Err(format!(
                    "instance '{}' was saved from model '{}' (FMI {}, instantiation token {}); \
                     this run's FMU is model '{}' (FMI {}, instantiation token {})",
                    instance.name, there.0, there.2, there.1, here.0, here.2, here.1
                ));
            }
        }
        let grid = |start: f64, step: f64, ordering: &str, conventions: &str| {
            format!(
                "start time {start} s, step {step} s, {ordering} ordering, conventions \
                 {conventions}"
            )
        };
        let saved_grid = grid(
            self.start_time,
            self.step_size,
            &self.ordering,
            &self.conventions,
        );
        let this_grid = grid(
            system.start_time,
            system.step_size,
            ordering_text(system.ordering),
            &format!("{conventions:?}"),
        );
        if saved_grid != this_grid {
            return Err(format!(
                "it was saved from a run with {saved_grid}; this run has {this_grid}"
            ));
        }
        let exchange = exchange_of(system);
        if self.exchange != exchange {
            return Err(format!(
                "it was saved from a run that exchanged {:?}; this run exchanges {:?} (continue \
                 with the same connections and --input)",
                self.exchange, exchange
            ));
        }
        let events_before = events_before(system, self.time);
        if self.events_before != events_before {
            let list = |events: &[String]| match events.is_empty() {
                true => "none".to_owned(),
                false => events.join(", "),
            };
            return Err(format!(
                "the events before t = {} s were {} in the run saved; this run's are {}: the \
                 FMU states hold what those set, so continue with the same events before that \
                 point (those due at or after it may differ)",
                self.time,
                list(&self.events_before),
                list(&events_before)
            ));
        }
        if self.columns != columns {
            return Err(format!(
                "it was saved from a run that recorded {:?}; this run records {:?} (continue \
                 with the same --record)",
                self.columns, columns
            ));
        }
        if conventions.stop_time_declared && system.stop_time > self.stop_time {
            return Err(format!(
                "its FMUs were told the stop time {} s, and this run goes on to {} s: \
                 continue to {} s at most, or save from a run with a later stop time",
                self.stop_time, system.stop_time, self.stop_time
            ));
        }
        if self.time > system.stop_time {
            return Err(format!(
                "it was saved at t = {} s, after this run's stop time {} s",
                self.time, system.stop_time
            ));
        }
        Ok(())
    }
}

/// What a run of `system` exchanges besides its FMUs' outputs, as [`SavedRun::exchange`].
pub(super) fn exchange_of(system: &SystemDescription) -> Vec<String> {
    let connections = system
        .connections
        .iter()
        .map(|c| format!("{} -> {}", c.from, c.to));
    let table = system.inputs.iter().flat_map(|table| {
        table
            .names
            .iter()
            .map(|name| format!("input table -> {name}"))
    });
    connections.chain(table).collect()
}

/// Why the FMUs of `system` cannot be saved (`save`) or continued: an instance run as Model
/// Exchange, or an FMU that does not declare it can serialize its state. `describe` as for
/// [`SavedRun::fits`].
pub fn refusal(
    system: &SystemDescription,
    describe: &dyn Fn(usize) -> (FmiVersion, ModelDescription),
) -> Option<String> {
    for (i, instance) in system.instances.iter().enumerate() {
        if instance.model_exchange.is_some() {
            return Some(format!(
                "instance '{}' runs as Model Exchange, whose solver state (step size, history, \
                 event search) is not saved; run it as co-simulation (--interface {}=co-simulation)",
                instance.name, instance.name
            ));
        }
        let (version, description) = describe(i);
        if let Some(reason) = fmi_import::fmu_state_refusal(
            &description,
            version,
            fmi_import::Interface::CoSimulation,
            true,
        ) {
            return Some(format!("instance '{}': {reason}", instance.name));
        }
    }
    None
}

/// What can be checked of `checkpoints` with the FMUs' descriptions alone (where the FMUs
/// are not loaded, e.g. by the parent of a supervised worker): every instance can be saved
/// and continued, and a saved run fits `system` and its FMUs.
pub fn check(
    system: &SystemDescription,
    conventions: &Conventions,
    columns: &[String],
    checkpoints: &Checkpoints,
    describe: &dyn Fn(usize) -> (FmiVersion, ModelDescription),
) -> Result<(), String> {
    if checkpoints.resume.is_none() && checkpoints.save.is_none() {
        return Ok(());
    }
    if let Some(reason) = refusal(system, describe) {
        return Err(reason);
    }
    let mut clock = Clock::new(
        conventions.time_grid,
        system.start_time,
        system.stop_time,
        system.step_size,
    );
    if let Some(saved) = &checkpoints.resume {
        saved.fits(system, conventions, columns, describe)?;
        clock.resume((saved.step, saved.accumulated));
    }
    if let Some(request) = &checkpoints.save {
        save_point(&clock, request.at)?;
    }
    Ok(())
}

/// The step counter at which to save, for `at` (`None`: the end): the first point of the
/// clock at `at` (within 1e-9 relative); an error when `at` is none of its points.
pub(super) fn save_point(clock: &Clock, at: Option<f64>) -> Result<u64, String> {
    let first = clock.position().0;
    let mut ahead = clock.clone();
    loop {
        let (k, _) = ahead.position();
        let time = match ahead.next_step() {
            Some((time, _)) => time,
            None => ahead.end_time(),
        };
        let ended = ahead.position().0 == k;
        let Some(at) = at else {
            if ended {
                return Ok(k);
            }
            continue;
        };
        if (time - at).abs() <= 1e-9 * at.abs().max(1.0) {
            return Ok(k);
        }
        if time > at && k == first {
            return Err(format!(
                "--save-at {at}: before the first communication point of this run, t = {time}"
            ));
        }
        if time > at {
            return Err(format!(
                "--save-at {at}: not a communication point of this run (start + k * step); \
                 the next one is t = {time}"
            ));
        }
        if ended {
            return Err(format!(
                "--save-at {at}: after this run's stop time, {time}"
            ));
        }
    }
}
