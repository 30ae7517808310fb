//! CSV: a header `time,instance.variable,...` and one row per communication point,
//! numbers in the shortest form that reads back to the same f64 (ryu), so a CSV written here
//! and read back (pandas, fmpy's `read_csv`, [`read_csv`]) compares bit-exactly.
use crate::master::Trajectory;
use std::io::Write;
use std::path::Path;

/// Writes a trajectory; creates parent directories.
pub fn write_csv(path: &Path, trajectory: &Trajectory) -> std::io::Result<()> {
    if let Some(parent) = path.parent() {
        std::fs::create_dir_all(parent)?;
    }
    let mut out = std::io::BufWriter::new(std::fs::File::create(path)?);
    write_csv_to(&mut out, trajectory)?;
    out.flush()
}

pub fn write_csv_to(out: &mut dyn Write, trajectory: &Trajectory) -> std::io::Result<()> {
    write!(out, "time")?;
    for name in &trajectory.names {
        write!(out, ",{}", quote(name))?;
    }
    writeln!(out)?;
    let mut buffer = ryu::Buffer::new();
    for k in 0..trajectory.len() {
        out.write_all(number(&mut buffer, trajectory.times[k]).as_bytes())?;
        for &value in trajectory.row(k) {
            out.write_all(b",")?;
            out.write_all(number(&mut buffer, value).as_bytes())?;
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
}

impl CsvStream {
    /// Creates the file (and its parent directories) and writes the header.
    pub(super) fn create(path: &Path, names: &[String]) -> std::io::Result<Self> {
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
        })
    }

    pub(super) fn row(&mut self, time: f64, values: &[f64]) -> std::io::Result<()> {
        self.out
            .write_all(number(&mut self.buffer, time).as_bytes())?;
        for &value in values {
            self.out.write_all(b",")?;
            self.out
                .write_all(number(&mut self.buffer, value).as_bytes())?;
        }
        writeln!(self.out)
    }

    pub(super) fn finish(mut self) -> std::io::Result<()> {
        self.out.flush()
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

/// Names with a comma or quote are quoted (ours never have one, but a third-party FMU's may).
pub(super) fn quote(name: &str) -> String {
    if name.contains([',', '"']) {
        format!("\"{}\"", name.replace('"', "\"\""))
    } else {
        name.to_owned()
    }
}

/// Reads a CSV written by [`write_csv`] (or any numeric CSV with a `time` first column).
pub fn read_csv(path: &Path) -> anyhow::Result<Trajectory> {
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
        let mut fields = record.iter().map(|f| f.trim().parse::<f64>());
        let time = fields
            .next()
            .transpose()?
            .ok_or_else(|| anyhow::anyhow!("{}: row {} is empty", path.display(), line + 2))?;
        trajectory.times.push(time);
        for field in fields {
            trajectory.values.push(
                field.map_err(|e| anyhow::anyhow!("{}: row {}: {e}", path.display(), line + 2))?,
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
