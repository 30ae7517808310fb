//! The `monte-carlo`, `merge-mc` and `replay` subcommands: their options and what they do.
use campaign::dispersion::DispersionRanges;
use campaign::manifest::{self, Row};
use campaign::seed::run_seed;
use campaign::{merge, replay, runner, summary, summary_csv};
use campaign::{CampaignSpec, Flight, Shard};
use lander::laws::{Law, Laws};
use std::path::{Path, PathBuf};

mod dask;

/// The definition of a campaign: with the same options, `monte-carlo` flies the same
/// flights bit for bit, on any machine, with any number of workers or shards.
#[derive(Debug, Clone, clap::Args)]
pub struct CampaignArgs {
    #[arg(long, default_value = campaign::DEFAULT_SCENARIO, help = lander::scenarios::campaign_scenario_help())]
    pub scenario: String,
    /// Campaign seed (0 ..= 2^63 - 1). Run j draws its dispersions from ChaCha8 seeded
    /// with output j of SplitMix64 seeded with this.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u64).range(..=i64::MAX as u64))]
    pub seed: u64,
    /// phi_cmd grid (deg), comma-separated or repeated.
    #[arg(
        long = "phi-cmd-deg",
        value_delimiter = ',',
        num_args = 1,
        allow_hyphen_values = true,
        default_values_t = [0.0, 30.0, 60.0, 90.0, 120.0, 150.0, 180.0]
    )]
    pub phi_cmd_deg: Vec<f64>,
    /// Control laws, comma-separated or repeated [default: every law of the GNC FMU's
    /// control_law enumeration]
    #[arg(long = "law", value_delimiter = ',', num_args = 1..)]
    pub laws: Vec<String>,
    /// Runs (dispersion draws) per (phi_cmd, law) point.
    #[arg(long, short = 'n', default_value_t = 10)]
    pub runs: u64,
    #[command(flatten)]
    pub dispersions: DispersionRanges,
    /// Override a parameter of the scenario for every flight, e.g. --set plant.m0=850
    /// (repeatable): the nominal the dispersions are drawn around. gnc.control_law and
    /// gnc.phi_cmd are the campaign's own (--law, --phi-cmd-deg).
    #[arg(long = "set", value_name = "INSTANCE.VAR=VALUE")]
    pub sets: Vec<String>,
}

impl CampaignArgs {
    /// The campaign these options define, its laws those of the scenario's GNC FMU in
    /// `fmu_dir` when `--law` names none.
    pub fn spec(&self, fmu_dir: &Path) -> anyhow::Result<CampaignSpec> {
        let laws = if self.laws.is_empty() {
            let (system, _) = lander::scenarios::spec::load(&self.scenario)?;
            Laws::of_instance(&system, "gnc", fmu_dir)?.all()
        } else {
            self.laws.iter().map(|name| Law::named(name)).collect()
        };
        Ok(CampaignSpec {
            scenario: self.scenario.clone(),
            seed: self.seed,
            phi_cmd_deg: self.phi_cmd_deg.clone(),
            laws,
            runs_per_point: self.runs,
            dispersions: self.dispersions.clone(),
            sets: self.sets.clone(),
        })
    }
}

#[derive(Debug, Clone, clap::Args)]
pub struct MonteCarloArgs {
    #[command(flatten)]
    pub campaign: CampaignArgs,
    /// Worker threads, each with its own FMU instance pair (default: the available cores).
    #[arg(long)]
    pub workers: Option<usize>,
    /// Where manifest.csv, campaign.toml and the plots go.
    #[arg(long, default_value = "target/monte-carlo")]
    pub out_dir: PathBuf,
    /// Fly only the flights whose index is k-1 modulo N (k = 1..N), e.g. an array job's task;
    /// combine the shards' directories with `merge-mc`.
    #[arg(long, value_name = "k/N")]
    pub shard: Option<Shard>,
    /// No progress bar and no summary table.
    #[arg(long, short)]
    pub quiet: bool,
    /// Skip the PNG figure.
    #[arg(long)]
    pub no_plots: bool,
    /// Continue the campaign already in --out-dir (same definition and shard): keep its
    /// finished flights, fly the others. Without a campaign there, start one.
    #[arg(long)]
    pub resume: bool,
    /// With --resume: fly these flight indices again (comma-separated), replacing their rows.
    #[arg(
        long,
        value_delimiter = ',',
        requires = "resume",
        value_name = "INDEX,..."
    )]
    pub rerun: Vec<u64>,
    /// Fly a campaign (or shard) of more than 10,000,000 flights, which is refused by
    /// default with the estimate of its time, manifest size and memory.
    #[arg(long)]
    pub force: bool,
    #[command(flatten)]
    pub dask: crate::dask::DaskArgs,
}

#[derive(Debug, Clone, clap::Args)]
pub struct MergeArgs {
    /// Shard directories (or their manifest.csv files), each with its campaign.toml.
    #[arg(required = true)]
    pub inputs: Vec<PathBuf>,
    /// Where the merged manifest.csv, campaign.toml and the figure go.
    #[arg(long)]
    pub out_dir: PathBuf,
    /// Merge even if flights are missing (they are listed); duplicates are always an error.
    #[arg(long)]
    pub allow_missing: bool,
    #[arg(long)]
    pub no_plots: bool,
}

#[derive(Debug, Clone, clap::Args)]
pub struct ReplayArgs {
    /// Replay flight --index of this manifest (or campaign directory) and check its metrics
    /// bit for bit; the campaign definition is read from the campaign.toml beside it, so
    /// the options that define a flight (--seed, --run, --law, --phi-cmd-deg, --scenario,
    /// --disp-*) are refused with it.
    #[arg(
        long,
        requires = "index",
        conflicts_with_all = ["seed", "run", "law", "phi_cmd_deg", "scenario", "DispersionRanges", "sets"]
    )]
    pub manifest: Option<PathBuf>,
    /// The flight's index (the manifest's `index` column).
    #[arg(long, requires = "manifest")]
    pub index: Option<u64>,
    /// Campaign seed (without --manifest).
    #[arg(long, required_unless_present = "manifest")]
    pub seed: Option<u64>,
    /// Run j (the manifest's `run` column): which dispersion draw.
    #[arg(long, required_unless_present = "manifest")]
    pub run: Option<u64>,
    /// Law to fly the run with (without --manifest): a law of the GNC FMU.
    #[arg(long, default_value = "decoupled")]
    pub law: String,
    /// phi_cmd to fly the run with (deg; without --manifest).
    #[arg(
        long = "phi-cmd-deg",
        default_value_t = 150.0,
        allow_negative_numbers = true
    )]
    pub phi_cmd_deg: f64,
    /// The scenario without --manifest: as for monte-carlo.
    #[arg(long, default_value = campaign::DEFAULT_SCENARIO)]
    pub scenario: String,
    #[command(flatten)]
    pub dispersions: DispersionRanges,
    /// The campaign's --set overrides (without --manifest): as for monte-carlo.
    #[arg(long = "set", value_name = "INSTANCE.VAR=VALUE")]
    pub sets: Vec<String>,
    /// The full trajectory (every output): CSV, or an Arrow IPC file for a .arrow, .feather
    /// or .ipc name.
    #[arg(long, short, default_value = "target/monte-carlo/replay.csv")]
    pub out: PathBuf,
    /// Also print the hover-to-descent handover: what the hover hands the descent's cubic
    /// and how far the cubic carries it (docs/results.md, the handover).
    #[arg(long)]
    pub handover: bool,
}

/// At most this many failed flights are printed (all are in `summary.csv`'s counts and the
/// manifest's `as_expected` column).
const FAILED_SHOWN: usize = 20;

/// Summary table, `summary.csv`, the failed flights and the figure of finished rows; returns
/// the exit code ([`lander::verdict::EXIT_ERROR`] when a flight ended in error,
/// [`lander::verdict::EXIT_FAILED_VERDICT`] when one failed its verdict).
fn report(
    rows: &[Row],
    scenario: &str,
    dir: &Path,
    title: &str,
    quiet: bool,
    plots: bool,
) -> anyhow::Result<i32> {
    let (_, spec) = lander::scenarios::spec::load(scenario)?;
    let requirements = lander::scenarios::spec::requirements(scenario)?.len();
    if !quiet {
        print!("{}", summary::table(&summary::summarise(rows)));
    }
    let path = summary_csv::write(rows, spec.expect, requirements, dir)?;
    println!("wrote {}", path.display());
    let failed = summary_csv::failed_lines(rows);
    if !failed.is_empty() {
        println!(
            "{} flights did not end as the scenario expects ({}):",
            failed.len(),
            summary_csv::requirement(spec.expect, requirements)
        );
        for line in failed.iter().take(FAILED_SHOWN) {
            println!("  {line}");
        }
        if failed.len() > FAILED_SHOWN {
            println!(
                "  ... and {} more (manifest.csv, column as_expected)",
                failed.len() - FAILED_SHOWN
            );
        }
    }
    if plots {
        let path = report::plots::monte_carlo::figure(rows, dir, title)?;
        println!("wrote {}", path.display());
    }
    let path = report::html::write(dir, title, &failed)?;
    println!("wrote {}", path.display());
    // A flight that could not be judged (its FMU crashed, exited or hung) is no verdict:
    // the campaign's result is an error, whatever the others did.
    let errors = rows.iter().filter(|row| row.end.is_error()).count();
    if errors > 0 {
        println!("{errors} flights ended in error (manifest.csv, column end)");
        return Ok(lander::verdict::EXIT_ERROR);
    }
    Ok(if failed.is_empty() {
        lander::verdict::EXIT_OK
    } else {
        lander::verdict::EXIT_FAILED_VERDICT
    })
}

/// LanderGnc declares `phi_cmd` within +-4 pi rad; said in the unit the option takes.
const PHI_CMD_MAX_DEG: f64 = 720.0;

/// Every `--phi-cmd-deg` value outside LanderGnc's declared range, at once, in degrees.
fn check_phi_cmd_deg(values: &[f64]) -> anyhow::Result<()> {
    let bad: Vec<String> = values
        .iter()
        .filter(|deg| !deg.is_finite() || deg.abs() > PHI_CMD_MAX_DEG)
        .map(|deg| format!("--phi-cmd-deg {deg}"))
        .collect();
    if !bad.is_empty() {
        anyhow::bail!(
            "{}: LanderGnc's phi_cmd is declared within -{PHI_CMD_MAX_DEG} to \
             {PHI_CMD_MAX_DEG} deg (+-4 pi rad)",
            bad.join(", ")
        );
    }
    Ok(())
}

/// Memory a flight's row takes once read back for the summary: the row and its strings.
const ROW_HEAP_BYTES: usize = 128;
/// Bytes a flight's row takes in manifest.csv (the paper scenario's rows: 804 on average).
const MANIFEST_ROW_BYTES: f64 = 800.0;

/// The most flights one campaign (or shard) flies without `--force`: about 8 GB of
/// manifest.csv, and for the paper scenario about three days of two workers.
pub const MAX_FLIGHTS: u64 = 10_000_000;
/// Seconds of one worker per communication point of a flight: the paper scenario's 2,556
/// flights of 17,201 points in 65 s on two workers (release build).
const SECONDS_PER_POINT: f64 = 3.0e-6;

/// A duration as a reader wants it: seconds, hours, days or years.
fn duration(seconds: f64) -> String {
    if seconds < 3600.0 {
        format!("{seconds:.0} s")
    } else if seconds < 2.0 * 86400.0 {
        format!("{:.1} hours", seconds / 3600.0)
    } else if seconds < 2.0 * 365.25 * 86400.0 {
        format!("{:.0} days", seconds / 86400.0)
    } else {
        format!("{:.3e} years", seconds / (365.25 * 86400.0))
    }
}

/// Refuses, before any flight, a campaign larger than [`MAX_FLIGHTS`] (unless `force`) or
/// whose rows could not be summarised in this machine's memory (the summary, the report
/// and the figure read every row back; `force` or not), with the estimate: the flights,
/// the time, manifest.csv's size and the memory.
fn check_campaign_size(
    spec: &CampaignSpec,
    shard: Shard,
    workers: usize,
    force: bool,
) -> anyhow::Result<()> {
    let flights = shard.len(spec.flight_count());
    let row_bytes = (std::mem::size_of::<Row>() + ROW_HEAP_BYTES) as f64;
    let memory = flights as f64 * row_bytes;
    let available = cosim::memory::available_bytes();
    let usable = available.map(|a| cosim::memory::USABLE_FRACTION * a);
    let too_large = usable.is_some_and(|usable| memory > usable);
    if !too_large && (flights <= MAX_FLIGHTS || force) {
        return Ok(());
    }
    // Flights end at their stop time at the latest.
    let time = lander::scenarios::spec::load(&spec.scenario)
        .ok()
        .map(|(system, _)| {
            let points = ((system.stop_time - system.start_time) / system.step_size).ceil() + 1.0;
            let seconds = flights as f64 * points * SECONDS_PER_POINT / workers.max(1) as f64;
            format!(
                "about {} on {workers} workers (up to {points:.0} communication points a \
                 flight, {:.0} us each), ",
                duration(seconds),
                SECONDS_PER_POINT * 1e6
            )
        })
        .unwrap_or_default();
    let estimate = format!(
        "{flights} flights ({} runs x {} phi_cmd x {} laws{}) would take {time}manifest.csv \
         would take about {:.3e} bytes, and the summary reads every row back, about \
         {memory:.3e} bytes of memory ({row_bytes:.0} per flight)",
        spec.runs_per_point,
        spec.phi_cmd_deg.len(),
        spec.laws.len(),
        if shard.is_whole() {
            String::new()
        } else {
            format!(", shard {shard}")
        },
        flights as f64 * MANIFEST_ROW_BYTES,
    );
    let points = (spec.phi_cmd_deg.len() * spec.laws.len()) as f64;
    match (available, usable) {
        (Some(available), Some(usable)) if too_large => anyhow::bail!(
            "{estimate}: too many for one campaign on this machine, with --force or without: \
             against the {:.1} GB available, at most {} flights fit (-n {} with these \
             points)",
            available / 1e9,
            (usable / row_bytes).floor(),
            (usable / row_bytes / points).floor()
        ),
        _ => anyhow::bail!(
            "{estimate}: more than the {MAX_FLIGHTS} flights a campaign (or shard) flies \
             without --force: fewer runs (at most -n {} with these points), or shards \
             (--shard k/N), or give --force to fly it anyway",
            (MAX_FLIGHTS as f64 / points).floor()
        ),
    }
}

pub fn monte_carlo(args: &MonteCarloArgs, fmu_dir: &Path) -> anyhow::Result<i32> {
    check_phi_cmd_deg(&args.campaign.phi_cmd_deg)?;
    let spec = args.campaign.spec(fmu_dir)?;
    let workers = args.workers.unwrap_or_else(runner::default_workers);
    check_campaign_size(
        &spec,
        args.shard.unwrap_or(Shard::WHOLE),
        workers,
        args.force,
    )?;
    if args.dask.dask.is_some() {
        return dask::campaign(args, &spec, fmu_dir);
    }
    let options = runner::RunOptions {
        fmu_dir: fmu_dir.to_owned(),
        out_dir: args.out_dir.clone(),
        workers,
        shard: args.shard.unwrap_or(Shard::WHOLE),
        progress: !args.quiet,
    };
    let resume = args.resume.then(|| runner::Resume {
        rerun: args.rerun.clone(),
    });
    let outcome = runner::run_resumed(&spec, &options, resume.as_ref())?;
    if outcome.kept > 0 {
        println!(
            "resumed: {} flights kept from the interrupted campaign",
            outcome.kept
        );
    }
    println!(
        "{} flights flown ({} errors) in {:.1} s ({:.1} flights/s, {} workers) -> {}",
        outcome.flights,
        outcome.failed,
        outcome.elapsed.as_secs_f64(),
        outcome.flights_per_second(),
        options.workers,
        outcome.manifest.display()
    );
    // The rows as the manifest holds them, kept as they were written: not read back.
    let rows = &outcome.rows;
    let title = format!(
        "Monte Carlo, scenario '{}', seed {}, {} runs per point{}",
        spec.scenario,
        spec.seed,
        spec.runs_per_point,
        if options.shard.is_whole() {
            String::new()
        } else {
            format!(", shard {}", options.shard)
        }
    );
    report(
        rows,
        &spec.scenario,
        &args.out_dir,
        &title,
        args.quiet,
        !args.no_plots,
    )
}

pub fn merge_mc(args: &MergeArgs) -> anyhow::Result<i32> {
    let merged = merge::merge(&args.inputs, args.allow_missing)?;
    let path = merge::write(&merged, &args.out_dir)?;
    println!(
        "{} of {} flights from {} inputs -> {}",
        merged.rows.len(),
        merged.spec.flight_count(),
        args.inputs.len(),
        path.display()
    );
    if !merged.missing.is_empty() {
        println!("missing: {} flights", merged.missing.len());
    }
    let title = format!(
        "Monte Carlo, scenario '{}', seed {}, {} runs per point",
        merged.spec.scenario, merged.spec.seed, merged.spec.runs_per_point
    );
    report(
        &merged.rows,
        &merged.spec.scenario,
        &args.out_dir,
        &title,
        false,
        !args.no_plots,
    )
}

pub fn replay(args: &ReplayArgs, fmu_dir: &Path) -> anyhow::Result<()> {
    // Before the flight: a name that is no result format is refused at once.
    let format = cosim::results::Format::for_output(&args.out, None).map_err(anyhow::Error::msg)?;
    if args.manifest.is_none() {
        check_phi_cmd_deg(&[args.phi_cmd_deg])?;
    }
    let (row, trajectory, verdict) = match (&args.manifest, args.index) {
        (Some(manifest), Some(index)) => {
            let r = replay::from_manifest(manifest, index, fmu_dir)?;
            let verdict = if r.matches() {
                "metrics identical to the manifest's, bit for bit".to_owned()
            } else {
                anyhow::bail!(
                    "flight {index} does not reproduce: manifest {:?} {:?}, replay {:?} {:?}",
                    r.recorded.end,
                    r.recorded.metrics,
                    r.replayed.end,
                    r.replayed.metrics
                );
            };
            (r.replayed, r.trajectory, verdict)
        }
        _ => {
            let (seed, run) = args.seed.zip(args.run).ok_or_else(|| {
                anyhow::anyhow!("give --seed and --run, or --manifest and --index")
            })?;
            let flight = Flight {
                index: u64::MAX,
                run,
                run_seed: run_seed(seed, run),
                law: Law::named(&args.law),
                phi_cmd_deg: args.phi_cmd_deg,
            };
            args.dispersions.validate().map_err(anyhow::Error::msg)?;
            let (row, trajectory) = replay::fly(
                &args.scenario,
                &args.sets,
                &args.dispersions,
                &flight,
                fmu_dir,
            )?;
            (row, trajectory, "flown from the seed".to_owned())
        }
    };
    if let manifest::End::Error { message } = &row.end {
        anyhow::bail!(
            "run {} (seed {}), {} at phi_cmd {} deg could not be flown: {message}",
            row.flight.run,
            row.flight.run_seed,
            row.flight.law.name(),
            row.flight.phi_cmd_deg
        );
    }
    cosim::results::write(&args.out, &trajectory, format)?;
    let m = &row.metrics;
    let end = match &row.end {
        manifest::End::Terminated { instance } => format!("stopped by '{instance}'"),
        _ => "completed".to_owned(),
    };
    println!(
        "run {} (seed {}), {} at phi_cmd {} deg: {end}, verdict {}{}; max horizontal deviation \
         {:.3} m, end-of-descent position error {:.4} m; {verdict}; {} rows -> {}",
        row.flight.run,
        row.flight.run_seed,
        row.flight.law.name(),
        row.flight.phi_cmd_deg,
        row.verdict.word,
        if row.verdict.detail.is_empty() {
            String::new()
        } else {
            format!(" ({})", row.verdict.detail)
        },
        m.max_horizontal_deviation_m,
        m.descent_end_position_error_m,
        trajectory.len(),
        args.out.display()
    );
    if args.handover {
        let handover = lander::handover::analyse(&trajectory).map_err(anyhow::Error::msg)?;
        println!("the hover-to-descent handover:");
        for (label, value) in handover.rows() {
            println!("{label:<48}{value:>10}");
        }
    }
    Ok(())
}
