//! Arrow IPC files (Feather v2): one float64 column per recorded variable after `time`, in
//! record batches of at most [`BATCH_ROWS`] rows, uncompressed, so that pandas, polars and
//! pyarrow map them without a conversion and every value is the f64 the FMU returned.
use crate::master::Trajectory;
use arrow_array::cast::AsArray;
use arrow_array::types::Float64Type;
use arrow_array::{Array, ArrayRef, Float64Array, RecordBatch};
use arrow_schema::{DataType, Field, Schema};
use std::fs::File;
use std::io::BufWriter;
use std::path::Path;
use std::sync::Arc;

/// Rows per record batch: large enough for column-at-a-time reading to pay, small enough
/// that writing holds only one batch's columns besides the trajectory.
pub const BATCH_ROWS: usize = 1 << 16;

/// Writes a trajectory as an Arrow IPC file, each column's unit (`units[j]` of
/// `trajectory.names[j]`; none where empty or absent) in its field metadata; creates parent
/// directories.
pub fn write_arrow(path: &Path, trajectory: &Trajectory, units: &[String]) -> anyhow::Result<()> {
    if let Some(parent) = path.parent() {
        std::fs::create_dir_all(parent)?;
    }
    let schema = schema(&trajectory.names, units);
    let out = BufWriter::new(File::create(path)?);
    let mut writer = arrow_ipc::writer::FileWriter::try_new(out, &schema)?;
    let width = trajectory.names.len();
    // At least one batch, so an empty trajectory still reads back with its columns.
    let mut start = 0;
    loop {
        let end = (start + BATCH_ROWS).min(trajectory.len());
        let mut columns: Vec<ArrayRef> = Vec::with_capacity(width + 1);
        columns.push(Arc::new(Float64Array::from(
            trajectory.times[start..end].to_vec(),
        )));
        for j in 0..width {
            let column: Vec<f64> = (start..end)
                .map(|k| trajectory.values[k * width + j])
                .collect();
            columns.push(Arc::new(Float64Array::from(column)));
        }
        writer.write(&RecordBatch::try_new(schema.clone(), columns)?)?;
        start = end;
        if start >= trajectory.len() {
            break;
        }
    }
    writer.finish()?;
    Ok(())
}

/// `time` and one float64 field per name, each with its unit as field metadata `unit`
/// (`s` for `time` when any units are given at all).
fn schema(names: &[String], units: &[String]) -> Arc<Schema> {
    let with_unit = |field: Field, unit: &str| {
        if unit.is_empty() {
            field
        } else {
            field.with_metadata([("unit".to_owned(), unit.to_owned())].into())
        }
    };
    let time = with_unit(
        Field::new("time", DataType::Float64, false),
        if units.is_empty() { "" } else { "s" },
    );
    let fields: Vec<Field> = std::iter::once(time)
        .chain(names.iter().enumerate().map(|(j, name)| {
            with_unit(
                Field::new(name, DataType::Float64, false),
                units.get(j).map(String::as_str).unwrap_or_default(),
            )
        }))
        .collect();
    Arc::new(Schema::new(fields))
}

/// An Arrow IPC file written batch by batch as a run records its rows (see
/// [`super::Stream`]): one batch of [`BATCH_ROWS`] rows held at a time, the same bytes as
/// [`write_arrow`] of the whole trajectory.
pub(super) struct ArrowStream {
    writer: arrow_ipc::writer::FileWriter<BufWriter<File>>,
    schema: Arc<Schema>,
    times: Vec<f64>,
    /// Column-major: one vector per recorded column.
    columns: Vec<Vec<f64>>,
    batches: usize,
}

impl ArrowStream {
    pub(super) fn create(path: &Path, names: &[String], units: &[String]) -> anyhow::Result<Self> {
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent)?;
        }
        let schema = schema(names, units);
        let out = BufWriter::new(File::create(path)?);
        let writer = arrow_ipc::writer::FileWriter::try_new(out, &schema)?;
        Ok(ArrowStream {
            writer,
            schema,
            times: Vec::new(),
            columns: vec![Vec::new(); names.len()],
            batches: 0,
        })
    }

    pub(super) fn row(&mut self, time: f64, values: &[f64]) -> anyhow::Result<()> {
        if self.times.is_empty() {
            self.times.reserve_exact(BATCH_ROWS);
            for column in &mut self.columns {
                column.reserve_exact(BATCH_ROWS);
            }
        }
        self.times.push(time);
        for (column, &value) in self.columns.iter_mut().zip(values) {
            column.push(value);
        }
        if self.times.len() == BATCH_ROWS {
            self.flush_batch()?;
        }
        Ok(())
    }

    fn flush_batch(&mut self) -> anyhow::Result<()> {
        let mut columns: Vec<ArrayRef> = Vec::with_capacity(self.columns.len() + 1);
        columns.push(Arc::new(Float64Array::from(std::mem::take(
            &mut self.times,
        ))));
        for column in &mut self.columns {
            columns.push(Arc::new(Float64Array::from(std::mem::take(column))));
        }
        self.writer
            .write(&RecordBatch::try_new(self.schema.clone(), columns)?)?;
        self.batches += 1;
        Ok(())
    }

    pub(super) fn finish(mut self) -> anyhow::Result<()> {
        // At least one batch, so an empty run still reads back with its columns.
        if !self.times.is_empty() || self.batches == 0 {
            self.flush_batch()?;
        }
        self.writer.finish()?;
        Ok(())
    }
}

/// The `unit` metadata of every column of an Arrow IPC file, in order ("" where none).
pub fn read_arrow_units(path: &Path) -> anyhow::Result<Vec<(String, String)>> {
    let reader = arrow_ipc::reader::FileReader::try_new(File::open(path)?, None)?;
    Ok(reader
        .schema()
        .fields()
        .iter()
        .map(|f| {
            let unit = f.metadata().get("unit").cloned().unwrap_or_default();
            (f.name().clone(), unit)
        })
        .collect())
}

/// Reads an Arrow IPC file of float64 columns with `time` first (as [`write_arrow`] writes).
pub fn read_arrow(path: &Path) -> anyhow::Result<Trajectory> {
    let file = File::open(path)?;
    let reader = arrow_ipc::reader::FileReader::try_new(file, None)?;
    let schema = reader.schema();
    let names: Vec<&str> = schema.fields().iter().map(|f| f.name().as_str()).collect();
    anyhow::ensure!(
        names.first() == Some(&"time"),
        "{}: first column must be 'time', not {:?}",
        path.display(),
        names.first()
    );
    if let Some(field) = schema
        .fields()
        .iter()
        .find(|f| f.data_type() != &DataType::Float64)
    {
        anyhow::bail!(
            "{}: column '{}' is {}, not float64",
            path.display(),
            field.name(),
            field.data_type()
        );
    }
    let mut trajectory = Trajectory {
        names: names[1..].iter().map(|n| n.to_string()).collect(),
        ..Default::default()
    };
    let width = trajectory.names.len();
    for batch in reader {
        let batch = batch?;
        let columns: Vec<&Float64Array> = batch
            .columns()
            .iter()
            .map(|c| c.as_primitive::<Float64Type>())
            .collect();
        anyhow::ensure!(
            columns.iter().all(|c| c.null_count() == 0),
            "{}: a column holds nulls",
            path.display()
        );
        trajectory.times.extend_from_slice(columns[0].values());
        trajectory.values.reserve(batch.num_rows() * width);
        for k in 0..batch.num_rows() {
            trajectory
                .values
                .extend(columns[1..].iter().map(|c| c.value(k)));
        }
    }
    Ok(trajectory)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bits(values: &[f64]) -> Vec<u64> {
        values.iter().map(|x| x.to_bits()).collect()
    }

    #[test]
    fn a_trajectory_round_trips_bit_exactly_across_batches() {
        // More rows than one batch, awkward values (subnormal, -0, NaN payload, infinities).
        let names = vec!["a.x[1]".to_owned(), "b,\"y\"".to_owned()];
        let rows = BATCH_ROWS + 3;
        let specials = [
            5e-324,
            -0.0,
            f64::from_bits(0x7ff8_0000_dead_beef),
            f64::INFINITY,
            f64::NEG_INFINITY,
            1.0 / 3.0,
        ];
        let trajectory = Trajectory {
            names,
            times: (0..rows).map(|k| k as f64 * 0.01).collect(),
            values: (0..2 * rows)
                .map(|i| specials[i % specials.len()] * if i % 7 == 0 { -1.0 } else { 1.0 })
                .collect(),
        };
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("sub/r.arrow");
        write_arrow(&path, &trajectory, &[]).unwrap();
        let back = read_arrow(&path).unwrap();
        assert_eq!(back.names, trajectory.names);
        assert_eq!(bits(&back.times), bits(&trajectory.times));
        assert_eq!(bits(&back.values), bits(&trajectory.values));
    }

    #[test]
    fn an_empty_trajectory_keeps_its_columns() {
        let trajectory = Trajectory {
            names: vec!["a.x".into()],
            ..Default::default()
        };
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("empty.arrow");
        write_arrow(&path, &trajectory, &[]).unwrap();
        let back = read_arrow(&path).unwrap();
        assert_eq!(back.names, trajectory.names);
        assert!(back.is_empty());
    }

    #[test]
    fn a_file_that_is_not_arrow_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("r.arrow");
        std::fs::write(&path, "time,a.x\n0,1\n").unwrap();
        assert!(read_arrow(&path).is_err());
    }
}
