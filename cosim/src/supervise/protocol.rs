//! What the parent and its worker say to each other over the worker's stdin and stdout:
//! length-prefixed postcard messages. Rows do not travel here but through the shared ring
//! (`shared.rs`); a message only says how far they go.
use crate::master::{Checkpoints, Conventions, EventCounts, MasterError, RunEnd};
use crate::system::event::Change;
use crate::system::{ParamValue, SystemDescription};
use serde::{Deserialize, Serialize};
use std::io::{Read, Write};
use std::path::PathBuf;

/// The largest message either side accepts: a system description or a list of names, never
/// near this; anything larger is a corrupt stream.
const MAX_MESSAGE: usize = 256 << 20;

#[derive(Debug, Serialize, Deserialize)]
pub(super) enum ToWorker {
    /// Load, resolve and instantiate; answered with `Ready` or `Failed`.
    Setup {
        system: Box<SystemDescription>,
        fmu_dir: PathBuf,
        conventions: Conventions,
        final_columns: Vec<String>,
    },
    /// [`crate::master::Simulation::set_final_columns`]; answered with `FinalSet` or `Failed`.
    SetFinal { names: Vec<String> },
    /// Set these parameters, then run; answered with `Rows` as the ring's halves fill, then
    /// `Done` or `Failed`.
    Run {
        parameters: Vec<(String, String, ParamValue)>,
        /// Scenario events changed, each by its name.
        events: Vec<(String, Change)>,
        conventions: Conventions,
        checkpoints: Box<Checkpoints>,
    },
    /// The parent has taken the rows before `upto`; with `stop`, it can keep no more and the
    /// run should end there.
    Ack { upto: u64, stop: Option<String> },
}

#[derive(Debug, Serialize, Deserialize)]
pub(super) enum FromWorker {
    Ready {
        column_names: Vec<String>,
        column_units: Vec<String>,
        column_types: Vec<crate::results::ColumnType>,
        final_names: Vec<String>,
        ring_capacity: u64,
    },
    FinalSet {
        names: Vec<String>,
    },
    Rows {
        upto: u64,
    },
    /// A text column's value from row `row` on (`Recorder::record_text`), sent before the
    /// `Rows` that hands that row on.
    Text {
        row: u64,
        column: u64,
        text: String,
    },
    Done {
        rows: u64,
        end: RunEnd,
        final_values: Vec<f64>,
        events: Vec<(String, EventCounts)>,
        /// The communication point the run was saved at, if it was.
        saved_at: Option<f64>,
    },
    Failed {
        rows: u64,
        error: WireError,
    },
}

/// A [`MasterError`] across the process boundary: a resolution error keeps its problems (a
/// caller tells which came from its command line), every other its message and causes.
#[derive(Debug, Serialize, Deserialize)]
pub(super) enum WireError {
    Resolve {
        system: String,
        problems: Vec<String>,
    },
    Other {
        message: String,
    },
}

impl From<&MasterError> for WireError {
    fn from(error: &MasterError) -> Self {
        match error {
            MasterError::Resolve { system, problems } => WireError::Resolve {
                system: system.clone(),
                problems: problems.clone(),
            },
            other => {
                let mut message = other.to_string();
                let mut source = std::error::Error::source(other);
                while let Some(cause) = source {
                    message.push_str(": ");
                    message.push_str(&cause.to_string());
                    source = cause.source();
                }
                WireError::Other { message }
            }
        }
    }
}

impl From<WireError> for MasterError {
    fn from(error: WireError) -> Self {
        match error {
            WireError::Resolve { system, problems } => MasterError::Resolve { system, problems },
            WireError::Other { message } => MasterError::Worker { message },
        }
    }
}

pub(super) fn send<T: Serialize>(out: &mut impl Write, message: &T) -> std::io::Result<()> {
    let bytes = postcard::to_stdvec(message)
        .map_err(|e| std::io::Error::new(std::io::ErrorKind::InvalidData, e))?;
    out.write_all(&(bytes.len() as u32).to_le_bytes())?;
    out.write_all(&bytes)?;
    out.flush()
}

/// One message; `Ok(None)` at a clean end of the stream.
pub(super) fn receive<T: for<'de> Deserialize<'de>>(
    input: &mut impl Read,
) -> std::io::Result<Option<T>> {
    let mut len = [0u8; 4];
    match input.read_exact(&mut len) {
        Ok(()) => {}
        Err(e) if e.kind() == std::io::ErrorKind::UnexpectedEof => return Ok(None),
        Err(e) => return Err(e),
    }
    let len = u32::from_le_bytes(len) as usize;
    if len > MAX_MESSAGE {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!("a message of {len} bytes"),
        ));
    }
    let mut bytes = vec![0u8; len];
    input.read_exact(&mut bytes)?;
    postcard::from_bytes(&bytes)
        .map(Some)
        .map_err(|e| std::io::Error::new(std::io::ErrorKind::InvalidData, e))
}
