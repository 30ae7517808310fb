//! Arrow IPC files (Feather v2): one float64 column per recorded variable after `time`, in
//! record batches of at most [`BATCH_ROWS`] rows, uncompressed, so that pandas, polars and
//! pyarrow map them without a conversion and every value is the f64 the FMU returned.
//!
//! With column types ([`ColumnType`]) a column is written in its own Arrow type: Int8 ..
//! UInt64 as those integers, Float32 as float32, Boolean as bool; without, every column is
//! float64. The reader takes either back into slots (see `columns.rs`).
use super::columns::{type_of, ColumnType};
use crate::master::Trajectory;
use arrow_array::cast::AsArray;
use arrow_array::types::{
    Float32Type, Float64Type, Int16Type, Int32Type, Int64Type, Int8Type, UInt16Type, UInt32Type,
    UInt64Type, UInt8Type,
};
use arrow_array::{
    Array, ArrayRef, BinaryArray, BooleanArray, Float32Array, Float64Array, Int16Array, Int32Array,
    Int64Array, Int8Array, RecordBatch, StringArray, UInt16Array, UInt32Array, UInt64Array,
    UInt8Array,
};
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
    write_arrow_typed(path, trajectory, units, &[])
}

/// [`write_arrow`] with each column's type (`types[j]`; float64 where absent).
pub fn write_arrow_typed(
    path: &Path,
    trajectory: &Trajectory,
    units: &[String],
    types: &[ColumnType],
) -> anyhow::Result<()> {
    if let Some(parent) = path.parent() {
        std::fs::create_dir_all(parent)?;
    }
    let schema = schema(&trajectory.names, units, types);
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
            columns.push(array(type_of(types, j), column));
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

/// The Arrow type of a column.
fn data_type(kind: ColumnType) -> DataType {
    match kind {
        ColumnType::Float64 => DataType::Float64,
        ColumnType::Float32 => DataType::Float32,
        ColumnType::Int8 => DataType::Int8,
        ColumnType::UInt8 => DataType::UInt8,
        ColumnType::Int16 => DataType::Int16,
        ColumnType::UInt16 => DataType::UInt16,
        ColumnType::Int32 => DataType::Int32,
        ColumnType::UInt32 => DataType::UInt32,
        ColumnType::Int64 => DataType::Int64,
        ColumnType::UInt64 => DataType::UInt64,
        ColumnType::Boolean => DataType::Boolean,
        ColumnType::String => DataType::Utf8,
        ColumnType::Binary => DataType::Binary,
    }
}

/// A text column of `texts` (a Binary's in hex, as `Recorder::record_text` gives them).
fn text_array(kind: ColumnType, texts: Vec<String>) -> ArrayRef {
    if kind == ColumnType::Binary {
        let bytes: Vec<Vec<u8>> = texts
            .iter()
            .map(|t| fmi_import::word::from_hex(t).unwrap_or_default())
            .collect();
        Arc::new(BinaryArray::from_iter_values(bytes))
    } else {
        Arc::new(StringArray::from(texts))
    }
}

/// The array of a column's slots in its type (each slot exact in it, see `columns.rs`).
fn array(kind: ColumnType, slots: Vec<f64>) -> ArrayRef {
    let integers = || slots.iter().map(|&slot| kind.integer(slot));
    match kind {
        ColumnType::Float64 => Arc::new(Float64Array::from(slots)),
        ColumnType::Float32 => Arc::new(Float32Array::from(
            slots.iter().map(|&x| x as f32).collect::<Vec<_>>(),
        )),
        ColumnType::Int8 => Arc::new(Int8Array::from_iter_values(integers().map(|i| i as i8))),
        ColumnType::UInt8 => Arc::new(UInt8Array::from_iter_values(integers().map(|i| i as u8))),
        ColumnType::Int16 => Arc::new(Int16Array::from_iter_values(integers().map(|i| i as i16))),
        ColumnType::UInt16 => Arc::new(UInt16Array::from_iter_values(integers().map(|i| i as u16))),
        ColumnType::Int32 => Arc::new(Int32Array::from_iter_values(integers().map(|i| i as i32))),
        ColumnType::UInt32 => Arc::new(UInt32Array::from_iter_values(integers().map(|i| i as u32))),
        ColumnType::Int64 => Arc::new(Int64Array::from_iter_values(integers().map(|i| i as i64))),
        ColumnType::UInt64 => Arc::new(UInt64Array::from_iter_values(integers().map(|i| i as u64))),
        ColumnType::Boolean => Arc::new(BooleanArray::from(
            slots.iter().map(|&b| b != 0.0).collect::<Vec<_>>(),
        )),
        // A trajectory in memory keeps no text: the column is empty texts.
        ColumnType::String | ColumnType::Binary => {
            text_array(kind, vec![String::new(); slots.len()])
        }
    }
}

/// The slots of an Arrow column of any type `array` writes.
fn slots(path: &Path, name: &str, column: &dyn Array) -> anyhow::Result<Vec<f64>> {
    let n = column.len();
    Ok(match column.data_type() {
        DataType::Float64 => column.as_primitive::<Float64Type>().values().to_vec(),
        DataType::Float32 => column
            .as_primitive::<Float32Type>()
            .values()
            .iter()
            .map(|&x| f64::from(x))
            .collect(),
        DataType::Int8 => cast(column.as_primitive::<Int8Type>().values(), f64::from),
        DataType::UInt8 => cast(column.as_primitive::<UInt8Type>().values(), f64::from),
        DataType::Int16 => cast(column.as_primitive::<Int16Type>().values(), f64::from),
        DataType::UInt16 => cast(column.as_primitive::<UInt16Type>().values(), f64::from),
        DataType::Int32 => cast(column.as_primitive::<Int32Type>().values(), f64::from),
        DataType::UInt32 => cast(column.as_primitive::<UInt32Type>().values(), f64::from),
        DataType::Int64 => cast(column.as_primitive::<Int64Type>().values(), |i| {
            f64::from_bits(i as u64)
        }),
        DataType::UInt64 => cast(column.as_primitive::<UInt64Type>().values(), f64::from_bits),
        DataType::Boolean => {
            let booleans = column.as_boolean();
            (0..n)
                .map(|k| f64::from(u8::from(booleans.value(k))))
                .collect()
        }
        // Text has no slot (see `columns.rs`).
        DataType::Utf8 | DataType::Binary => vec![0.0; n],
        other => anyhow::bail!(
            "{}: column '{name}' is {other}, not one of the types a result file holds",
            path.display()
        ),
    })
}

fn cast<T: Copy>(values: &[T], f: impl Fn(T) -> f64) -> Vec<f64> {
    values.iter().map(|&v| f(v)).collect()
}

/// The column type of an Arrow type `data_type` writes.
fn column_type(data_type: &DataType) -> ColumnType {
    [
        ColumnType::Float32,
        ColumnType::Int8,
        ColumnType::UInt8,
        ColumnType::Int16,
        ColumnType::UInt16,
        ColumnType::Int32,
        ColumnType::UInt32,
        ColumnType::Int64,
        ColumnType::UInt64,
        ColumnType::Boolean,
        ColumnType::String,
        ColumnType::Binary,
    ]
    .into_iter()
    .find(|&kind| self::data_type(kind) == *data_type)
    .unwrap_or_default()
}

/// `time` and one field per name in its type (float64 where none is given), each with its
/// unit as field metadata `unit` (`s` for `time` when any units are given at all).
fn schema(names: &[String], units: &[String], types: &[ColumnType]) -> Arc<Schema> {
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
                Field::new(name, data_type(type_of(types, j)), false),
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
    types: Vec<ColumnType>,
    /// The current value of each text column, and each text column's values in the batch.
    texts: Vec<String>,
    text_columns: Vec<Vec<String>>,
    times: Vec<f64>,
    /// Column-major: one vector per recorded column.
    columns: Vec<Vec<f64>>,
    batches: usize,
}

impl ArrowStream {
    pub(super) fn create(
        path: &Path,
        names: &[String],
        units: &[String],
        types: &[ColumnType],
    ) -> anyhow::Result<Self> {
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent)?;
        }
        let schema = schema(names, units, types);
        let out = BufWriter::new(File::create(path)?);
        let writer = arrow_ipc::writer::FileWriter::try_new(out, &schema)?;
        Ok(ArrowStream {
            writer,
            schema,
            types: types.to_vec(),
            texts: vec![String::new(); names.len()],
            text_columns: vec![Vec::new(); names.len()],
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
        for (j, texts) in self.text_columns.iter_mut().enumerate() {
            if type_of(&self.types, j).is_text() {
                texts.push(self.texts[j].clone());
            }
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
        for (j, column) in self.columns.iter_mut().enumerate() {
            let kind = type_of(&self.types, j);
            let slots = std::mem::take(column);
            columns.push(if kind.is_text() {
                text_array(kind, std::mem::take(&mut self.text_columns[j]))
            } else {
                array(kind, slots)
            });
        }
        self.writer
            .write(&RecordBatch::try_new(self.schema.clone(), columns)?)?;
        self.batches += 1;
        Ok(())
    }

    /// The value of text column `column` from the next row on.
    pub(super) fn text(&mut self, column: usize, text: &str) {
        if let Some(slot) = self.texts.get_mut(column) {
            text.clone_into(slot);
        }
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

/// Reads an Arrow IPC file with `time` first (as [`write_arrow`] writes): every column as
/// slots (an Int64 or UInt64 as its bits, see `columns.rs`; [`read_arrow_typed`] says which).
pub fn read_arrow(path: &Path) -> anyhow::Result<Trajectory> {
    read_arrow_typed(path).map(|(trajectory, _)| trajectory)
}

/// [`read_arrow`] with the type of each column after `time`.
pub fn read_arrow_typed(path: &Path) -> anyhow::Result<(Trajectory, Vec<ColumnType>)> {
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
    if schema.fields()[0].data_type() != &DataType::Float64 {
        anyhow::bail!(
            "{}: column 'time' is {}, not float64",
            path.display(),
            schema.fields()[0].data_type()
        );
    }
    let types: Vec<ColumnType> = schema.fields()[1..]
        .iter()
        .map(|f| column_type(f.data_type()))
        .collect();
    let mut trajectory = Trajectory {
        names: names[1..].iter().map(|n| n.to_string()).collect(),
        ..Default::default()
    };
    let width = trajectory.names.len();
    for batch in reader {
        let batch = batch?;
        anyhow::ensure!(
            batch.columns().iter().all(|c| c.null_count() == 0),
            "{}: a column holds nulls",
            path.display()
        );
        let columns: Vec<Vec<f64>> = batch
            .columns()
            .iter()
            .zip(&names)
            .map(|(c, name)| slots(path, name, c.as_ref()))
            .collect::<anyhow::Result<_>>()?;
        trajectory.times.extend_from_slice(&columns[0]);
        trajectory.values.reserve(batch.num_rows() * width);
        for k in 0..batch.num_rows() {
            trajectory.values.extend(columns[1..].iter().map(|c| c[k]));
        }
    }
    Ok((trajectory, types))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn typed_columns_are_written_in_their_arrow_types_and_read_back_exactly() {
        let types = [
            ColumnType::Int8,
            ColumnType::UInt8,
            ColumnType::Int16,
            ColumnType::UInt16,
            ColumnType::Int32,
            ColumnType::UInt32,
            ColumnType::Int64,
            ColumnType::UInt64,
            ColumnType::Float32,
            ColumnType::Boolean,
            ColumnType::Float64,
        ];
        let values = vec![
            -128.0,
            255.0,
            -32768.0,
            65535.0,
            -2147483648.0,
            4294967295.0,
            ColumnType::Int64.slot_of_word(i64::MIN as u64),
            ColumnType::UInt64.slot_of_word(u64::MAX - 1),
            f64::from(1.0f32 / 3.0),
            1.0,
            0.1,
        ];
        let trajectory = Trajectory {
            names: (0..types.len()).map(|j| format!("a.v{j}")).collect(),
            times: vec![0.0],
            values,
        };
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("typed.arrow");
        write_arrow_typed(&path, &trajectory, &[], &types).unwrap();
        let (back, read_types) = read_arrow_typed(&path).unwrap();
        assert_eq!(read_types, types);
        assert_eq!(bits(&back.values), bits(&trajectory.values));
        let reader =
            arrow_ipc::reader::FileReader::try_new(File::open(&path).unwrap(), None).unwrap();
        let schema = reader.schema();
        assert_eq!(schema.field(8).data_type(), &DataType::UInt64);
        assert_eq!(schema.field(10).data_type(), &DataType::Boolean);
    }

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
