//! `manifest.csv`: one row per flight with its identity (index, run, run seed, law,
//! phi_cmd), every drawn dispersion, every metric and how the flight ended. Numbers are
//! written in ryu's shortest round-trip form, so a row read back compares bit-exactly
//! with a replay.
use crate::definition::Flight;
use crate::dispersion::{self, Dispersion};
use anyhow::Context;
use lander::laws::Law;
use lander::metrics::{metric_values, metrics_from, Metrics, METRIC_COUNT, METRIC_NAMES};
use std::io::Write;
use std::path::Path;

pub const FILE_NAME: &str = "manifest.csv";

thread_local! {
    /// Manifests parsed on this thread ([`reads_on_this_thread`]).
    static READS: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
}

/// How many manifests this thread has parsed ([`read`], [`read_complete`]): a campaign
/// parses its own at most once (to resume it), which its tests check with this count.
pub fn reads_on_this_thread() -> u64 {
    READS.with(std::cell::Cell::get)
}

/// How a flight ended.
#[derive(Debug, Clone, PartialEq)]
pub enum End {
    Completed,
    /// An instance stopped the run (touchdown).
    Terminated {
        instance: String,
    },
    /// The run failed; its metrics are NaN.
    Error {
        message: String,
    },
}

impl End {
    fn columns(&self) -> (String, &str) {
        match self {
            End::Completed => ("completed".into(), ""),
            End::Terminated { instance } => (format!("terminated:{instance}"), ""),
            End::Error { message } => ("error".into(), message),
        }
    }

    fn parse(end: &str, error: &str) -> Option<Self> {
        match end {
            "completed" => Some(End::Completed),
            "error" => Some(End::Error {
                message: error.to_owned(),
            }),
            _ => end.strip_prefix("terminated:").map(|i| End::Terminated {
                instance: i.to_owned(),
            }),
        }
    }

    pub fn is_error(&self) -> bool {
        matches!(self, End::Error { .. })
    }
}

/// A flight's verdict as the manifest keeps it.
#[derive(Debug, Clone, PartialEq)]
pub struct Judged {
    /// [`lander::verdict::Verdict::word`].
    pub word: String,
    /// Whether the flight ended as its scenario expects (false for every error).
    pub as_expected: bool,
    /// The broken touchdown limits ("vertical speed 4.88 m/s > 2.00 m/s (by 2.88 m/s); ..."),
    /// or why a flight that stopped did; empty otherwise.
    pub detail: String,
}

impl Judged {
    pub fn of(verdict: &lander::verdict::Verdict, expect: lander::verdict::Expect) -> Self {
        use lander::verdict::Verdict;
        Self {
            word: verdict.word().to_owned(),
            as_expected: verdict.meets(expect),
            detail: match verdict {
                Verdict::HardLanding { broken, .. } => broken
                    .iter()
                    .map(ToString::to_string)
                    .collect::<Vec<_>>()
                    .join("; "),
                Verdict::Stopped { reason, .. } => reason.clone(),
                _ => String::new(),
            },
        }
    }

    pub fn error() -> Self {
        Self {
            word: "error".into(),
            as_expected: false,
            detail: String::new(),
        }
    }
}

/// One manifest row.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    pub flight: Flight,
    pub dispersion: Dispersion,
    pub metrics: Metrics,
    pub end: End,
    pub verdict: Judged,
}

const IDENTITY: [&str; 5] = ["index", "run", "run_seed", "law", "phi_cmd_deg"];
const END: [&str; 5] = ["end", "error", "verdict", "as_expected", "verdict_detail"];

pub fn header() -> Vec<&'static str> {
    IDENTITY
        .iter()
        .chain(&dispersion::FIELD_NAMES)
        .chain(&METRIC_NAMES)
        .chain(&END)
        .copied()
        .collect()
}

pub(crate) fn number(value: f64) -> String {
    if value.is_finite() {
        ryu::Buffer::new().format_finite(value).to_owned()
    } else {
        // Rust's own spelling ("NaN", "inf", "-inf") parses back with `str::parse`.
        value.to_string()
    }
}

/// Writes rows as they come, flushing each so a killed campaign keeps its finished rows.
pub struct Writer<W: Write> {
    csv: csv::Writer<W>,
}

impl Writer<std::fs::File> {
    pub fn create(path: &Path) -> anyhow::Result<Self> {
        let file =
            std::fs::File::create(path).with_context(|| format!("creating {}", path.display()))?;
        Self::new(file)
    }

    /// Appends rows to a manifest whose first `keep` bytes (header and whole rows) stay; the
    /// rest (a row cut off by a kill) is cut away.
    pub fn append(path: &Path, keep: u64) -> anyhow::Result<Self> {
        Ok(Self {
            csv: append_at(path, keep)?,
        })
    }
}

/// A CSV writer appending to `path` after its first `keep` bytes (header and whole rows);
/// the rest (a row cut off by a kill) is cut away.
pub(crate) fn append_at(path: &Path, keep: u64) -> anyhow::Result<csv::Writer<std::fs::File>> {
    let file = std::fs::OpenOptions::new()
        .write(true)
        .open(path)
        .with_context(|| format!("opening {}", path.display()))?;
    file.set_len(keep)?;
    let mut file = file;
    std::io::Seek::seek(&mut file, std::io::SeekFrom::End(0))?;
    Ok(csv::WriterBuilder::new()
        .has_headers(false)
        .from_writer(file))
}

/// Rewrites a manifest with `rows` sorted by flight index (through a temporary file, so a
/// kill leaves either the old or the new file), so it does not depend on the order in which
/// workers, shards or resumed runs finished.
pub fn write_sorted(path: &Path, rows: &mut [Row]) -> anyhow::Result<()> {
    rows.sort_by_key(|r| r.flight.index);
    let tmp = path.with_extension("csv.tmp");
    let mut writer = Writer::create(&tmp)?;
    for row in rows.iter() {
        writer.write(row)?;
    }
    drop(writer);
    std::fs::rename(&tmp, path).with_context(|| format!("replacing {}", path.display()))
}

impl<W: Write> Writer<W> {
    pub fn new(out: W) -> anyhow::Result<Self> {
        let mut csv = csv::Writer::from_writer(out);
        csv.write_record(header())?;
        csv.flush()?;
        Ok(Self { csv })
    }

    pub fn write(&mut self, row: &Row) -> anyhow::Result<()> {
        let f = &row.flight;
        let mut record: Vec<String> = vec![
            f.index.to_string(),
            f.run.to_string(),
            f.run_seed.to_string(),
            f.law.name().to_owned(),
            number(f.phi_cmd_deg),
        ];
        record.extend(row.dispersion.to_fields().map(number));
        record.extend(metric_values(&row.metrics).map(number));
        let (end, error) = row.end.columns();
        record.push(end);
        record.push(error.to_owned());
        record.push(row.verdict.word.clone());
        record.push(row.verdict.as_expected.to_string());
        record.push(row.verdict.detail.clone());
        self.csv.write_record(&record)?;
        self.csv.flush()?;
        Ok(())
    }
}

/// Reads every row of a manifest, checking its header.
pub fn read(path: &Path) -> anyhow::Result<Vec<Row>> {
    let reader =
        csv::Reader::from_path(path).with_context(|| format!("opening {}", path.display()))?;
    read_from(reader, path)
}

/// The rows of a manifest that a killed campaign left, and the length in bytes of the part
/// holding them: a last record not ended by a newline (cut off mid-write) is not counted.
pub fn read_complete(path: &Path) -> anyhow::Result<(Vec<Row>, u64)> {
    let bytes = std::fs::read(path).with_context(|| format!("reading {}", path.display()))?;
    let complete = complete_length(&bytes)?;
    let whole = csv::Reader::from_reader(&bytes[..complete as usize]);
    Ok((read_from(whole, path)?, complete))
}

/// The length of the part of a CSV file holding its header and whole records: a last record
/// not ended by a newline (cut off mid-write) is not counted.
fn complete_length(bytes: &[u8]) -> anyhow::Result<u64> {
    let mut reader = csv::Reader::from_reader(bytes);
    reader.headers()?;
    let mut complete = reader.position().byte();
    let mut record = csv::StringRecord::new();
    while let Ok(true) = reader.read_record(&mut record) {
        let end = reader.position().byte();
        if end == 0 || bytes.get(end as usize - 1) != Some(&b'\n') {
            break;
        }
        complete = end;
    }
    Ok(complete)
}

/// The header and whole records of a CSV file, and the bytes holding them
/// ([`read_complete`] for any manifest layout).
pub(crate) fn complete_records(
    path: &Path,
) -> anyhow::Result<(Vec<String>, Vec<csv::StringRecord>, u64)> {
    let bytes = std::fs::read(path).with_context(|| format!("reading {}", path.display()))?;
    let complete = complete_length(&bytes)?;
    let mut reader = csv::Reader::from_reader(&bytes[..complete as usize]);
    let header = reader.headers()?.iter().map(str::to_owned).collect();
    let records = reader
        .records()
        .collect::<Result<_, _>>()
        .with_context(|| format!("reading {}", path.display()))?;
    Ok((header, records, complete))
}

fn read_from<R: std::io::Read>(
    mut reader: csv::Reader<R>,
    path: &Path,
) -> anyhow::Result<Vec<Row>> {
    READS.with(|reads| reads.set(reads.get() + 1));
    let expected = header();
    let found: Vec<&str> = reader.headers()?.iter().collect();
    anyhow::ensure!(
        found == expected,
        "{}: not a manifest of this harness version (header differs)",
        path.display()
    );
    let mut rows = Vec::new();
    for (line, record) in reader.records().enumerate() {
        let record = record?;
        let at = || format!("{} row {}", path.display(), line + 2);
        let field = |i: usize| record.get(i).unwrap_or_default();
        let integer = |i: usize| field(i).parse::<u64>().with_context(at);
        let real = |i: usize| field(i).parse::<f64>().with_context(at);
        anyhow::ensure!(!field(3).is_empty(), "{}: no law", at());
        let law = Law::named(field(3));
        let mut fields = [0.0; dispersion::FIELD_COUNT];
        for (k, slot) in fields.iter_mut().enumerate() {
            *slot = real(IDENTITY.len() + k)?;
        }
        let base = IDENTITY.len() + fields.len();
        let mut metrics = [0.0; METRIC_COUNT];
        for (k, slot) in metrics.iter_mut().enumerate() {
            *slot = real(base + k)?;
        }
        let end_at = base + metrics.len();
        let end = End::parse(field(end_at), field(end_at + 1))
            .with_context(|| format!("{}: end '{}'", at(), field(end_at)))?;
        rows.push(Row {
            flight: Flight {
                index: integer(0)?,
                run: integer(1)?,
                run_seed: integer(2)?,
                law,
                phi_cmd_deg: real(4)?,
            },
            dispersion: Dispersion::from_fields(&fields),
            metrics: metrics_from(metrics),
            end,
            verdict: Judged {
                word: field(end_at + 2).to_owned(),
                as_expected: field(end_at + 3)
                    .parse()
                    .with_context(|| format!("{}: as_expected", at()))?,
                detail: field(end_at + 4).to_owned(),
            },
        });
    }
    Ok(rows)
}

/// Whether two metric sets are the same bit for bit (NaN equal to the same NaN).
pub fn metrics_bit_equal(a: &Metrics, b: &Metrics) -> bool {
    metric_values(a)
        .iter()
        .zip(&metric_values(b))
        .all(|(x, y)| x.to_bits() == y.to_bits())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dispersion::DispersionRanges;

    #[test]
    fn rows_round_trip_bit_exactly() {
        let dispersion = Dispersion::draw(99, &DispersionRanges::default());
        let mut metrics = metrics_from(std::array::from_fn(|i| 1.0 / (i as f64 + 3.0)));
        metrics.roll_settling_time_s = f64::NAN;
        let rows = [
            Row {
                flight: Flight {
                    index: 3,
                    run: 1,
                    run_seed: u64::MAX,
                    law: Law::new("reduced"),
                    phi_cmd_deg: 150.0,
                },
                dispersion,
                metrics,
                end: End::Completed,
                verdict: Judged {
                    word: "completed".into(),
                    as_expected: true,
                    detail: String::new(),
                },
            },
            Row {
                flight: Flight {
                    index: 4,
                    run: 1,
                    run_seed: 5,
                    law: Law::COUPLED,
                    phi_cmd_deg: -1e-300,
                },
                dispersion,
                metrics,
                end: End::Error {
                    message: "instance 'plant', \"quoted\"\nsecond line".into(),
                },
                verdict: Judged::error(),
            },
            Row {
                flight: Flight {
                    index: 5,
                    run: 1,
                    run_seed: 5,
                    law: Law::DECOUPLED,
                    phi_cmd_deg: 0.1 + 0.2,
                },
                dispersion,
                metrics,
                end: End::Terminated {
                    instance: "plant".into(),
                },
                verdict: Judged {
                    word: "hard landing".into(),
                    as_expected: false,
                    detail: "tilt 56.00 deg > 12.00 deg (by 44.00 deg); x, \"y\"".into(),
                },
            },
        ];
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(FILE_NAME);
        let mut writer = Writer::create(&path).unwrap();
        for row in &rows {
            writer.write(row).unwrap();
        }
        drop(writer);
        let back = read(&path).unwrap();
        assert_eq!(back.len(), rows.len());
        for (a, b) in back.iter().zip(&rows) {
            assert_eq!(a.flight.index, b.flight.index);
            assert_eq!(a.flight.run_seed, b.flight.run_seed);
            assert_eq!(a.flight.law, b.flight.law);
            assert_eq!(
                a.flight.phi_cmd_deg.to_bits(),
                b.flight.phi_cmd_deg.to_bits()
            );
            assert_eq!(a.dispersion, b.dispersion);
            assert!(metrics_bit_equal(&a.metrics, &b.metrics));
            assert_eq!(a.end, b.end);
            assert_eq!(a.verdict, b.verdict);
        }
    }

    #[test]
    fn a_foreign_csv_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("x.csv");
        std::fs::write(&path, "time,a\n0,1\n").unwrap();
        assert!(read(&path).unwrap_err().to_string().contains("header"));
    }
}
