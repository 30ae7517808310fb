//! LanderPlant against the same equations packaged with pythonfmu, in one process, through
//! the same loader calls, fed the same recorded commands.
//!
//! pythonfmu's binary needs libpython preloaded, so this runs in a child process started
//! with that environment ([`crate::python::embedding_env`]); measuring our plant in the same
//! child, interleaved pass by pass with the Python one, makes the ratio a comparison under
//! the same conditions rather than across two processes.
use crate::record::PaperRecord;
use crate::replay::{
    plant_cycles, plant_steps, timer_cost, BatchMeans, BATCH_STEPS, TIMER_BATCHES,
};
use anyhow::{ensure, Result};
use fmi_import::Fmu;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// One plant's figures.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct PlantFigures {
    /// Per-step time of `fmi2DoStep` alone (s), per batch of [`BATCH_STEPS`].
    pub step_means: BatchMeans,
    /// Per-step time of set 4 + `fmi2DoStep` + get 14 (s), per batch of [`BATCH_STEPS`].
    pub cycle_means: BatchMeans,
    /// Whether every pass retraced the recorded LanderPlant flight bit for bit.
    pub bit_identical: bool,
    /// Largest distance from the recorded LanderPlant position over every pass (m).
    pub max_position_error_m: f64,
}

impl PlantFigures {
    fn measure(&mut self, fmu: &Fmu, record: &PaperRecord, steps: usize) -> Result<()> {
        let first_pass = self.cycle_means.is_empty();
        let (step_means, step_agreement) = plant_steps(fmu, record, steps, BATCH_STEPS)?;
        let (cycle_means, cycle_agreement) = plant_cycles(fmu, record, steps, BATCH_STEPS)?;
        for agreement in [step_agreement, cycle_agreement] {
            ensure!(
                agreement.max_position_error_m.is_finite(),
                "{} left the finite numbers under the paper's commands",
                fmu.model_name()
            );
            self.max_position_error_m = self
                .max_position_error_m
                .max(agreement.max_position_error_m);
        }
        let identical = step_agreement.bit_identical && cycle_agreement.bit_identical;
        self.bit_identical = identical && (first_pass || self.bit_identical);
        self.step_means.extend(step_means);
        self.cycle_means.extend(cycle_means);
        Ok(())
    }
}

/// Both plants' figures.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Duel {
    pub ours: PlantFigures,
    pub python: PlantFigures,
    /// Communication steps per pass.
    pub steps: usize,
    /// The timer's own cost in each per-call `fmi2DoStep` time, measured in the child (s).
    pub timer_cost_s: f64,
}

/// `ours_passes` passes of LanderPlant and `python_passes` of the pythonfmu plant over the
/// first `steps` steps of `record`, interleaved.
pub fn run(
    ours: &Path,
    python: &Path,
    record: &PaperRecord,
    steps: usize,
    ours_passes: usize,
    python_passes: usize,
) -> Result<Duel> {
    let ours_fmu = Fmu::load(ours)?;
    let python_fmu = Fmu::load(python)?;
    let mut duel = Duel {
        ours: PlantFigures::default(),
        python: PlantFigures::default(),
        steps,
        timer_cost_s: timer_cost(TIMER_BATCHES, BATCH_STEPS),
    };
    for pass in 0..ours_passes.max(python_passes) {
        if pass < ours_passes {
            duel.ours.measure(&ours_fmu, record, steps)?;
        }
        if pass < python_passes {
            duel.python.measure(&python_fmu, record, steps)?;
        }
    }
    ensure!(
        duel.ours.bit_identical,
        "LanderPlant did not retrace the recorded flight under its own commands"
    );
    Ok(duel)
}
