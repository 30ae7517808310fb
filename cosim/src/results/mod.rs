//! Results on disk: CSV for reading by eye and by any tool, Arrow IPC (the file format, also
//! known as Feather v2) for large runs. Both hold the same table, a `time` column and one
//! column per recorded `instance.variable`, and both read back bit-exactly.
mod arrow;
mod columns;
mod csv;

pub use self::arrow::{
    read_arrow, read_arrow_typed, read_arrow_units, write_arrow, write_arrow_typed,
};
pub use self::columns::ColumnType;
pub use self::csv::{read_csv, read_csv_typed, write_csv, write_csv_to, write_csv_typed};

use crate::master::{Recorder, Trajectory};
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
    write_with_units(path, trajectory, &[], format)
}

/// As [`write`], with each column's unit in an Arrow file's schema (as
/// [`Stream::create_with_units`] writes them; a CSV takes them in [`write_units`]).
pub fn write_with_units(
    path: &Path,
    trajectory: &Trajectory,
    units: &[String],
    format: Format,
) -> anyhow::Result<()> {
    write_typed(path, trajectory, units, &[], format)
}

/// As [`write_with_units`], with each column's type (see [`ColumnType`]; Float64 where
/// absent), as [`Stream::create_typed`] writes them.
pub fn write_typed(
    path: &Path,
    trajectory: &Trajectory,
    units: &[String],
    types: &[ColumnType],
    format: Format,
) -> anyhow::Result<()> {
    match format {
        Format::Csv => write_csv_typed(path, trajectory, types)?,
        Format::Arrow => write_arrow_typed(path, trajectory, units, types)?,
    }
    Ok(())
}

/// A result file written while the run records it (a [`Recorder`]): each row goes to the
/// file as it comes (CSV), or each batch of 65,536 rows (Arrow), so memory
/// does not grow with the run. The finished file is the one [`write`] would write of the
/// whole trajectory, byte for byte.
///
/// [`Recorder::record`] cannot fail: the first write error is kept and reported by
/// [`Recorder::failure`], which stops the master's run at that row; [`Stream::finish`]
/// returns it too.
pub struct Stream {
    sink: Sink,
    rows: usize,
    error: Option<anyhow::Error>,
}

enum Sink {
    Csv(self::csv::CsvStream),
    Arrow(Box<self::arrow::ArrowStream>),
}

impl Stream {
    /// Creates `path` (and its parent directories) for a run recording `names` (after
    /// `time`), in `format`.
    pub fn create(path: &Path, names: &[String], format: Format) -> anyhow::Result<Self> {
        Self::create_with_units(path, names, &[], format)
    }

    /// As [`Stream::create`], with each column's unit (`units[j]` of `names[j]`; "" or
    /// absent for none) in the Arrow schema: field metadata `unit`, `s` for `time`. A CSV
    /// has nowhere to hold them that every reader skips; [`write_units`] writes them beside it.
    pub fn create_with_units(
        path: &Path,
        names: &[String],
        units: &[String],
        format: Format,
    ) -> anyhow::Result<Self> {
        Self::create_typed(path, names, units, &[], format)
    }

    /// As [`Stream::create_with_units`], with each column's type (`types[j]` of `names[j]`,
    /// Float64 where absent): integers written as integers in a CSV, typed columns in Arrow
    /// (see [`ColumnType`]).
    pub fn create_typed(
        path: &Path,
        names: &[String],
        units: &[String],
        types: &[ColumnType],
        format: Format,
    ) -> anyhow::Result<Self> {
        let sink = match format {
            Format::Csv => Sink::Csv(self::csv::CsvStream::create(path, names, types)?),
            Format::Arrow => Sink::Arrow(Box::new(self::arrow::ArrowStream::create(
                path, names, units, types,
            )?)),
        };
        Ok(Stream {
            sink,
            rows: 0,
            error: None,
        })
    }

    /// Values held in memory at most besides the row being written (one Arrow batch).
    pub fn buffered_values(format: Format, width: usize) -> usize {
        match format {
            Format::Csv => 0,
            Format::Arrow => arrow::BATCH_ROWS * (width + 1),
        }
    }

    /// Writes what is left and closes the file: the rows written, or the first error.
    pub fn finish(self) -> anyhow::Result<usize> {
        if let Some(error) = self.error {
            return Err(error);
        }
        match self.sink {
            Sink::Csv(csv) => csv.finish()?,
            Sink::Arrow(arrow) => arrow.finish()?,
        }
        Ok(self.rows)
    }
}

impl Recorder for Stream {
    fn record(&mut self, time: f64, values: &[f64]) {
        if self.error.is_some() {
            return;
        }
        let written = match &mut self.sink {
            Sink::Csv(csv) => csv.row(time, values).map_err(anyhow::Error::from),
            Sink::Arrow(arrow) => arrow.row(time, values),
        };
        match written {
            Ok(()) => self.rows += 1,
            Err(error) => self.error = Some(error.context(format!("row {}", self.rows + 1))),
        }
    }

    fn failure(&self) -> Option<String> {
        self.error.as_ref().map(|e| format!("{e:#}"))
    }

    fn record_text(&mut self, column: usize, text: &str) {
        match &mut self.sink {
            Sink::Csv(csv) => csv.text(column, text),
            Sink::Arrow(arrow) => arrow.text(column, text),
        }
    }
}

/// The units file beside a CSV result `path`: `run.csv` -> `run.units.csv`.
pub fn units_path(path: &Path) -> std::path::PathBuf {
    let stem = path.file_stem().unwrap_or_default().to_string_lossy();
    path.with_file_name(format!("{stem}.units.csv"))
}

/// Writes the unit of every column of a result file, `time` first, as a two-column CSV
/// (`column,unit`; the unit empty where the FMU declares none).
pub fn write_units(path: &Path, names: &[String], units: &[String]) -> std::io::Result<()> {
    let mut text = String::from("column,unit\ntime,s\n");
    for (j, name) in names.iter().enumerate() {
        let unit = units.get(j).map(String::as_str).unwrap_or_default();
        text.push_str(&format!(
            "{},{}\n",
            self::csv::quote(name),
            self::csv::quote(unit)
        ));
    }
    std::fs::write(path, text)
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

#[cfg(test)]
mod stream_tests {
    use super::{write, Format, Stream};
    use crate::master::{Recorder, Trajectory};

    /// Rows across more than one Arrow batch, awkward values, and no rows at all.
    fn trajectories() -> Vec<Trajectory> {
        let rows = super::arrow::BATCH_ROWS + 3;
        let specials = [5e-324, -0.0, f64::NAN, f64::INFINITY, -1.0 / 3.0, 1e300];
        vec![
            Trajectory {
                names: vec!["a.x[1]".into(), "b,\"y\"".into()],
                times: (0..rows).map(|k| k as f64 * 0.01).collect(),
                values: (0..2 * rows)
                    .map(|i| specials[i % specials.len()])
                    .collect(),
            },
            Trajectory {
                names: vec!["a.x".into()],
                ..Default::default()
            },
        ]
    }

    #[test]
    fn a_streamed_file_is_the_file_written_from_memory_byte_for_byte() {
        let dir = tempfile::tempdir().unwrap();
        for (t, trajectory) in trajectories().iter().enumerate() {
            for format in [Format::Csv, Format::Arrow] {
                let whole = dir.path().join(format!("whole-{t}.{}", format.extension()));
                let streamed = dir
                    .path()
                    .join(format!("sub/streamed-{t}.{}", format.extension()));
                write(&whole, trajectory, format).unwrap();
                let mut stream = Stream::create(&streamed, &trajectory.names, format).unwrap();
                for k in 0..trajectory.len() {
                    stream.record(trajectory.times[k], trajectory.row(k));
                }
                assert_eq!(stream.finish().unwrap(), trajectory.len());
                assert!(
                    std::fs::read(&whole).unwrap() == std::fs::read(&streamed).unwrap(),
                    "{format:?}, trajectory {t}: the streamed file differs"
                );
            }
        }
    }

    #[test]
    fn a_write_error_is_returned_by_finish() {
        if !std::path::Path::new("/dev/full").exists() {
            return;
        }
        let mut stream = Stream::create(
            std::path::Path::new("/dev/full"),
            &["a.x".to_owned()],
            Format::Csv,
        )
        .unwrap();
        for k in 0..100_000 {
            stream.record(k as f64, &[1.0]);
        }
        assert!(stream.finish().is_err());
    }
}
