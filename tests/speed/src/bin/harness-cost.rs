//! What the harness's master costs on top of the FMUs, in instructions (callgrind), for the
//! paper flight (172 s, 17,200 steps):
//!
//! - `direct`: both FMUs driven through the loader (`fmi_import::Fmu`/`Instance`, C ABI) by a
//!   hand-written Gauss-Seidel loop with the harness's exchange: per step, set the
//!   controller's 14 inputs, get its 4 commands, set the plant's 4 inputs, step both, get the
//!   plant's 14 outputs. Nothing recorded. This is the floor any master pays.
//! - `master`: `Simulation::run` on the same scenario, every output of both FMUs recorded in
//!   memory (a `Trajectory`).
//! - `master-csv`, `master-arrow`: the same, then the trajectory written to a file.
//! - `campaign`: Monte Carlo flights as a campaign worker flies them (`Flyer::fly`: the
//!   dispersion drawn and applied, the instances reset, the run recording only the columns
//!   the metrics and verdict read, the metrics and verdict computed), on the paper scenario
//!   with the decoupled law at phi_cmd = 150 deg, seed 1; per step of those flights.
//!
//! `harness-cost compare` runs each mode under `valgrind --tool=callgrind`, counting only
//! the measured region (`--toggle-collect`: loading, instantiating and the first run's lazy
//! set-up stay out), and prints instructions per step and the ratio to `direct`. Each mode
//! also prints the plant's final state, and `compare` checks that `direct` and `master`
//! flew the same flight bit for bit, so the two counts are of the same work.
#![deny(unsafe_code)]

use anyhow::{bail, ensure, Context, Result};
use cosim::master::{set_parameter, RunEnd, Simulation, Trajectory};
use cosim::system::SystemDescription;
use fmi_import::{Fmu, Instance, StepStatus};
use speed_bench::record::{paper_system, COMMANDS, GNC, NAVIGATION, PLANT};
use std::path::{Path, PathBuf};
use std::process::Command;

/// Everything executed inside this function (and what it calls) is what callgrind counts.
#[inline(never)]
fn measured_region<R>(work: impl FnOnce() -> R) -> R {
    std::hint::black_box(work())
}

const MODES: [&str; 5] = ["direct", "master", "master-csv", "master-arrow", "campaign"];

/// Flights counted by `campaign` (after one flown outside the count).
const CAMPAIGN_FLIGHTS: u64 = 4;

fn main() -> Result<()> {
    let mut args = std::env::args().skip(1);
    let mode = args.next().unwrap_or_else(|| "compare".into());
    let mut fmu_dir = default_fmu_dir();
    let mut stop_time = None;
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--fmu-dir" => fmu_dir = PathBuf::from(args.next().context("--fmu-dir DIR")?),
            "--stop-time" => {
                stop_time = Some(args.next().context("--stop-time S")?.parse::<f64>()?)
            }
            other => bail!("unknown argument {other:?} (modes: compare, {MODES:?})"),
        }
    }
    let system = paper_system(stop_time)?;
    match mode.as_str() {
        "compare" => compare(&fmu_dir, stop_time),
        "direct" => print_final(&direct(&fmu_dir, &system)?),
        "master" | "master-csv" | "master-arrow" => print_final(&master(&fmu_dir, system, &mode)?),
        "campaign" => campaign(&fmu_dir, stop_time),
        other => bail!("unknown mode {other:?} (modes: compare, {MODES:?})"),
    }
}

fn default_fmu_dir() -> PathBuf {
    std::env::var_os("LANDER_FMU_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("../../target/fmu")
                .to_path_buf()
        })
}

/// The plant's final navigation outputs, as bits.
fn print_final(values: &[f64]) -> Result<()> {
    let bits: Vec<String> = values
        .iter()
        .map(|v| format!("{:016x}", v.to_bits()))
        .collect();
    println!("final {}", bits.join(" "));
    Ok(())
}

/// The harness's master: a first run outside the count, the second one counted.
fn master(fmu_dir: &Path, mut system: SystemDescription, mode: &str) -> Result<Vec<f64>> {
    system.record = None;
    let mut simulation = Simulation::new(system, fmu_dir)?;
    let names = simulation.column_names().to_vec();
    let fresh = || Trajectory {
        names: names.clone(),
        ..Default::default()
    };
    simulation.run(&mut fresh())?;
    let scratch = tempfile::tempdir()?;
    let mut trajectory = fresh();
    let end = measured_region(|| -> Result<RunEnd> {
        let end = simulation.run(&mut trajectory)?;
        match mode {
            "master-csv" => cosim::results::write_csv(&scratch.path().join("r.csv"), &trajectory)?,
            "master-arrow" => {
                cosim::results::write_arrow(&scratch.path().join("r.arrow"), &trajectory, &[])?
            }
            _ => {}
        }
        Ok(end)
    })?;
    ensure!(
        end == RunEnd::Completed,
        "the paper flight ended early: {end:?}"
    );
    let last = trajectory.len() - 1;
    NAVIGATION
        .iter()
        .map(|name| {
            let j = trajectory
                .column_index(&format!("{PLANT}.{name}"))
                .with_context(|| format!("no column {PLANT}.{name}"))?;
            Ok(trajectory.row(last)[j])
        })
        .collect()
}

/// Campaign flights through a reused `Flyer`, the first outside the count; prints the steps
/// flown in the counted ones.
fn campaign(fmu_dir: &Path, stop_time: Option<f64>) -> Result<()> {
    use campaign::{flight, CampaignSpec, DispersionRanges};
    let (mut system, spec) = flight::campaign_system("paper", &[], false)?;
    if let Some(stop) = stop_time {
        system.stop_time = stop;
    }
    let campaign = CampaignSpec {
        scenario: "paper".into(),
        seed: 1,
        phi_cmd_deg: vec![150.0],
        laws: vec![lander::laws::Law::DECOUPLED],
        runs_per_point: CAMPAIGN_FLIGHTS + 1,
        dispersions: DispersionRanges::default(),
        sets: Vec::new(),
    };
    let mut flyer = flight::Flyer::new(system, spec, fmu_dir)?;
    let first = flyer.fly(&campaign.flight(0), &campaign.dispersions);
    ensure!(!first.end.is_error(), "flight 0 failed: {:?}", first.end);
    let rows = measured_region(|| {
        (1..=CAMPAIGN_FLIGHTS)
            .map(|i| {
                let row = flyer.fly(&campaign.flight(i), &campaign.dispersions);
                let steps = flyer.trajectory().len().saturating_sub(1);
                (row, steps)
            })
            .collect::<Vec<_>>()
    });
    let mut steps = 0;
    for (row, flown) in &rows {
        ensure!(
            !row.end.is_error(),
            "flight {} failed: {:?}",
            row.flight.index,
            row.end
        );
        steps += flown;
    }
    println!("steps {steps}");
    Ok(())
}

/// Both FMUs through the loader, the harness's Gauss-Seidel exchange and nothing else.
fn direct(fmu_dir: &Path, system: &SystemDescription) -> Result<Vec<f64>> {
    let gnc_fmu = Fmu::load(fmu_dir.join("LanderGnc.fmu"))?;
    let plant_fmu = Fmu::load(fmu_dir.join("LanderPlant.fmu"))?;
    let mut gnc = gnc_fmu.instantiate(GNC, false)?;
    let mut plant = plant_fmu.instantiate(PLANT, false)?;
    let nav_out = vrs(&plant, &NAVIGATION)?;
    let nav_in = vrs(&gnc, &NAVIGATION)?;
    let cmd_out = vrs(&gnc, &COMMANDS)?;
    let cmd_in = vrs(&plant, &COMMANDS)?;
    let mut nav = [0.0; 14];
    let mut cmd = [0.0; 4];
    let mut fly = |gnc: &mut Instance, plant: &mut Instance| -> Result<()> {
        // Initialization as the master does it: the plant's initial state to the controller,
        // its first command to the plant.
        for (instance, name) in [(&mut *gnc, GNC), (&mut *plant, PLANT)] {
            instance.setup_experiment(None, system.start_time, Some(system.stop_time))?;
            for (variable, value) in system.instance(name).map_or(&[][..], |i| &i.parameters) {
                set_parameter(instance, variable, value)?;
            }
            instance.enter_initialization_mode()?;
        }
        plant.get_real(&nav_out, &mut nav)?;
        gnc.set_real(&nav_in, &nav)?;
        gnc.get_real(&cmd_out, &mut cmd)?;
        plant.set_real(&cmd_in, &cmd)?;
        gnc.exit_initialization_mode()?;
        plant.exit_initialization_mode()?;
        plant.get_real(&nav_out, &mut nav)?;
        let steps = ((system.stop_time - system.start_time) / system.step_size).round() as u64;
        for k in 0..steps {
            let time = system.start_time + k as f64 * system.step_size;
            let h = if k + 1 == steps {
                system.stop_time - time
            } else {
                system.step_size
            };
            gnc.set_real(&nav_in, &nav)?;
            gnc.get_real(&cmd_out, &mut cmd)?;
            plant.set_real(&cmd_in, &cmd)?;
            for instance in [&mut *gnc, &mut *plant] {
                match instance.do_step(time, h)? {
                    StepStatus::Complete(_) => {}
                    other => bail!("{} stopped at t = {time}: {other:?}", instance.name()),
                }
            }
            plant.get_real(&nav_out, &mut nav)?;
        }
        gnc.terminate()?;
        plant.terminate()?;
        Ok(())
    };
    fly(&mut gnc, &mut plant)?;
    gnc.reset()?;
    plant.reset()?;
    measured_region(|| fly(&mut gnc, &mut plant))?;
    Ok(nav.to_vec())
}

fn vrs(instance: &Instance, names: &[&str]) -> Result<Vec<u32>> {
    names
        .iter()
        .map(|name| Ok(instance.variable(name)?.value_reference))
        .collect()
}

/// Runs every mode under callgrind and prints instructions per step and the ratios.
fn compare(fmu_dir: &Path, stop_time: Option<f64>) -> Result<()> {
    let system = paper_system(stop_time)?;
    let steps = ((system.stop_time - system.start_time) / system.step_size).round();
    let mut steps_of = Vec::new();
    let exe = std::env::current_exe()?;
    let scratch = tempfile::tempdir()?;
    let mut counts = Vec::new();
    let mut finals = Vec::new();
    for mode in MODES {
        let out_file = scratch.path().join(format!("callgrind.{mode}"));
        let mut command = Command::new("valgrind");
        command
            .arg("--tool=callgrind")
            .arg(format!("--callgrind-out-file={}", out_file.display()))
            .arg("--toggle-collect=*measured_region*")
            .arg(&exe)
            .arg(mode)
            .arg("--fmu-dir")
            .arg(fmu_dir);
        if let Some(stop) = stop_time {
            command.arg("--stop-time").arg(stop.to_string());
        }
        let output = command
            .output()
            .context("running valgrind (is it installed?)")?;
        ensure!(
            output.status.success(),
            "{mode} under callgrind failed:\n{}",
            String::from_utf8_lossy(&output.stderr)
        );
        let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
        finals.push(
            stdout
                .lines()
                .find(|l| l.starts_with("final "))
                .unwrap_or_default()
                .to_owned(),
        );
        counts.push(total_instructions(&out_file)?);
        // A mode that flies another number of steps says so.
        steps_of.push(
            stdout
                .lines()
                .find_map(|l| l.strip_prefix("steps ")?.parse::<f64>().ok())
                .unwrap_or(steps),
        );
    }
    ensure!(
        finals[0] == finals[1],
        "direct and master flew different flights:\n  {}\n  {}",
        finals[0],
        finals[1]
    );
    println!("| Loop | Instructions per step | Ratio to direct |");
    println!("| --- | --- | --- |");
    let direct_per_step = counts[0] as f64 / steps_of[0];
    for ((mode, count), steps) in MODES.iter().zip(&counts).zip(&steps_of) {
        let per_step = *count as f64 / steps;
        println!(
            "| {mode} | {per_step:.0} | {:.2}x |",
            per_step / direct_per_step
        );
    }
    println!(
        "({steps} steps, campaign {} steps in {CAMPAIGN_FLIGHTS} flights; direct and master \
         end in the same state bit for bit)",
        steps_of[4]
    );
    Ok(())
}

/// The `totals:` (or `summary:`) line of a callgrind output file: instructions executed.
fn total_instructions(file: &Path) -> Result<u64> {
    let text = std::fs::read_to_string(file)?;
    text.lines()
        .rev()
        .find_map(|line| {
            line.strip_prefix("totals:")
                .or_else(|| line.strip_prefix("summary:"))
        })
        .and_then(|rest| rest.split_whitespace().next()?.parse().ok())
        .with_context(|| format!("no totals in {}", file.display()))
}
