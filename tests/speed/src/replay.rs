//! One FMU at a time, through the harness's loader (so through the C ABI, as any master
//! calls it), fed the inputs it had in the recorded paper flight, timed in batches of
//! consecutive steps.
//!
//! A master cycle is timed per batch of consecutive steps, one clock read pair per batch,
//! which keeps the timer's own cost (tens of nanoseconds, against about a microsecond for a
//! cycle of our FMUs) out of the figures; `fmi2DoStep` alone must be timed call by call, and
//! the timer's cost is measured beside it. Instances are created and initialized outside the timed region, fresh for every
//! pass, so the measured work is the stepping alone.
// std's transcendental functions make the statistics of the timings here, outside any FMU (the
// workspace clippy.toml forbids them for the FMUs' sake).
#![allow(clippy::disallowed_methods)]
use crate::record::{PaperRecord, COMMANDS, GNC, NAVIGATION, PLANT};
use anyhow::{bail, ensure, Context, Result};
use cosim::master::set_parameter;
use fmi_import::{Fmu, Instance, StepStatus, VariableKind};
use std::time::{Duration, Instant};

/// Steps per timed batch: one second of the flight.
pub const BATCH_STEPS: usize = 100;

/// Batches of empty timed regions behind [`timer_cost`]'s median.
pub const TIMER_BATCHES: usize = 1000;

/// Per-step time (s) of each batch of one pass.
pub type BatchMeans = Vec<f64>;

/// How far a plant followed the recorded LanderPlant flight under the same commands.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Agreement {
    /// Every navigation output equal to the recorded one, bit for bit, at every step.
    pub bit_identical: bool,
    /// Largest distance between its `r_nue` and the recorded one over the pass (m).
    pub max_position_error_m: f64,
}

/// `fmi2DoStep` alone, through the same master cycle as [`plant_cycles`]: each step's
/// call is timed on its own (the set and get around it are not), and a batch's mean is the
/// sum of its steps' times over its length. Each clock read pair adds the timer's own cost,
/// which [`timer_cost`] measures so it can be taken off.
pub fn plant_steps(
    fmu: &Fmu,
    record: &PaperRecord,
    steps: usize,
    batch: usize,
) -> Result<(BatchMeans, Agreement)> {
    ensure!(batch > 0, "a batch holds at least one step");
    let mut plant = Unit::start(fmu, PLANT, record, &COMMANDS, &record.commands[0])?;
    let output_vrs = value_references(&plant.instance, &NAVIGATION)?;
    let mut outputs = vec![[0.0; 14]; steps];
    let mut means = Vec::with_capacity(steps.div_ceil(batch));
    for first in (0..steps).step_by(batch) {
        let range = first..(first + batch).min(steps);
        let mut stepping = Duration::ZERO;
        for k in range.clone() {
            plant.set(&record.commands[k])?;
            let started = Instant::now();
            plant.step(record, k)?;
            stepping += started.elapsed();
            plant.instance.get_real(&output_vrs, &mut outputs[k])?;
        }
        means.push(stepping.as_secs_f64() / range.len() as f64);
    }
    Ok((means, agreement(record, &outputs)))
}

/// What one timed region costs with nothing in it (s): the median over `batches` batches
/// of `batch` empty regions, accumulated as [`plant_steps`] accumulates its steps.
pub fn timer_cost(batches: usize, batch: usize) -> f64 {
    let mut means: Vec<f64> = (0..batches)
        .map(|_| {
            let mut total = Duration::ZERO;
            for _ in 0..batch {
                let started = Instant::now();
                total += std::hint::black_box(started).elapsed();
            }
            total.as_secs_f64() / batch as f64
        })
        .collect();
    means.sort_by(f64::total_cmp);
    means.get(means.len() / 2).copied().unwrap_or(0.0)
}

/// What a master does with the plant at every communication point: set the 4 commands,
/// `fmi2DoStep`, get the 14 navigation outputs. With the recorded commands, LanderPlant
/// must retrace the recorded flight exactly; the returned [`Agreement`] says whether it did.
pub fn plant_cycles(
    fmu: &Fmu,
    record: &PaperRecord,
    steps: usize,
    batch: usize,
) -> Result<(BatchMeans, Agreement)> {
    ensure!(batch > 0, "a batch holds at least one step");
    let mut plant = Unit::start(fmu, PLANT, record, &COMMANDS, &record.commands[0])?;
    let output_vrs = value_references(&plant.instance, &NAVIGATION)?;
    // Written by the timed loop in place of a master's own buffers, compared afterwards.
    let mut outputs = vec![[0.0; 14]; steps];
    let mut means = Vec::with_capacity(steps.div_ceil(batch));
    for first in (0..steps).step_by(batch) {
        let range = first..(first + batch).min(steps);
        let started = Instant::now();
        for k in range.clone() {
            plant.set(&record.commands[k])?;
            plant.step(record, k)?;
            plant.instance.get_real(&output_vrs, &mut outputs[k])?;
        }
        means.push(started.elapsed().as_secs_f64() / range.len() as f64);
    }
    Ok((means, agreement(record, &outputs)))
}

/// What a master does with the controller at every communication point: set the 14
/// navigation inputs, get the 4 commands (direct feedthrough: this evaluates the
/// controller), `fmi2DoStep` (commits the sample; every tenth step of the descent re-solves
/// the guidance polynomial). The commands must equal the recorded ones bit for bit, which
/// proves the replay flew the paper's phases and not some other path.
pub fn gnc_cycles(
    fmu: &Fmu,
    record: &PaperRecord,
    steps: usize,
    batch: usize,
) -> Result<BatchMeans> {
    ensure!(batch > 0, "a batch holds at least one step");
    let mut gnc = Unit::start(fmu, GNC, record, &NAVIGATION, record.gnc_inputs(0))?;
    let command_vrs = value_references(&gnc.instance, &COMMANDS)?;
    let mut commands = vec![[0.0; 4]; steps];
    let mut means = Vec::with_capacity(steps.div_ceil(batch));
    for first in (0..steps).step_by(batch) {
        let range = first..(first + batch).min(steps);
        let started = Instant::now();
        for k in range.clone() {
            gnc.set(record.gnc_inputs(k))?;
            gnc.instance.get_real(&command_vrs, &mut commands[k])?;
            gnc.step(record, k)?;
        }
        means.push(started.elapsed().as_secs_f64() / range.len() as f64);
    }
    for (k, (replayed, recorded)) in commands.iter().zip(&record.commands).enumerate() {
        let same = replayed
            .iter()
            .zip(recorded)
            .all(|(a, b)| a.to_bits() == b.to_bits());
        if !same {
            bail!(
                "LanderGnc replayed at t = {} s commanded {replayed:?}, the closed loop {recorded:?}: \
                 the replay does not reproduce the paper flight",
                record.times[k]
            );
        }
    }
    Ok(means)
}

/// An initialized instance with the value references of its inputs.
struct Unit {
    instance: Instance,
    input_vrs: Vec<u32>,
}

impl Unit {
    /// Instantiates, applies the scenario's parameters of `role`, and initializes with
    /// `initial_inputs` set in initialization mode, as the harness's initial exchange does.
    fn start(
        fmu: &Fmu,
        role: &str,
        record: &PaperRecord,
        inputs: &[&str],
        initial_inputs: &[f64],
    ) -> Result<Self> {
        let mut instance = fmu.instantiate(role, false)?;
        let input_vrs = value_references(&instance, inputs)?;
        instance.setup_experiment(None, record.system.start_time, None)?;
        for (name, value) in record.parameters(role) {
            set_parameter(&mut instance, name, value)
                .with_context(|| format!("{role}: parameter {name}"))?;
        }
        instance.enter_initialization_mode()?;
        instance.set_real(&input_vrs, initial_inputs)?;
        instance.exit_initialization_mode()?;
        Ok(Self {
            instance,
            input_vrs,
        })
    }

    fn set(&mut self, values: &[f64]) -> Result<()> {
        self.instance.set_real(&self.input_vrs, values)?;
        Ok(())
    }

    /// The step from `t_k` the harness took: the scenario's step size, or the remainder to
    /// the stop time for the last one.
    fn step(&mut self, record: &PaperRecord, k: usize) -> Result<()> {
        let time = record.times[k];
        let h = if k + 1 == record.steps() {
            record.times[k + 1] - time
        } else {
            record.step_size_s()
        };
        match self.instance.do_step(time, h)? {
            StepStatus::Complete(_) => Ok(()),
            StepStatus::Discarded { .. } | StepStatus::Terminated { .. } => bail!(
                "{} discarded the step at t = {time} s of the replayed flight",
                self.instance.name()
            ),
        }
    }
}

fn value_references(instance: &Instance, names: &[&str]) -> Result<Vec<u32>> {
    names
        .iter()
        .map(|name| {
            let variable = instance.variable(name)?;
            ensure!(
                variable.kind == VariableKind::Real,
                "{}: {name} is {:?}, not Real",
                instance.name(),
                variable.kind
            );
            Ok(variable.value_reference)
        })
        .collect()
}

/// Compares a replayed plant's outputs after step `k` with the recorded ones at `t_{k+1}`.
fn agreement(record: &PaperRecord, outputs: &[[f64; 14]]) -> Agreement {
    let mut bit_identical = true;
    let mut max_position_error_m: f64 = 0.0;
    for (replayed, recorded) in outputs.iter().zip(&record.navigation[1..]) {
        bit_identical &= replayed
            .iter()
            .zip(recorded)
            .all(|(a, b)| a.to_bits() == b.to_bits());
        let error_m = (0..3)
            .map(|i| (replayed[i] - recorded[i]).powi(2))
            .sum::<f64>()
            .sqrt();
        // f64::max drops a NaN; a plant that produced one must show it.
        max_position_error_m = if error_m.is_nan() || max_position_error_m.is_nan() {
            f64::NAN
        } else {
            max_position_error_m.max(error_m)
        };
    }
    Agreement {
        bit_identical,
        max_position_error_m,
    }
}
