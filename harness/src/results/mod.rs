//! Results on disk: CSV for reading by eye and by any tool, Arrow IPC (the file format, also
//! known as Feather v2) for large runs. Both hold the same table, a `time` column and one
//! column per recorded `instance.variable`, and both read back bit-exactly.
mod arrow;
mod csv;

pub use self::arrow::{read_arrow, write_arrow};
pub use self::csv::{read_csv, write_csv, write_csv_to};

use crate::master::Trajectory;
use std::path::Path;

/// A result file format.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Format {
    /// Text, one row per communication point, shortest round-trip numbers.
    Csv,
    /// Arrow IPC file ("Feather v2"): binary float64 columns, read by pandas
    /// (`read_feather`), polars (`read_ipc`) and pyarrow.
    Arrow,
}

impl Format {
    /// By the file's extension: `.arrow`, `.feather` and `.ipc` are Arrow, anything else CSV.
    pub fn of_path(path: &Path) -> Self {
        match path.extension().and_then(|e| e.to_str()) {
            Some(ext)
                if ["arrow", "feather", "ipc"].contains(&ext.to_ascii_lowercase().as_str()) =>
            {
                Format::Arrow
            }
            _ => Format::Csv,
        }
    }

    /// The file extension this format is written with.
    pub fn extension(self) -> &'static str {
        match self {
            Format::Csv => "csv",
            Format::Arrow => "arrow",
        }
    }
}

/// Writes `trajectory` to `path` in `format`; creates parent directories.
pub fn write(path: &Path, trajectory: &Trajectory, format: Format) -> anyhow::Result<()> {
    match format {
        Format::Csv => write_csv(path, trajectory)?,
        Format::Arrow => write_arrow(path, trajectory)?,
    }
    Ok(())
}

/// Reads a file written by [`write`], its format by its extension.
pub fn read(path: &Path) -> anyhow::Result<Trajectory> {
    match Format::of_path(path) {
        Format::Csv => read_csv(path),
        Format::Arrow => read_arrow(path),
    }
}
