//! The `campaign.toml` of a scenario campaign: the scenario, its `[campaign]` table as run
//! (with the command line's seed and runs), the shard, how it ran and the FMUs' versions.
//! Its table `[scenario_campaign]` tells it from a `harness monte-carlo` campaign's file.
use crate::config::{Execution, ShardSection, Versions, FILE_NAME};
use crate::definition::Shard;
use anyhow::Context;
use cosim::system::campaign_table::Declaration;
use std::path::Path;

#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CampaignFile {
    pub scenario_campaign: Section,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shard: Option<ShardSection>,
    pub execution: Execution,
    pub versions: Versions,
}

/// What defines every run: equal sections, equal runs.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Section {
    /// The scenario file, as an absolute path.
    pub scenario: String,
    /// Runs in the whole campaign (all sweep points).
    pub total_runs: u64,
    pub campaign: Declaration,
}

impl CampaignFile {
    pub fn shard(&self) -> Shard {
        self.shard
            .map_or(Shard::WHOLE, |s| Shard { k: s.k, n: s.n })
    }

    pub fn write(&self, dir: &Path) -> anyhow::Result<()> {
        let path = dir.join(FILE_NAME);
        let text = format!(
            "# Scenario campaign written by `harness campaign` (replay any run with `harness \
             campaign SCENARIO --replay INDEX`).\n{}",
            toml::to_string_pretty(self)?
        );
        std::fs::write(&path, text).with_context(|| format!("writing {}", path.display()))
    }

    pub fn read(dir: &Path) -> anyhow::Result<Self> {
        let path = dir.join(FILE_NAME);
        let text = std::fs::read_to_string(&path)
            .with_context(|| format!("reading {}", path.display()))?;
        toml::from_str(&text).with_context(|| format!("parsing {}", path.display()))
    }
}

/// Whether `dir` holds a scenario campaign (rather than a `monte-carlo` one, or none).
pub fn is_scenario_campaign(dir: &Path) -> bool {
    std::fs::read_to_string(dir.join(FILE_NAME))
        .ok()
        .and_then(|text| text.parse::<toml::Table>().ok())
        .is_some_and(|table| table.contains_key("scenario_campaign"))
}
