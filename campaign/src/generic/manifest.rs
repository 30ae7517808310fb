//! The `manifest.csv` of a scenario campaign: one row per run with its identity (index, run,
//! run seed, sweep point), each input's value by name, how the run ended, its verdict and each
//! requirement's robustness. Numbers in ryu's shortest round-trip form, so a row read back
//! compares bit for bit with a replay.
use crate::generic::plan::RunId;
use crate::manifest::number;
use anyhow::Context;
use std::path::Path;

pub use crate::manifest::FILE_NAME;

/// A run's verdict: "pass" (it ended and every requirement holds), "fail" (a requirement is
/// violated, inconclusive or undefined) or "error" (the run failed).
pub const PASS: &str = "pass";
pub const FAIL: &str = "fail";
pub const ERROR: &str = "error";

/// One manifest row.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    pub id: RunId,
    pub inputs: Vec<f64>,
    /// "completed", "terminated:INSTANCE" or "error".
    pub end: String,
    pub verdict: String,
    pub robustness: Vec<f64>,
    /// The error of a failed run.
    pub error: String,
}

impl Row {
    pub fn passed(&self) -> bool {
        self.verdict == PASS
    }

    /// Same identity, inputs, end, verdict and robustness, bit for bit.
    pub fn bit_equal(&self, other: &Row) -> bool {
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        self.id == other.id
            && bits(&self.inputs) == bits(&other.inputs)
            && bits(&self.robustness) == bits(&other.robustness)
            && (
                self.end.as_str(),
                self.verdict.as_str(),
                self.error.as_str(),
            ) == (
                other.end.as_str(),
                other.verdict.as_str(),
                other.error.as_str(),
            )
    }
}

/// The columns of a campaign's manifest: its inputs' and requirements' names.
#[derive(Debug, Clone, PartialEq)]
pub struct Layout {
    pub inputs: Vec<String>,
    pub requirements: Vec<String>,
}

const IDENTITY: [&str; 4] = ["index", "run", "run_seed", "point"];

impl Layout {
    pub fn header(&self) -> Vec<String> {
        let identity = IDENTITY.iter().map(|s| s.to_string());
        identity
            .chain(self.inputs.iter().cloned())
            .chain(["end".into(), "verdict".into()])
            .chain(self.requirements.iter().map(|r| format!("robustness:{r}")))
            .chain(["error".into()])
            .collect()
    }

    /// A row's inputs as a reader wants them: `osc.c = 0.2, osc.k = 0.93`.
    pub fn describe_inputs(&self, row: &Row) -> String {
        let named = self.inputs.iter().zip(&row.inputs);
        named
            .map(|(n, v)| format!("{n} = {v}"))
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// The layout a manifest's header shows.
    pub fn of_manifest(path: &Path) -> anyhow::Result<Self> {
        let (header, _, _) = crate::manifest::complete_records(path)?;
        let inputs_end = header.iter().position(|h| h == "end");
        let ok = header.len() >= 7
            && header[..4] == IDENTITY
            && inputs_end.is_some_and(|e| header.get(e + 1).is_some_and(|v| v == "verdict"))
            && header.last().is_some_and(|l| l == "error");
        anyhow::ensure!(ok, "{}: not a scenario campaign's manifest", path.display());
        let end = inputs_end.unwrap_or_default();
        let requirements = header[end + 2..header.len() - 1]
            .iter()
            .map(|h| h.strip_prefix("robustness:").unwrap_or(h).to_owned())
            .collect();
        Ok(Self {
            inputs: header[4..end].to_vec(),
            requirements,
        })
    }

    fn record(&self, row: &Row) -> Vec<String> {
        let id = &row.id;
        let identity = [id.index, id.run, id.run_seed, id.point].map(|n| n.to_string());
        identity
            .into_iter()
            .chain(row.inputs.iter().map(|&x| input_number(x)))
            .chain([row.end.clone(), row.verdict.clone()])
            .chain(row.robustness.iter().map(|&x| number(x)))
            .chain([row.error.clone()])
            .collect()
    }

    fn parse(&self, record: &csv::StringRecord, at: &dyn Fn() -> String) -> anyhow::Result<Row> {
        let field = |i: usize| record.get(i).unwrap_or_default();
        let integer = |i: usize| field(i).parse::<u64>().with_context(at);
        let real = |i: usize| field(i).parse::<f64>().with_context(at);
        let n = self.inputs.len();
        let inputs = (0..n).map(|k| real(4 + k)).collect::<anyhow::Result<_>>()?;
        let robustness = (0..self.requirements.len())
            .map(|k| real(6 + n + k))
            .collect::<anyhow::Result<_>>()?;
        Ok(Row {
            id: RunId {
                index: integer(0)?,
                run: integer(1)?,
                run_seed: integer(2)?,
                point: integer(3)?,
            },
            inputs,
            end: field(4 + n).to_owned(),
            verdict: field(5 + n).to_owned(),
            robustness,
            error: field(6 + n + self.requirements.len()).to_owned(),
        })
    }

    /// Writes `rows` sorted by index into `path` (through a temporary file, so a kill leaves
    /// the old or the new file).
    pub fn write_sorted(&self, path: &Path, mut rows: Vec<Row>) -> anyhow::Result<()> {
        rows.sort_by_key(|r| r.id.index);
        let tmp = path.with_extension("csv.tmp");
        let mut writer = Writer::create(self, &tmp)?;
        for row in &rows {
            writer.write(row)?;
        }
        drop(writer);
        std::fs::rename(&tmp, path).with_context(|| format!("replacing {}", path.display()))
    }

    /// The whole rows of a manifest (a last row cut off by a kill left out) and the bytes
    /// holding them; the header must be this layout's.
    pub fn read_complete(&self, path: &Path) -> anyhow::Result<(Vec<Row>, u64)> {
        let (header, records, bytes) = crate::manifest::complete_records(path)?;
        anyhow::ensure!(
            header == self.header(),
            "{}: not a manifest of this campaign (its columns differ: {})",
            path.display(),
            header.join(",")
        );
        let rows = records
            .iter()
            .enumerate()
            .map(|(line, record)| {
                self.parse(record, &|| format!("{} row {}", path.display(), line + 2))
            })
            .collect::<anyhow::Result<_>>()?;
        Ok((rows, bytes))
    }
}

/// An input as the manifest writes it: a whole number (an Integer parameter's, a swept
/// `1.0`) as an integer, `2` not `2.0`, which reads back to the same bits; others as
/// [`number`] does.
fn input_number(x: f64) -> String {
    // Below 2^53 every whole f64 is exactly an i64 and back; -0 stays "-0.0", keeping its sign.
    let whole = x.fract() == 0.0 && x.abs() < 9_007_199_254_740_992.0;
    if whole && (x != 0.0 || x.is_sign_positive()) {
        (x as i64).to_string()
    } else {
        number(x)
    }
}

/// Writes rows as they come, flushing each so a killed campaign keeps its finished rows.
pub struct Writer<'a> {
    layout: &'a Layout,
    csv: csv::Writer<std::fs::File>,
}

impl<'a> Writer<'a> {
    pub fn create(layout: &'a Layout, path: &Path) -> anyhow::Result<Self> {
        let file =
            std::fs::File::create(path).with_context(|| format!("creating {}", path.display()))?;
        let mut csv = csv::Writer::from_writer(file);
        csv.write_record(layout.header())?;
        csv.flush()?;
        Ok(Self { layout, csv })
    }

    /// Appends to a manifest whose first `keep` bytes stay.
    pub fn append(layout: &'a Layout, path: &Path, keep: u64) -> anyhow::Result<Self> {
        Ok(Self {
            layout,
            csv: crate::manifest::append_at(path, keep)?,
        })
    }

    pub fn write(&mut self, row: &Row) -> anyhow::Result<()> {
        self.csv.write_record(self.layout.record(row))?;
        self.csv.flush()?;
        Ok(())
    }
}
