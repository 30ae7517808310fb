//! `harness merge-mc`: shards of one campaign (from an array job, say) into one manifest,
//! with every row checked against the campaign definition: same definition and FMUs in
//! every shard, every row the flight its index says, no index twice, none missing.
use crate::config::{self, CampaignFile};
use crate::definition::CampaignSpec;
use crate::manifest::{self, Row};
use crate::runner::locate;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// At most this many indices are listed in an error.
const LIST: usize = 10;

fn list(indices: &[u64]) -> String {
    let shown: Vec<String> = indices.iter().take(LIST).map(u64::to_string).collect();
    let more = indices.len().saturating_sub(LIST);
    if more > 0 {
        format!("{} and {more} more", shown.join(", "))
    } else {
        shown.join(", ")
    }
}

/// The merged campaign: its definition, file and rows sorted by index.
#[derive(Debug)]
pub struct Merged {
    pub spec: CampaignSpec,
    pub file: CampaignFile,
    pub rows: Vec<Row>,
    pub missing: Vec<u64>,
}

/// Reads and checks `inputs` (campaign directories or manifests, each with its
/// `campaign.toml` beside it). Missing flights are an error unless `allow_missing`.
pub fn merge(inputs: &[PathBuf], allow_missing: bool) -> anyhow::Result<Merged> {
    anyhow::ensure!(!inputs.is_empty(), "nothing to merge");
    let mut first: Option<(PathBuf, CampaignFile, CampaignSpec)> = None;
    let mut rows: BTreeMap<u64, (Row, usize)> = BTreeMap::new();
    let mut duplicates = Vec::new();
    for (source, input) in inputs.iter().enumerate() {
        let (manifest_path, config_path) = locate(input)?;
        let file = CampaignFile::read(&config_path)?;
        let spec = file.campaign.to_spec()?;
        match &first {
            None => first = Some((config_path.clone(), file.clone(), spec.clone())),
            Some((first_path, first_file, first_spec)) => {
                anyhow::ensure!(
                    spec == *first_spec,
                    "{} defines another campaign than {} (seed, scenario, grid, laws, runs or \
                     dispersions differ)",
                    config_path.display(),
                    first_path.display()
                );
                anyhow::ensure!(
                    file.versions.fmu == first_file.versions.fmu,
                    "{} flew other FMUs than {} (model name or GUID differ)",
                    config_path.display(),
                    first_path.display()
                );
            }
        }
        let shard = file.shard();
        for row in manifest::read(&manifest_path)? {
            let index = row.flight.index;
            let at = || format!("{} flight {index}", manifest_path.display());
            anyhow::ensure!(
                index < spec.flight_count(),
                "{}: the campaign has {} flights",
                at(),
                spec.flight_count()
            );
            let expected = spec.flight(index);
            anyhow::ensure!(
                row.flight.run == expected.run
                    && row.flight.run_seed == expected.run_seed
                    && row.flight.law == expected.law
                    && row.flight.phi_cmd_deg.to_bits() == expected.phi_cmd_deg.to_bits(),
                "{}: run, seed, law or phi_cmd is not the campaign's flight {index}",
                at()
            );
            anyhow::ensure!(
                index % shard.n == shard.k - 1,
                "{}: not in shard {shard}",
                at()
            );
            if let Some((_, earlier)) = rows.get(&index) {
                duplicates.push((index, *earlier, source));
            } else {
                rows.insert(index, (row, source));
            }
        }
    }
    let (_, mut file, spec) = first.ok_or_else(|| anyhow::anyhow!("nothing to merge"))?;
    if !duplicates.is_empty() {
        let (index, a, b) = duplicates[0];
        anyhow::bail!(
            "{} flights appear twice (first: flight {index} in {} and {}); indices: {}",
            duplicates.len(),
            inputs[a].display(),
            inputs[b].display(),
            list(&duplicates.iter().map(|d| d.0).collect::<Vec<_>>())
        );
    }
    let missing: Vec<u64> = (0..spec.flight_count())
        .filter(|i| !rows.contains_key(i))
        .collect();
    anyhow::ensure!(
        allow_missing || missing.is_empty(),
        "{} of {} flights are missing (a shard not merged, or not finished): {}",
        missing.len(),
        spec.flight_count(),
        list(&missing)
    );
    file.shard = None;
    file.execution = config::Execution {
        workers: None,
        merged_from: inputs.iter().map(|p| p.display().to_string()).collect(),
    };
    Ok(Merged {
        spec,
        file,
        rows: rows.into_values().map(|(row, _)| row).collect(),
        missing,
    })
}

/// Writes a merged campaign into `out_dir`: `manifest.csv` sorted by index, `campaign.toml`.
pub fn write(merged: &Merged, out_dir: &Path) -> anyhow::Result<PathBuf> {
    std::fs::create_dir_all(out_dir)?;
    merged.file.write(&out_dir.join(config::FILE_NAME))?;
    let path = out_dir.join(manifest::FILE_NAME);
    let mut writer = manifest::Writer::create(&path)?;
    for row in &merged.rows {
        writer.write(row)?;
    }
    Ok(path)
}
