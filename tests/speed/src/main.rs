//! Speed side by side in one run: prints a markdown table of
//!
//! 1. LanderPlant, one `fmi2DoStep` of 0.01 s, and the master cycle around it;
//! 2. LanderGnc, set inputs + get commands + `fmi2DoStep`, guidance re-solves included;
//! 3. the paper scenario (172 s, both FMUs, Gauss-Seidel) in the harness's master;
//! 4. a Monte Carlo campaign (default 1,000 runs) on 2 workers;
//! 5. the same scenario in fmpy's master loop;
//! 6. the same plant equations packaged with pythonfmu, in the same master with the same
//!    commands, and our speed-up over it.
//!
//! Rows 1 and 2 replay what each FMU exchanged in a paper flight flown first in the harness,
//! and check that the replay reproduces it bit for bit. Run with `cargo xtask bench`
//! (release build, FMUs packaged first); `--quick` is the smoke test's tiny version.
#![deny(unsafe_code)]

use anyhow::{ensure, Context, Result};
use clap::{Parser, Subcommand};
use cosim::supervise::Execution;
use fmi_import::Fmu;
use speed_bench::closed_loop::{monte_carlo, paper_flights, paper_flights_with};
use speed_bench::duel::{self, Duel};
use speed_bench::python::{self, PythonEnv};
use speed_bench::record::PaperRecord;
use speed_bench::replay::{
    gnc_cycles, plant_cycles, plant_steps, timer_cost, BATCH_STEPS, TIMER_BATCHES,
};
use speed_bench::stats::Summary;
use speed_bench::table::{self, figure, Machine, Row};
use std::path::{Path, PathBuf};
use std::process::Command;

#[derive(Parser)]
#[command(
    name = "speed-bench",
    about = "Our FMUs against fmpy's loop and a pythonfmu plant, in one run"
)]
struct Cli {
    /// Folder with LanderGnc.fmu and LanderPlant.fmu (default: <target>/fmu, as `cargo xtask
    /// fmus` writes them).
    #[arg(long, global = true)]
    fmu_dir: Option<PathBuf>,
    /// Tiny counts (a 5 s flight, one pass, 4 Monte Carlo runs): checks that everything
    /// runs, measures nothing worth quoting.
    #[arg(long)]
    quick: bool,
    /// Monte Carlo runs (default 1,000; 4 with --quick).
    #[arg(long)]
    runs: Option<u64>,
    /// Monte Carlo worker threads.
    #[arg(long, default_value_t = 2)]
    workers: usize,
    /// Skip rows 5 and 6 (fmpy, pythonfmu), which need the venv of `cargo xtask python-env`.
    #[arg(long)]
    no_python: bool,
    #[command(subcommand)]
    child: Option<Child>,
}

#[derive(Subcommand)]
enum Child {
    /// Row 6 in a process started with pythonfmu's embedding environment; prints JSON.
    #[command(hide = true)]
    PlantDuel {
        #[arg(long)]
        python_plant: PathBuf,
        #[arg(long)]
        stop_time: Option<f64>,
        #[arg(long)]
        ours_passes: usize,
        #[arg(long)]
        python_passes: usize,
    },
}

/// Runs in a worker process of this very program, as the harness runs its flights.
fn supervised_execution() -> Result<Execution> {
    Ok(Execution::Supervised {
        program: std::env::current_exe().context("this program's path, to start workers")?,
        limits: cosim::supervise::Limits::default(),
    })
}

/// How much of each measurement a run does.
#[derive(Debug, Clone, Copy)]
struct Counts {
    /// A shorter paper flight for every replay and flight; `None` is the full 172 s.
    stop_time_s: Option<f64>,
    /// Passes over the flight for rows 1 and 2.
    replay_passes: usize,
    /// Flights for row 3.
    flights: usize,
    /// Row 4.
    mc_runs: u64,
    /// Flights for row 5.
    fmpy_flights: usize,
    /// Passes of each plant in row 6.
    duel_ours_passes: usize,
    duel_python_passes: usize,
}

const FULL: Counts = Counts {
    stop_time_s: None,
    replay_passes: 10,
    flights: 20,
    mc_runs: 1000,
    fmpy_flights: 5,
    duel_ours_passes: 10,
    // A pass of the Python plant takes seconds; three, interleaved with ours, keep one
    // burst of load on a shared machine from setting the ratio.
    duel_python_passes: 3,
};

const QUICK: Counts = Counts {
    stop_time_s: Some(5.0),
    replay_passes: 1,
    flights: 2,
    mc_runs: 4,
    fmpy_flights: 1,
    duel_ours_passes: 1,
    duel_python_passes: 1,
};

fn main() -> Result<()> {
    // The supervised rows start this program again as their worker.
    cosim::supervise::serve_if_worker();
    let cli = Cli::parse();
    let fmu_dir = cli.fmu_dir.clone().unwrap_or_else(interop_tests::fmu_dir);
    for name in ["LanderGnc.fmu", "LanderPlant.fmu"] {
        ensure!(
            fmu_dir.join(name).is_file(),
            "no {name} in {}: run `cargo xtask fmus` (or `cargo xtask bench`, which does)",
            fmu_dir.display()
        );
    }
    match cli.child {
        Some(Child::PlantDuel {
            python_plant,
            stop_time,
            ours_passes,
            python_passes,
        }) => {
            let record = PaperRecord::fly(&fmu_dir, stop_time)?;
            let duel = duel::run(
                &fmu_dir.join("LanderPlant.fmu"),
                &python_plant,
                &record,
                record.steps(),
                ours_passes,
                python_passes,
            )?;
            println!("{}", serde_json::to_string(&duel)?);
            Ok(())
        }
        None => {
            let mut counts = if cli.quick { QUICK } else { FULL };
            if let Some(runs) = cli.runs {
                counts.mc_runs = runs;
            }
            measure_all(&fmu_dir, counts, cli.workers, !cli.no_python)
        }
    }
}

fn measure_all(fmu_dir: &Path, counts: Counts, workers: usize, with_python: bool) -> Result<()> {
    let machine = Machine::describe();
    let load_before = table::load_average().unwrap_or_else(|| "unknown".into());
    let env = if with_python {
        Some(PythonEnv::locate(&interop_tests::workspace_root())?)
    } else {
        None
    };
    progress("flying the paper scenario once to record what each FMU exchanges");
    let record = PaperRecord::fly(fmu_dir, counts.stop_time_s)?;
    let steps = record.steps();
    let plant = Fmu::load(fmu_dir.join("LanderPlant.fmu"))?;
    let gnc = Fmu::load(fmu_dir.join("LanderGnc.fmu"))?;
    let mut rows = Vec::new();

    progress("1: LanderPlant");
    let timer_s = timer_cost(TIMER_BATCHES, BATCH_STEPS);
    let (mut step_means, mut cycle_means) = (Vec::new(), Vec::new());
    for _ in 0..counts.replay_passes {
        let (steps_only, step_agreement) = plant_steps(&plant, &record, steps, BATCH_STEPS)?;
        let (cycles, cycle_agreement) = plant_cycles(&plant, &record, steps, BATCH_STEPS)?;
        ensure!(
            step_agreement.bit_identical && cycle_agreement.bit_identical,
            "LanderPlant did not retrace the recorded flight under its recorded commands"
        );
        step_means.extend(steps_only);
        cycle_means.extend(cycles);
    }
    rows.push(Row::timed(
        "1",
        "LanderPlant: one fmi2DoStep of 0.01 s",
        summary(&step_means)?.less(timer_s),
        1e6,
        "µs",
        format!("{} batches of {BATCH_STEPS} steps", step_means.len()),
        format!(
            "harness loader, C ABI; each call timed alone, the timer's own {} ns taken off; \
             retraces the recorded flight bit for bit",
            figure(timer_s * 1e9)
        ),
    ));
    rows.push(Row::timed(
        "1b",
        "LanderPlant: set 4 inputs + fmi2DoStep + get 14 outputs",
        summary(&cycle_means)?,
        1e6,
        "µs",
        format!("{} batches of {BATCH_STEPS} steps", cycle_means.len()),
        "timed per batch; retraces the recorded flight bit for bit",
    ));

    progress("2: LanderGnc");
    let mut gnc_means = Vec::new();
    for _ in 0..counts.replay_passes {
        gnc_means.extend(gnc_cycles(&gnc, &record, steps, BATCH_STEPS)?);
    }
    rows.push(Row::timed(
        "2",
        "LanderGnc: set 14 inputs + get 4 commands + fmi2DoStep",
        summary(&gnc_means)?,
        1e6,
        "µs",
        format!("{} batches of {BATCH_STEPS} steps", gnc_means.len()),
        format!(
            "{}; commands equal the closed loop's bit for bit",
            if counts.stop_time_s.is_none() {
                "every phase of the flight (re-solve every 10th step of the descent)"
            } else {
                "the start of the flight only (hover, no re-solve)"
            }
        ),
    ));

    progress("3: the paper scenario in the harness");
    let flight_seconds = paper_flights(fmu_dir, counts.flights, counts.stop_time_s)?;
    let flights = summary(&flight_seconds)?;
    rows.push(Row::timed(
        "3",
        format!(
            "Paper scenario, {} s, both FMUs, Gauss-Seidel, harness master",
            figure(record.times[steps] - record.times[0])
        ),
        flights,
        1e3,
        "ms",
        table::count(flights.count, "flight"),
        format!(
            "{steps} steps, every output recorded; {} µs per step",
            figure(flights.median / steps as f64 * 1e6)
        ),
    ));

    progress("3s: the paper scenario in a supervised worker");
    let supervised = supervised_execution()?;
    let in_process = paper_flights_with(fmu_dir, 1, counts.stop_time_s, Execution::InProcess)?;
    let worker = paper_flights_with(
        fmu_dir,
        counts.flights,
        counts.stop_time_s,
        supervised.clone(),
    )?;
    ensure!(
        worker.trajectory.times == in_process.trajectory.times
            && worker
                .trajectory
                .values
                .iter()
                .zip(&in_process.trajectory.values)
                .all(|(a, b)| a.to_bits() == b.to_bits()),
        "the supervised flight differs from the in-process one"
    );
    let worker_flights = summary(&worker.seconds)?;
    rows.push(Row::timed(
        "3s",
        "The same, its FMUs in a supervised worker process (the harness's default)",
        worker_flights,
        1e3,
        "ms",
        table::count(worker_flights.count, "flight"),
        format!(
            "{}x row 3's median; rows bit-identical to in-process; starting the worker and \
             the first flight {} ms",
            figure(worker_flights.median / flights.median),
            figure(worker.first_with_start_s * 1e3)
        ),
    ));

    progress(&format!(
        "4: Monte Carlo, {} runs on {workers} workers",
        counts.mc_runs
    ));
    let campaign = monte_carlo(fmu_dir, counts.mc_runs, workers)?;
    progress(&format!(
        "4s: Monte Carlo, {} runs on {workers} supervised workers",
        counts.mc_runs
    ));
    cosim::supervise::set_default(supervised);
    let supervised_campaign = monte_carlo(fmu_dir, counts.mc_runs, workers);
    cosim::supervise::set_default(Execution::InProcess);
    let supervised_campaign = supervised_campaign?;
    rows.push(Row::timed(
        "4",
        format!(
            "Monte Carlo: {} dispersed paper flights on {} workers",
            campaign.flights, campaign.workers
        ),
        Summary::of(&[campaign.elapsed.as_secs_f64()]).context("campaign time")?,
        1.0,
        "s",
        "1 campaign",
        format!(
            "{} runs/s; {} failed; harness montecarlo runner, manifest streamed to disk",
            figure(campaign.flights_per_second()),
            campaign.failed
        ),
    ));
    rows.push(Row::timed(
        "4s",
        "The same campaign, each worker's FMUs in a supervised process (the harness's \
         default)",
        Summary::of(&[supervised_campaign.elapsed.as_secs_f64()]).context("campaign time")?,
        1.0,
        "s",
        "1 campaign",
        format!(
            "{} runs/s, {}x row 4's; {} failed",
            figure(supervised_campaign.flights_per_second()),
            figure(supervised_campaign.flights_per_second() / campaign.flights_per_second()),
            supervised_campaign.failed
        ),
    ));

    if let Some(env) = &env {
        progress("5: the paper scenario in fmpy's master loop");
        let fmpy = python::fmpy_flights(env, fmu_dir, &record, counts.fmpy_flights)?;
        let loop_s = summary(&fmpy.loop_seconds)?;
        rows.push(Row::timed(
            "5",
            "The same scenario in fmpy's master loop (FMU2Slave, Python)",
            loop_s,
            1.0,
            "s",
            table::count(loop_s.count, "flight"),
            format!(
                "loop only; {} µs per step; {}x the harness's time; final row equal to the \
                 harness's bit for bit",
                figure(loop_s.median / fmpy.steps as f64 * 1e6),
                figure(loop_s.median / flights.median)
            ),
        ));

        progress("6: LanderPlant against the pythonfmu plant");
        let duel = plant_duel(env, fmu_dir, counts)?;
        rows.extend(duel_rows(&duel)?);
    }

    let load_after = table::load_average().unwrap_or_else(|| "unknown".into());
    println!(
        "Speed side by side: {} ({} cores available); load average (1 / 5 / 15 min) {} at \
         the start, {} at the end.\n",
        machine.cpu, machine.cores, load_before, load_after
    );
    if counts.stop_time_s.is_some() {
        println!("Quick mode: a short flight and tiny counts; nothing here is worth quoting.\n");
    }
    print!("{}", table::markdown(&rows));
    if !with_python {
        println!("\nRows 5 and 6 (fmpy, pythonfmu) skipped: --no-python.");
    }
    Ok(())
}

/// Builds the pythonfmu plant and runs row 6 in a child process that can host it.
fn plant_duel(env: &PythonEnv, fmu_dir: &Path, counts: Counts) -> Result<Duel> {
    let scratch = tempfile::Builder::new()
        .prefix("speed-pythonfmu-")
        .tempdir()?;
    let python_plant = python::build_python_plant(env, scratch.path())?;
    let mut child = Command::new(std::env::current_exe()?);
    child
        .arg("--fmu-dir")
        .arg(fmu_dir)
        .arg("plant-duel")
        .arg("--python-plant")
        .arg(&python_plant)
        .args(["--ours-passes", &counts.duel_ours_passes.to_string()])
        .args(["--python-passes", &counts.duel_python_passes.to_string()])
        .envs(python::embedding_env(env)?);
    if let Some(stop) = counts.stop_time_s {
        child.args(["--stop-time", &stop.to_string()]);
    }
    let output = child
        .output()
        .context("cannot start the plant-duel child")?;
    ensure!(
        output.status.success(),
        "the plant-duel child failed ({}):\n{}",
        output.status,
        String::from_utf8_lossy(&output.stderr)
    );
    let stdout = String::from_utf8_lossy(&output.stdout);
    serde_json::from_str(stdout.trim()).context("the plant-duel child printed no report")
}

fn duel_rows(duel: &Duel) -> Result<[Row; 3]> {
    let timer_s = duel.timer_cost_s;
    let ours_step = summary(&duel.ours.step_means)?.less(timer_s);
    let ours_cycle = summary(&duel.ours.cycle_means)?;
    let py_step = summary(&duel.python.step_means)?.less(timer_s);
    let py_cycle = summary(&duel.python.cycle_means)?;
    let step_ratio = py_step.median / ours_step.median;
    let cycle_ratio = py_cycle.median / ours_cycle.median;
    Ok([
        Row::timed(
            "6",
            "pythonfmu plant (same equations, Python): one fmi2DoStep of 0.01 s",
            py_step,
            1e6,
            "µs",
            format!("{} batches of {BATCH_STEPS} steps", py_step.count),
            format!(
                "same master (harness loader, in a child process hosting libpython), same \
                 commands, same timing; LanderPlant in that process: {} µs",
                figure(ours_step.median * 1e6)
            ),
        ),
        Row::timed(
            "6b",
            "pythonfmu plant: set 4 inputs + fmi2DoStep + get 14 outputs",
            py_cycle,
            1e6,
            "µs",
            format!("{} batches of {BATCH_STEPS} steps", py_cycle.count),
            format!(
                "LanderPlant in that process: {} µs; the two plants' positions differ by at \
                 most {} m over the flight",
                figure(ours_cycle.median * 1e6),
                figure(duel.python.max_position_error_m)
            ),
        ),
        Row {
            id: "6c",
            what: "Our speed-up over the pythonfmu plant (target ≥ 100x)".into(),
            median: format!("{}x", figure(step_ratio)),
            spread: "–".into(),
            samples: "ratio of medians".into(),
            notes: format!(
                "fmi2DoStep alone {}x; whole master cycle {}x",
                figure(step_ratio),
                figure(cycle_ratio)
            ),
        },
    ])
}

fn summary(samples: &[f64]) -> Result<Summary> {
    Summary::of(samples).context("no valid samples (empty, or not finite)")
}

fn progress(what: &str) {
    eprintln!("speed-bench: {what}");
}
