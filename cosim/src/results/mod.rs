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

    /// The format a result file `path` is written in: `requested` (`--format`) or the one its
    /// extension names. Refused, with the reason: an extension that names neither format
    /// (`.parquet`), or one that names the other (`--format arrow -o x.csv`), since either
    /// would write a file whose name says something else than its content.
    pub fn for_output(path: &Path, requested: Option<Format>) -> Result<Format, String> {
        let named = match path.extension().and_then(|e| e.to_str()) {
            None => None,
            Some(ext) if ext.eq_ignore_ascii_case("csv") => Some(Format::Csv),
            Some(_) if Format::of_path(path) == Format::Arrow => Some(Format::Arrow),
            // A name that says nothing about its content is the user's to choose, with
            // --format saying what goes in.
            Some(_) if requested.is_some() => None,
            Some(ext) => {
                return Err(format!(
                    "{}: .{ext} is not a result format this harness writes (CSV: .csv; Arrow \
                     IPC: .arrow, .feather, .ipc)",
                    path.display()
                ))
            }
        };
        match (named, requested) {
            (Some(named), Some(requested)) if named != requested => Err(format!(
                "{}: --format {} asks for {requested:?}, but the name says {named:?} (.{})",
                path.display(),
                requested.extension(),
                named.extension()
            )),
            (named, requested) => Ok(requested.or(named).unwrap_or(Format::Csv)),
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

#[cfg(test)]
mod format_tests {
    use super::Format;
    use std::path::Path;

    #[test]
    fn an_output_name_and_format_must_agree() {
        let f = |p: &str, r| Format::for_output(Path::new(p), r);
        assert_eq!(f("run.csv", None), Ok(Format::Csv));
        assert_eq!(f("run", None), Ok(Format::Csv));
        assert_eq!(f("run", Some(Format::Arrow)), Ok(Format::Arrow));
        assert_eq!(f("run.feather", None), Ok(Format::Arrow));
        assert_eq!(f("run.CSV", Some(Format::Csv)), Ok(Format::Csv));
        assert!(f("run.parquet", None).unwrap_err().contains(".parquet"));
        assert_eq!(f("run.bin", Some(Format::Arrow)), Ok(Format::Arrow));
        assert!(f("run.csv", Some(Format::Arrow))
            .unwrap_err()
            .contains("--format arrow"));
    }
}
