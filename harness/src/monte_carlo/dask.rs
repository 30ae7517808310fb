//! `monte-carlo --dask`: the campaign's shards flown as Dask tasks (`crate::dask`), merged
//! here into --out-dir as `merge-mc` merges them.
use super::{report, MonteCarloArgs};
use campaign::{manifest, merge, CampaignSpec};
use std::path::Path;

/// `monte-carlo --dask`: the shards flown on the cluster, merged into --out-dir as `merge-mc`
/// merges them, the scenario named as the user named it.
pub fn campaign(args: &MonteCarloArgs, spec: &CampaignSpec, fmu_dir: &Path) -> anyhow::Result<i32> {
    let mut on_workers = spec.clone();
    on_workers.scenario = crate::dask::worker_scenario(&spec.scenario);
    let same_campaign = |dir: &Path| -> anyhow::Result<()> {
        let stored = merge::merge(&[dir.to_owned()], true)?.spec;
        anyhow::ensure!(
            stored == on_workers,
            "--resume: {} holds shards of another campaign than these options: without \
             --resume the campaign starts again",
            dir.parent().unwrap_or(dir).display()
        );
        Ok(())
    };
    // Resumed after the merge: the campaign in --out-dir is this one, whole.
    let merged_before = args.resume
        && !crate::dask::store_of(&args.out_dir).exists()
        && args.out_dir.join(manifest::FILE_NAME).exists();
    if merged_before {
        if let Ok(done) = merge::merge(std::slice::from_ref(&args.out_dir), false) {
            if done.spec == *spec {
                println!(
                    "resumed: the campaign in {} is complete",
                    args.out_dir.display()
                );
                return finish(args, spec, &done.rows);
            }
        }
    }
    let job = crate::dask::Job {
        subcommand: "monte-carlo",
        scenario_id: "scenario",
        scenario: &spec.scenario,
        fmu_dir,
        out_dir: &args.out_dir,
        flights: spec.flight_count(),
        resume: args.resume,
        quiet: args.quiet,
    };
    let shards = crate::dask::fly(&args.dask, &job, &same_campaign)?;
    let mut merged = merge::merge(&shards.dirs, false)?;
    anyhow::ensure!(
        merged.spec == on_workers,
        "the Dask workers flew another campaign than these options define"
    );
    merged.spec.scenario = spec.scenario.clone();
    merged.file.campaign.scenario = spec.scenario.clone();
    merged.file.execution.merged_from = shards.provenance.clone();
    let path = merge::write(&merged, &args.out_dir)?;
    shards.remove()?;
    println!(
        "{} flights from {} Dask shards -> {}",
        merged.rows.len(),
        merged.file.execution.merged_from.len(),
        path.display()
    );
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
