//! `harness replay`: one flight of a campaign flown again from its seed, recording every
//! output. The draw is a function of the seed alone and the FMUs are deterministic, so the
//! metrics come out bit for bit as in the manifest.
use crate::definition::Flight;
use crate::dispersion::DispersionRanges;
use crate::flight::{campaign_system, Flyer};
use crate::manifest::{self, Row};
use crate::runner::locate;
use cosim::master::Trajectory;
use std::path::Path;

/// Flies `flight` of a campaign on `scenario` with `ranges`, recording every output.
pub fn fly(
    scenario: &str,
    sets: &[String],
    ranges: &DispersionRanges,
    flight: &Flight,
    fmu_dir: &Path,
) -> anyhow::Result<(Row, Trajectory)> {
    let (system, spec) = campaign_system(scenario, sets, true)?;
    let requirements = lander::scenarios::spec::requirements(scenario)?;
    let mut flyer = Flyer::new(system, spec, fmu_dir)?.with_requirements(requirements)?;
    let row = flyer.fly(flight, ranges);
    Ok((row, flyer.trajectory().clone()))
}

/// A flight replayed from a manifest, with the manifest's row.
#[derive(Debug)]
pub struct Replayed {
    pub recorded: Row,
    pub replayed: Row,
    pub trajectory: Trajectory,
}

impl Replayed {
    /// Same end and every metric bit-identical.
    pub fn matches(&self) -> bool {
        self.recorded.end == self.replayed.end
            && self.recorded.verdict == self.replayed.verdict
            && manifest::metrics_bit_equal(&self.recorded.metrics, &self.replayed.metrics)
            && self.recorded.dispersion == self.replayed.dispersion
    }
}

/// Replays flight `index` of the campaign whose manifest (or directory) is `manifest_path`.
pub fn from_manifest(manifest_path: &Path, index: u64, fmu_dir: &Path) -> anyhow::Result<Replayed> {
    let (manifest_path, config_path) = locate(manifest_path)?;
    let spec = crate::config::CampaignFile::read(&config_path)?
        .campaign
        .to_spec()?;
    let recorded = manifest::read(&manifest_path)?
        .into_iter()
        .find(|r| r.flight.index == index)
        .ok_or_else(|| anyhow::anyhow!("{} has no flight {index}", manifest_path.display()))?;
    anyhow::ensure!(
        recorded.flight == spec.flight(index),
        "{}: flight {index} does not match its campaign definition",
        manifest_path.display()
    );
    let (replayed, trajectory) = fly(
        &spec.scenario,
        &spec.sets,
        &spec.dispersions,
        &recorded.flight,
        fmu_dir,
    )?;
    Ok(Replayed {
        recorded,
        replayed,
        trajectory,
    })
}
