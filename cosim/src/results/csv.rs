//! CSV: a header `time,instance.variable,...` and one row per communication point,
//! numbers in the shortest form that reads back to the same f64 (ryu), so a CSV written here
//! and read back (pandas, fmpy's `read_csv`, [`read_csv`]) compares bit-exactly. With column
//! types ([`ColumnType`]), integers and booleans are written as integers (`1000`, `1`) and a
//! UInt64 or Int64 as its exact value.
use super::columns::{type_of, ColumnType};
use crate::master::Trajectory;
use std::io::Write;
use std::path::Path;

/// Writes a trajectory; creates parent directories.
pub fn write_csv(path: &Path, trajectory: &Trajectory) -> std::io::Result<()> {
    write_csv_typed(path, trajectory, &[])
}

/// [`write_csv`] with each column's type (`types[j]` of column `j`; Float64 where absent).
pub fn write_csv_typed(
    path: &Path,
    trajectory: &Trajectory,
    types: &[ColumnType],
) -> std::io::Result<()> {
    if let Some(parent) = path.parent() {
        std::fs::create_dir_all(parent)?;
    }
    let mut out = std::io::BufWriter::new(std::fs::File::create(path)?);
    write_csv_typed_to(&mut out, trajectory, types)?;
    out.flush()
}

pub fn write_csv_to(out: &mut dyn Write, trajectory: &Trajectory) -> std::io::Result<()> {
    write_csv_typed_to(out, trajectory, &[])
}

fn write_csv_typed_to(
    out: &mut dyn Write,
    trajectory: &Trajectory,
    types: &[ColumnType],
) -> std::io::Result<()> {
    write!(out, "time")?;
    for name in &trajectory.names {
        write!(out, ",{}", quote(name))?;
    }
    writeln!(out)?;
    let mut buffer = ryu::Buffer::new();
    for k in 0..trajectory.len() {
        out.write_all(number(&mut buffer, trajectory.times[k]).as_bytes())?;
        for (j, &value) in trajectory.row(k).iter().enumerate() {
            out.write_all(b",")?;
            // A trajectory in memory keeps no text: its text columns are empty.
            if !type_of(types, j).is_text() {
                write_value(out, &mut buffer, type_of(types, j), value)?;
            }
        }
        writeln!(out)?;
    }
    Ok(())
}

/// A CSV written row by row as a run records them (see [`super::Stream`]): the same bytes
/// as [`write_csv`] of the whole trajectory.
pub(super) struct CsvStream {
    out: std::io::BufWriter<std::fs::File>,
    buffer: ryu::Buffer,
    types: Vec<ColumnType>,
    /// The current value of each text column, as written.
    texts: Vec<String>,
}

impl CsvStream {
    /// Creates the file (and its parent directories) and writes the header.
    pub(super) fn create(
        path: &Path,
        names: &[String],
        types: &[ColumnType],
    ) -> std::io::Result<Self> {
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent)?;
        }
        let mut out = std::io::BufWriter::new(std::fs::File::create(path)?);
        write!(out, "time")?;
        for name in names {
            write!(out, ",{}", quote(name))?;
        }
        writeln!(out)?;
        Ok(CsvStream {
            out,
            buffer: ryu::Buffer::new(),
            types: types.to_vec(),
            texts: vec![String::new(); names.len()],
        })
    }

    /// The value of text column `column` from the next row on.
    pub(super) fn text(&mut self, column: usize, text: &str) {
        if let Some(slot) = self.texts.get_mut(column) {
            *slot = quote(text);
        }
    }

    pub(super) fn row(&mut self, time: f64, values: &[f64]) -> std::io::Result<()> {
        self.out
            .write_all(number(&mut self.buffer, time).as_bytes())?;
        for (j, &value) in values.iter().enumerate() {
            self.out.write_all(b",")?;
            let kind = type_of(&self.types, j);
            if kind.is_text() {
                self.out.write_all(self.texts[j].as_bytes())?;
            } else {
                write_value(&mut self.out, &mut self.buffer, kind, value)?;
            }
        }
        writeln!(self.out)
    }

    pub(super) fn finish(mut self) -> std::io::Result<()> {
        self.out.flush()
    }
}

/// A slot as its column's type writes it: integers and booleans as integers, the rest as
/// numbers.
fn write_value(
    out: &mut dyn Write,
    buffer: &mut ryu::Buffer,
    kind: ColumnType,
    value: f64,
) -> std::io::Result<()> {
    if kind.is_integer() || (kind == ColumnType::Boolean && value.is_finite()) {
        write!(out, "{}", kind.integer(value))
    } else {
        out.write_all(number(buffer, value).as_bytes())
    }
}

fn number(buffer: &mut ryu::Buffer, value: f64) -> &str {
    if value.is_finite() {
        buffer.format_finite(value)
    } else if value.is_nan() {
        "nan"
    } else if value > 0.0 {
        "inf"
    } else {
        "-inf"
    }
}

/// Names with a comma or quote are quoted (ours never have one, but a third-party FMU's may),
/// and so are String values with one or a line break.
pub(super) fn quote(name: &str) -> String {
    if name.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", name.replace('"', "\"\""))
    } else {
        name.to_owned()
    }
}

/// Reads a CSV written by [`write_csv`] (or any numeric CSV with a `time` first column).
/// An Int64 or UInt64 column reads as the nearest f64; [`read_csv_typed`] reads it exactly.
pub fn read_csv(path: &Path) -> anyhow::Result<Trajectory> {
    read_csv_typed(path, &[])
}

/// [`read_csv`] of a file written with column types: each Int64 and UInt64 value into its
/// slot exactly (see [`ColumnType`]).
pub fn read_csv_typed(path: &Path, types: &[ColumnType]) -> anyhow::Result<Trajectory> {
    let mut reader = csv::Reader::from_path(path)?;
    let headers = reader.headers()?.clone();
    anyhow::ensure!(
        headers.get(0) == Some("time"),
        "{}: first column must be 'time'",
        path.display()
    );
    let mut trajectory = Trajectory {
        names: headers.iter().skip(1).map(str::to_owned).collect(),
        ..Default::default()
    };
    for (line, record) in reader.records().enumerate() {
        let record = record?;
        let mut fields = record.iter();
        let time = fields
            .next()
            .ok_or_else(|| anyhow::anyhow!("{}: row {} is empty", path.display(), line + 2))?
            .trim()
            .parse::<f64>()?;
        trajectory.times.push(time);
        for (j, field) in fields.enumerate() {
            if type_of(types, j).is_text() {
                trajectory.values.push(0.0);
                continue;
            }
            trajectory.values.push(
                type_of(types, j)
                    .parse_slot(field)
                    .map_err(|e| anyhow::anyhow!("{}: row {}: {e}", path.display(), line + 2))?,
            );
        }
    }
    anyhow::ensure!(
        trajectory.values.len() == trajectory.times.len() * trajectory.names.len(),
        "{}: ragged rows",
        path.display()
    );
    Ok(trajectory)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn typed_columns_write_integers_as_integers_and_64_bits_exactly() {
        let types = [
            ColumnType::Int32,
            ColumnType::Boolean,
            ColumnType::UInt64,
            ColumnType::Int64,
            ColumnType::Float32,
            ColumnType::Float64,
        ];
        let big = u64::MAX - 1;
        let trajectory = Trajectory {
            names: ["i", "b", "u", "s", "f", "x"].map(String::from).to_vec(),
            times: vec![0.0],
            values: vec![
                1000.0,
                1.0,
                ColumnType::UInt64.slot_of_word(big),
                ColumnType::Int64.slot_of_word(i64::MIN as u64),
                f64::from(0.1f32),
                1000.0,
            ],
        };
        let mut text = Vec::new();
        write_csv_typed_to(&mut text, &trajectory, &types).unwrap();
        let text = String::from_utf8(text).unwrap();
        let row = text.lines().nth(1).unwrap();
        assert_eq!(
            row,
            format!(
                "0.0,1000,1,{big},{},{},1000.0",
                i64::MIN,
                ryu::Buffer::new().format(f64::from(0.1f32))
            )
        );
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("typed.csv");
        write_csv_typed(&path, &trajectory, &types).unwrap();
        let back = read_csv_typed(&path, &types).unwrap();
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&back.values), bits(&trajectory.values));
    }

    #[test]
    fn a_trajectory_round_trips_bit_exactly() {
        let trajectory = Trajectory {
            names: vec!["a.x[1]".into(), "b.y".into()],
            times: vec![0.0, 0.01, 0.1 + 0.2],
            values: vec![1e-300, -0.0, std::f64::consts::PI, 1.0 / 3.0, 7.0, -2.5e17],
        };
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("sub/r.csv");
        write_csv(&path, &trajectory).unwrap();
        let back = read_csv(&path).unwrap();
        assert_eq!(back.names, trajectory.names);
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&back.times), bits(&trajectory.times));
        assert_eq!(bits(&back.values), bits(&trajectory.values));
    }
}
