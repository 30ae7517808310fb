//! Both FMUs in the harness's own master: the paper scenario, and a Monte Carlo campaign.
use crate::record::paper_system;
use anyhow::{ensure, Result};
use campaign::dispersion::DispersionRanges;
use campaign::runner::{self, RunOptions};
use campaign::{CampaignSpec, Shard};
use cosim::master::{RunEnd, Trajectory};
use cosim::supervise::{Execution, Runner};
use lander::laws::Law;
use std::path::Path;
use std::time::{Duration, Instant};

/// Wall time of each of `runs` paper flights through `Simulation::run`, every output
/// recorded in memory as a user's run does; loading and instantiating are done once,
/// before. Every flight must reach the stop time.
pub fn paper_flights(fmu_dir: &Path, runs: usize, stop_time_s: Option<f64>) -> Result<Vec<f64>> {
    Ok(paper_flights_with(fmu_dir, runs, stop_time_s, Execution::InProcess)?.seconds)
}

/// Paper flights run where `execution` says, timed one by one.
pub struct Flights {
    /// Each flight's wall time (the worker, if any, already started).
    pub seconds: Vec<f64>,
    /// From loading the system (starting the worker) to the end of its first flight.
    pub first_with_start_s: f64,
    /// The last flight's rows.
    pub trajectory: Trajectory,
}

/// [`paper_flights`] in process or in a supervised worker.
pub fn paper_flights_with(
    fmu_dir: &Path,
    runs: usize,
    stop_time_s: Option<f64>,
    execution: Execution,
) -> Result<Flights> {
    let loading = Instant::now();
    let mut simulation = Runner::with(paper_system(stop_time_s)?, fmu_dir, execution)?;
    let mut seconds = Vec::with_capacity(runs);
    let mut first_with_start_s = 0.0;
    let mut trajectory = Trajectory::default();
    for run in 0..runs {
        trajectory = Trajectory {
            names: simulation.column_names().to_vec(),
            ..Default::default()
        };
        let started = Instant::now();
        let end = simulation.run(&mut trajectory)?;
        seconds.push(started.elapsed().as_secs_f64());
        if run == 0 {
            first_with_start_s = loading.elapsed().as_secs_f64();
        }
        ensure!(
            end == RunEnd::Completed,
            "the paper flight ended early: {end:?}"
        );
    }
    Ok(Flights {
        seconds,
        first_with_start_s,
        trajectory,
    })
}

/// What one campaign did, as the harness's runner reports it.
#[derive(Debug, Clone, Copy)]
pub struct CampaignTiming {
    pub flights: u64,
    pub failed: u64,
    pub workers: usize,
    pub elapsed: Duration,
}

impl CampaignTiming {
    pub fn flights_per_second(&self) -> f64 {
        self.flights as f64 / self.elapsed.as_secs_f64()
    }
}

/// A campaign of `runs` dispersed paper flights (decoupled law, phi_cmd = 150 deg, the
/// harness's default dispersions, so one run is one flight) on `workers` threads, its
/// manifest streamed into a scratch folder. The elapsed time is the runner's: from loading
/// the first instance pair to the last row written.
pub fn monte_carlo(fmu_dir: &Path, runs: u64, workers: usize) -> Result<CampaignTiming> {
    let spec = CampaignSpec {
        scenario: "paper".into(),
        seed: 1,
        phi_cmd_deg: vec![150.0],
        laws: vec![Law::DECOUPLED],
        runs_per_point: runs,
        dispersions: DispersionRanges::default(),
        sets: Vec::new(),
    };
    let out = tempfile::Builder::new().prefix("speed-mc-").tempdir()?;
    let options = RunOptions {
        fmu_dir: fmu_dir.to_owned(),
        out_dir: out.path().to_owned(),
        workers,
        shard: Shard::WHOLE,
        progress: false,
    };
    let outcome = runner::run(&spec, &options)?;
    ensure!(
        outcome.flights == spec.flight_count(),
        "the campaign flew {} of {} flights",
        outcome.flights,
        spec.flight_count()
    );
    Ok(CampaignTiming {
        flights: outcome.flights,
        failed: outcome.failed,
        workers,
        elapsed: outcome.elapsed,
    })
}
