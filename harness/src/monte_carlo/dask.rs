//! `monte-carlo --dask`: the campaign's shards flown as Dask tasks (`crate::dask`), merged
//! into --out-dir as `merge-mc` merges them.
use super::{report, MonteCarloArgs};
use campaign::{manifest, merge, CampaignSpec};
use std::path::{Path, PathBuf};

/// A `monte-carlo` campaign's files, merged as `merge-mc` merges them.
struct Format<'a> {
    spec: &'a CampaignSpec,
}

impl crate::dask::Format for Format<'_> {
    type Merged = merge::Merged;

    fn merge(&self, dirs: &[PathBuf], allow_missing: bool) -> anyhow::Result<merge::Merged> {
        let mut merged = merge::merge(dirs, allow_missing)?;
        if merged.spec.scenario == crate::dask::worker_scenario(&self.spec.scenario) {
            merged.spec.scenario = self.spec.scenario.clone();
            merged.file.campaign.scenario = self.spec.scenario.clone();
        }
        Ok(merged)
    }

    fn is_this(&self, merged: &merge::Merged) -> bool {
        merged.spec == *self.spec
    }

    fn write(
        &self,
        merged: &mut merge::Merged,
        merged_from: Vec<String>,
        out_dir: &Path,
    ) -> anyhow::Result<(PathBuf, usize)> {
        merged.file.execution.merged_from = merged_from;
        Ok((merge::write(merged, out_dir)?, merged.rows.len()))
    }
}

/// `monte-carlo --dask`: the shards flown on the cluster, merged into --out-dir as `merge-mc`
/// merges them, the scenario named as the user named it.
pub fn campaign(args: &MonteCarloArgs, spec: &CampaignSpec, fmu_dir: &Path) -> anyhow::Result<i32> {
    let job = crate::dask::Job {
        subcommand: "monte-carlo",
        scenario_id: "scenario",
        scenario: &spec.scenario,
        declaration: None,
        fmu_dir,
        out_dir: &args.out_dir,
        flights: spec.flight_count(),
        unit: "flights",
        resume: args.resume,
        quiet: args.quiet,
    };
    let merged = crate::dask::campaign(&args.dask, &job, &Format { spec })?;
    finish(args, spec, &merged.rows)
}

/// The summary, figure and report of the merged rows, as a local campaign ends.
fn finish(
    args: &MonteCarloArgs,
    spec: &CampaignSpec,
    rows: &[manifest::Row],
) -> anyhow::Result<i32> {
    let title = format!(
        "Monte Carlo, scenario '{}', seed {}, {} runs per point",
        spec.scenario, spec.seed, spec.runs_per_point
    );
    report(
        rows,
        &spec.scenario,
        &args.out_dir,
        &title,
        args.quiet,
        !args.no_plots,
    )
}
