//! Shards of one scenario campaign joined into one manifest, every row checked against the
//! campaign's definition: the same definition and FMUs in every shard, each row the run its
//! index says, no index twice, none missing.
use crate::generic::config::CampaignFile;
use crate::generic::manifest::{Layout, Row};
use crate::generic::plan::Plan;
use crate::runner::locate;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The merged campaign: its file (no shard, `merged_from` the inputs), columns and rows.
pub struct Merged {
    pub file: CampaignFile,
    pub layout: Layout,
    pub rows: Vec<Row>,
    pub missing: Vec<u64>,
}

/// Reads and checks the shard directories (or their manifests) `inputs`. Missing runs are
/// an error unless `allow_missing` (they are listed in [`Merged::missing`]).
pub fn merge(inputs: &[PathBuf], allow_missing: bool) -> anyhow::Result<Merged> {
    let mut first: Option<(CampaignFile, Layout, Plan)> = None;
    let mut rows: BTreeMap<u64, Row> = BTreeMap::new();
    let mut duplicates = Vec::new();
    for input in inputs {
        let (manifest_path, config_path) = locate(input)?;
        let dir = config_path.parent().unwrap_or(Path::new("."));
        let file = CampaignFile::read(dir)?;
        let layout = Layout::of_manifest(&manifest_path)?;
        if let Some((f, l, _)) = &first {
            anyhow::ensure!(
                f.scenario_campaign == file.scenario_campaign && *l == layout,
                "{} holds another campaign than {} (scenario, seed, runs or [campaign] differ)",
                input.display(),
                inputs[0].display()
            );
            anyhow::ensure!(
                f.versions.fmu == file.versions.fmu,
                "{} ran other FMUs than {} (model name or GUID differ)",
                input.display(),
                inputs[0].display()
            );
        } else {
            let plan = Plan::new(&file.scenario_campaign.campaign)
                .map_err(|p| anyhow::anyhow!("{}: {}", config_path.display(), p.join("; ")))?;
            first = Some((file.clone(), layout.clone(), plan));
        }
        let plan = first.as_ref().map(|f| &f.2).expect("set above");
        let shard = file.shard();
        let (found, _) = layout.read_complete(&manifest_path)?;
        for row in found {
            let index = row.id.index;
            anyhow::ensure!(
                index < plan.total()
                    && row.id == plan.run_id(index)
                    && index % shard.n == shard.k - 1,
                "{} run {index} is not run {index} of shard {shard} of its campaign",
                manifest_path.display()
            );
            if rows.insert(index, row).is_some() {
                duplicates.push(index);
            }
        }
    }
    let (mut file, layout, plan) = first.ok_or_else(|| anyhow::anyhow!("nothing to merge"))?;
    anyhow::ensure!(
        duplicates.is_empty(),
        "{} runs appear in two shards: {:?}",
        duplicates.len(),
        &duplicates[..duplicates.len().min(10)]
    );
    let missing: Vec<u64> = (0..plan.total())
        .filter(|i| !rows.contains_key(i))
        .collect();
    anyhow::ensure!(
        allow_missing || missing.is_empty(),
        "{} of {} runs are missing (a shard not merged, or not finished): {:?}",
        missing.len(),
        plan.total(),
        &missing[..missing.len().min(10)]
    );
    file.shard = None;
    file.execution = crate::config::Execution {
        workers: None,
        merged_from: inputs.iter().map(|p| p.display().to_string()).collect(),
    };
    Ok(Merged {
        file,
        layout,
        rows: rows.into_values().collect(),
        missing,
    })
}

/// Writes the merged campaign into `out_dir`: `manifest.csv` sorted by index, `campaign.toml`.
pub fn write(merged: &Merged, out_dir: &Path) -> anyhow::Result<PathBuf> {
    std::fs::create_dir_all(out_dir)?;
    merged.file.write(out_dir)?;
    let path = out_dir.join(crate::manifest::FILE_NAME);
    merged.layout.write_sorted(&path, merged.rows.clone())?;
    Ok(path)
}
