//! Running a scenario campaign (or one shard of it) in parallel ([`crate::parallel`], as
//! `monte-carlo` does), resumably, and replaying one run. Rows are appended to
//! `manifest.csv` as they finish and the manifest is rewritten sorted by index at the end, so
//! it does not depend on workers, shards (after merging) or interruptions.
use crate::config::{self, Execution, ShardSection};
use crate::definition::Shard;
use crate::generic::campaign::{Campaign, Overrides};
use crate::generic::config::{CampaignFile, Section};
use crate::generic::manifest::{self, Row, Writer};
use anyhow::Context;
use cosim::master::Trajectory;
use cosim::supervise::Runner;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// How to run; none of this changes a run's result.
#[derive(Debug, Clone)]
pub struct RunOptions {
    pub fmu_dir: PathBuf,
    pub out_dir: PathBuf,
    pub workers: usize,
    pub shard: Shard,
    /// Keep the finished rows of the campaign in `out_dir` and run only the others.
    pub resume: bool,
    /// Show a progress bar (it still hides itself when stderr is not a terminal).
    pub progress: bool,
}

/// What a campaign invocation did.
#[derive(Debug, Clone)]
pub struct Outcome {
    pub manifest: PathBuf,
    /// Runs run now, and rows kept from before (resume).
    pub ran: u64,
    pub kept: u64,
}

impl Campaign {
    fn section(&self) -> Section {
        Section {
            scenario: self.scenario.clone(),
            total_runs: self.plan.total(),
            campaign: self.declaration.clone(),
        }
    }
}

/// Runs `options.shard` of the campaign of `scenario` into `options.out_dir`.
pub fn run(
    scenario: &str,
    overrides: Overrides,
    options: &RunOptions,
) -> anyhow::Result<(Campaign, Outcome)> {
    anyhow::ensure!(options.workers > 0, "--workers must be at least 1");
    let (campaign, first) = Campaign::load(scenario, overrides, &options.fmu_dir)?;
    let manifest_path = options.out_dir.join(manifest::FILE_NAME);
    let shard = options.shard;
    let total = campaign.plan.total();
    let kept_rows = if options.resume {
        finished_rows(&campaign, options, &manifest_path)?
    } else {
        None
    };
    std::fs::create_dir_all(&options.out_dir)
        .with_context(|| format!("creating {}", options.out_dir.display()))?;
    CampaignFile {
        scenario_campaign: campaign.section(),
        shard: (!shard.is_whole()).then_some(ShardSection {
            k: shard.k,
            n: shard.n,
        }),
        execution: Execution {
            workers: Some(options.workers),
            merged_from: Vec::new(),
        },
        versions: config::versions(&first),
    }
    .write(&options.out_dir)?;
    let layout = &campaign.layout;
    let (mut writer, done) = match kept_rows {
        None => (Writer::create(layout, &manifest_path)?, BTreeSet::new()),
        Some((rows, bytes)) => {
            let done: BTreeSet<u64> = rows.iter().map(|r| r.id.index).collect();
            (Writer::append(layout, &manifest_path, bytes)?, done)
        }
    };
    let positions = shard.len(total);
    let progress = crate::runner::progress_bar(
        positions.saturating_sub(done.len() as u64),
        options.progress,
        "runs",
    );
    let load = || -> anyhow::Result<Runner> {
        Ok(Runner::new(campaign.system.clone(), &options.fmu_dir)?)
    };
    let work = crate::parallel::Work {
        workers: options.workers,
        shard,
        total,
        done: &done,
    };
    let written = crate::parallel::run(
        work,
        (first, Trajectory::default()),
        &|| Ok((load()?, Trajectory::default())),
        &|(runner, trajectory), index| {
            let row = campaign.fly(runner, campaign.plan.run_id(index), trajectory);
            let failed = row.verdict == manifest::ERROR;
            (row, failed)
        },
        |row| {
            writer.write(&row)?;
            progress.inc(1);
            Ok(())
        },
    );
    progress.finish_and_clear();
    let ran = written?;
    drop(writer);
    let (rows, _) = layout.read_complete(&manifest_path)?;
    anyhow::ensure!(
        rows.len() as u64 == positions,
        "{} holds {} rows, the campaign (shard {shard}) {positions}",
        manifest_path.display(),
        rows.len()
    );
    layout.write_sorted(&manifest_path, rows)?;
    Ok((
        campaign,
        Outcome {
            manifest: manifest_path,
            ran,
            kept: done.len() as u64,
        },
    ))
}

/// For `--resume`: the whole rows of this campaign and shard already in `out_dir`, and the
/// bytes holding them; `None` when no campaign is there yet.
fn finished_rows(
    campaign: &Campaign,
    options: &RunOptions,
    manifest_path: &Path,
) -> anyhow::Result<Option<(Vec<Row>, u64)>> {
    if !manifest_path.exists() || !options.out_dir.join(config::FILE_NAME).exists() {
        return Ok(None);
    }
    let file = CampaignFile::read(&options.out_dir)?;
    anyhow::ensure!(
        file.scenario_campaign == campaign.section(),
        "--resume: {} holds another campaign (scenario, seed, runs or [campaign] differ)",
        options.out_dir.display()
    );
    anyhow::ensure!(
        file.shard() == options.shard,
        "--resume: {} is shard {}, not {}",
        options.out_dir.display(),
        file.shard(),
        options.shard
    );
    let (rows, bytes) = campaign.layout.read_complete(manifest_path)?;
    let mut seen = BTreeSet::new();
    for row in &rows {
        let index = row.id.index;
        anyhow::ensure!(
            index < campaign.plan.total() && row.id == campaign.plan.run_id(index),
            "--resume: {} run {index} is not this campaign's",
            manifest_path.display()
        );
        anyhow::ensure!(
            seen.insert(index),
            "--resume: {} holds run {index} twice",
            manifest_path.display()
        );
    }
    Ok(Some((rows, bytes)))
}

/// Run `index` flown again: its row (from the campaign's own recording) and its trajectory
/// with every output (a second run of the same inputs: recording does not change a run).
pub fn replay(
    scenario: &str,
    overrides: Overrides,
    index: u64,
    fmu_dir: &Path,
) -> anyhow::Result<(Campaign, Row, Trajectory)> {
    let (campaign, mut runner) = Campaign::load(scenario, overrides, fmu_dir)?;
    anyhow::ensure!(
        index < campaign.plan.total(),
        "--replay {index}: the campaign has runs 0 to {}",
        campaign.plan.total() - 1
    );
    let id = campaign.plan.run_id(index);
    let mut trajectory = Trajectory::default();
    let row = campaign.fly(&mut runner, id, &mut trajectory);
    let mut system = campaign.system.clone();
    system.record = None;
    let mut everything = Runner::new(system, fmu_dir)?;
    let again = campaign.fly(&mut everything, id, &mut trajectory);
    anyhow::ensure!(
        again.inputs == row.inputs && again.end == row.end,
        "run {index} ended otherwise when every output was recorded"
    );
    Ok((campaign, row, trajectory))
}
