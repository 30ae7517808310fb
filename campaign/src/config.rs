//! `campaign.toml`: the campaign definition (enough to re-create every flight), the shard,
//! how it was executed, and the versions of the harness and the FMUs it flew.
use crate::definition::{CampaignSpec, Shard};
use crate::dispersion::DispersionRanges;
use anyhow::Context;
use lander::laws::Law;
use std::path::Path;

pub const FILE_NAME: &str = "campaign.toml";

#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CampaignFile {
    pub campaign: CampaignSection,
    /// Absent for a whole (or merged) campaign.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shard: Option<ShardSection>,
    pub execution: Execution,
    pub versions: Versions,
}

#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CampaignSection {
    pub scenario: String,
    pub seed: u64,
    pub phi_cmd_deg: Vec<f64>,
    pub laws: Vec<String>,
    pub runs_per_point: u64,
    /// Derived (phi_cmd count x law count x runs per point), for the reader's benefit.
    pub flights: u64,
    pub dispersions: DispersionRanges,
    /// The campaign's `--set` overrides of the scenario, in the order given.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub sets: Vec<String>,
}

#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShardSection {
    pub k: u64,
    pub n: u64,
}

#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Execution {
    /// Worker threads of this run (absent for a merge); results do not depend on it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub workers: Option<usize>,
    /// Shard directories or manifests merged into this one (empty unless merged).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub merged_from: Vec<String>,
}

#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Versions {
    pub harness: String,
    pub fmu: Vec<FmuVersion>,
}

#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FmuVersion {
    pub instance: String,
    pub model_name: String,
    pub guid: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub generation_tool: Option<String>,
}

impl CampaignSection {
    pub fn from_spec(spec: &CampaignSpec) -> Self {
        Self {
            scenario: spec.scenario.clone(),
            seed: spec.seed,
            phi_cmd_deg: spec.phi_cmd_deg.clone(),
            laws: spec.laws.iter().map(|l| l.name().to_owned()).collect(),
            runs_per_point: spec.runs_per_point,
            flights: spec.flight_count(),
            dispersions: spec.dispersions.clone(),
            sets: spec.sets.clone(),
        }
    }

    pub fn to_spec(&self) -> anyhow::Result<CampaignSpec> {
        // Checked against the GNC FMU's laws when the campaign loads it.
        let laws = self.laws.iter().map(|name| Law::named(name)).collect();
        let spec = CampaignSpec {
            scenario: self.scenario.clone(),
            seed: self.seed,
            phi_cmd_deg: self.phi_cmd_deg.clone(),
            laws,
            runs_per_point: self.runs_per_point,
            dispersions: self.dispersions.clone(),
            sets: self.sets.clone(),
        };
        spec.validate().map_err(anyhow::Error::msg)?;
        anyhow::ensure!(
            spec.flight_count() == self.flights,
            "flights = {} does not match the definition ({})",
            self.flights,
            spec.flight_count()
        );
        Ok(spec)
    }
}

impl CampaignFile {
    pub fn shard(&self) -> Shard {
        self.shard
            .map(|s| Shard { k: s.k, n: s.n })
            .unwrap_or(Shard::WHOLE)
    }

    pub fn write(&self, path: &Path) -> anyhow::Result<()> {
        let text = format!(
            "# Monte Carlo campaign written by `harness monte-carlo` (re-run or replay any \
             flight from this definition).\n{}",
            toml::to_string_pretty(self)?
        );
        std::fs::write(path, text).with_context(|| format!("writing {}", path.display()))
    }

    pub fn read(path: &Path) -> anyhow::Result<Self> {
        let text =
            std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
        toml::from_str(&text).with_context(|| format!("parsing {}", path.display()))
    }
}

/// The versions of the harness and of the FMUs of a loaded simulation.
pub fn versions(simulation: &cosim::supervise::Runner) -> Versions {
    Versions {
        harness: env!("CARGO_PKG_VERSION").to_owned(),
        fmu: simulation
            .system()
            .instances
            .iter()
            .enumerate()
            .map(|(index, instance)| {
                let (_, md) = simulation.description(index);
                FmuVersion {
                    instance: instance.name.clone(),
                    model_name: md.model_name.clone(),
                    guid: md.guid.clone(),
                    generation_tool: md.generation_tool.clone(),
                }
            })
            .collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_campaign_file_round_trips() {
        let spec = CampaignSpec {
            scenario: "paper".into(),
            seed: u64::MAX >> 1,
            phi_cmd_deg: vec![0.0, 0.1 + 0.2, 150.0],
            laws: vec![Law::DECOUPLED, Law::COUPLED],
            runs_per_point: 3,
            dispersions: DispersionRanges::default(),
            sets: vec!["plant.m0=850".into(), "gnc.rate_shaping_margin=0.5".into()],
        };
        let file = CampaignFile {
            campaign: CampaignSection::from_spec(&spec),
            shard: Some(ShardSection { k: 2, n: 3 }),
            execution: Execution {
                workers: Some(2),
                merged_from: vec![],
            },
            versions: Versions {
                harness: "0".into(),
                fmu: vec![],
            },
        };
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(FILE_NAME);
        file.write(&path).unwrap();
        let back = CampaignFile::read(&path).unwrap();
        assert_eq!(back, file);
        assert_eq!(back.campaign.to_spec().unwrap(), spec);
        assert_eq!(back.shard(), Shard { k: 2, n: 3 });
    }

    #[test]
    fn an_inconsistent_flight_count_is_refused() {
        let mut section = CampaignSection::from_spec(&CampaignSpec {
            scenario: "paper".into(),
            seed: 1,
            phi_cmd_deg: vec![0.0],
            laws: vec![Law::DECOUPLED],
            runs_per_point: 3,
            dispersions: DispersionRanges::default(),
            sets: Vec::new(),
        });
        section.flights = 4;
        assert!(section.to_spec().is_err());
    }
}
