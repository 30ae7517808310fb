//! `campaign --dask`: the scenario campaign's shards flown as Dask tasks (`crate::dask`),
//! merged into --out-dir as `merge-mc` merges scenario campaigns.
use super::{summarise, CampaignArgs};
use campaign::generic::campaign::{declared_in, Campaign, Overrides};
use campaign::generic::config::{CampaignFile, Section};
use campaign::generic::merge;
use std::path::{Path, PathBuf};

/// A scenario campaign's files. A stored shard's `campaign.toml` names the scenario by its
/// path in the task's directory on its worker (`.../scenario/NAME`), another for each shard:
/// it is named as it is here before the shards are merged.
struct Format {
    /// The campaign these options define, its scenario as an absolute path here.
    section: Section,
    /// The scenario's path in a task's directory.
    on_workers: PathBuf,
    store: PathBuf,
}

impl Format {
    fn name_scenario_here(&self, dir: &Path) -> anyhow::Result<()> {
        if std::path::absolute(dir)?.parent() != Some(self.store.as_path()) {
            return Ok(());
        }
        let mut file = CampaignFile::read(dir)?;
        let stored = &mut file.scenario_campaign.scenario;
        if *stored != self.section.scenario && Path::new(stored).ends_with(&self.on_workers) {
            stored.clone_from(&self.section.scenario);
            file.write(dir)?;
        }
        Ok(())
    }
}

impl crate::dask::Format for Format {
    type Merged = merge::Merged;

    fn merge(&self, dirs: &[PathBuf], allow_missing: bool) -> anyhow::Result<merge::Merged> {
        for dir in dirs {
            self.name_scenario_here(dir)?;
        }
        merge::merge(dirs, allow_missing)
    }

    fn is_this(&self, merged: &merge::Merged) -> bool {
        merged.file.scenario_campaign == self.section
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

/// `campaign --dask`: the campaign checked here against the FMUs, its shards flown on the
/// cluster and merged into --out-dir; the summary as a local campaign ends.
pub fn campaign(args: &CampaignArgs, overrides: Overrides, fmu_dir: &Path) -> anyhow::Result<i32> {
    let (campaign, _) = Campaign::load(&args.scenario, overrides, fmu_dir)?;
    let scenario = Path::new(&args.scenario);
    let declared = declared_in(scenario);
    let job = crate::dask::Job {
        subcommand: "campaign",
        scenario_id: "scenario",
        scenario: &args.scenario,
        declaration: (declared != scenario).then_some(declared.as_path()),
        fmu_dir,
        out_dir: &args.out_dir,
        flights: campaign.plan.total(),
        unit: "runs",
        resume: args.resume,
        quiet: args.quiet,
    };
    let format = Format {
        section: Section {
            scenario: campaign.scenario.clone(),
            total_runs: campaign.plan.total(),
            campaign: campaign.declaration.clone(),
        },
        on_workers: PathBuf::from(crate::dask::worker_scenario(&args.scenario)),
        store: std::path::absolute(crate::dask::store_of(&args.out_dir))?,
    };
    crate::dask::campaign(&args.dask, &job, &format)?;
    summarise(&args.out_dir, args.quiet)
}
