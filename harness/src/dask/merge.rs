//! The end of a Dask campaign, the same for every campaign subcommand: a `--resume` after the
//! merge finds the campaign complete in --out-dir; otherwise the shards not yet stored are
//! flown, the stored ones checked, merged into --out-dir as a local campaign writes it, and
//! the store removed. What depends on the campaign's files is its [`Format`].
use super::{fly, store_of, DaskArgs, Job};
use campaign::manifest;
use std::path::{Path, PathBuf};

/// A campaign's files as the Dask side merges them.
pub trait Format {
    /// A merged campaign: its definition and rows.
    type Merged;
    /// Merges shard directories (an error when a run is missing, unless `allow_missing`),
    /// the scenario named as it is here: a worker names it by its path in the task.
    fn merge(&self, dirs: &[PathBuf], allow_missing: bool) -> anyhow::Result<Self::Merged>;
    /// Whether `merged` is the campaign these options define.
    fn is_this(&self, merged: &Self::Merged) -> bool;
    /// Writes the merged campaign into `out_dir`, with where each shard was flown
    /// (`shard k/S: dask worker ...`) as what it was merged from; the manifest's path and
    /// the rows (flights or runs) written.
    fn write(
        &self,
        merged: &mut Self::Merged,
        merged_from: Vec<String>,
        out_dir: &Path,
    ) -> anyhow::Result<(PathBuf, usize)>;
}

/// Flies `job` on the cluster (the shards not yet stored, with `--resume`) and merges every
/// shard into `job.out_dir`; the merged campaign, for the subcommand's summary.
pub fn campaign<F: Format>(dask: &DaskArgs, job: &Job, format: &F) -> anyhow::Result<F::Merged> {
    // Resumed after the merge: the campaign in --out-dir is this one, whole.
    let merged_before = job.resume
        && !store_of(job.out_dir).exists()
        && job.out_dir.join(manifest::FILE_NAME).exists();
    if merged_before {
        if let Ok(done) = format.merge(&[job.out_dir.to_owned()], false) {
            if format.is_this(&done) {
                println!(
                    "resumed: the campaign in {} is complete",
                    job.out_dir.display()
                );
                return Ok(done);
            }
        }
    }
    let same_campaign = |dir: &Path| -> anyhow::Result<()> {
        let stored = format.merge(&[dir.to_owned()], true)?;
        anyhow::ensure!(
            format.is_this(&stored),
            "--resume: {} holds shards of another campaign than these options: without \
             --resume the campaign starts again",
            dir.parent().unwrap_or(dir).display()
        );
        Ok(())
    };
    let shards = fly(dask, job, &same_campaign)?;
    let mut merged = format.merge(&shards.dirs, false)?;
    anyhow::ensure!(
        format.is_this(&merged),
        "the Dask workers flew another campaign than these options define"
    );
    let count = shards.provenance.len();
    let (path, rows) = format.write(&mut merged, shards.provenance.clone(), job.out_dir)?;
    shards.remove()?;
    println!(
        "{rows} {} from {count} Dask shards -> {}",
        job.unit,
        path.display()
    );
    Ok(merged)
}
