//! `harness`: runs the lander FMUs (or any FMI 2.0 CS FMUs exposing the same signals).
use anyhow::Context;
use clap::{Parser, Subcommand};
use harness::master::{Simulation, Trajectory};
use harness::scenarios::Law;
use harness::system::{split_path, ParamValue};
use std::path::PathBuf;

#[derive(Parser)]
#[command(
    name = "harness",
    version,
    about = "FMI 2.0 co-simulation master for the lunar-lander GNC and plant FMUs",
    long_about = "Loads FMI 2.0 Co-Simulation FMUs through their C ABI, connects them as a \
                  scenario describes (TOML or SSP .ssd), and flies the paper's powered descent.\n\
                  Built-in scenarios: paper (tilted start, phi_cmd = 150 deg at t = 0), upright \
                  (Table II literally), descent-roll (tilted start, phi_cmd at the descent), \
                  landing (the paper's descent, then a terminal descent to touchdown).",
    after_help = "Exit codes: 0 every run ended as its scenario expects (the `[verdict]` table \
                  of its TOML: completed, or landed inside the touchdown envelope); 1 error \
                  (bad input, FMU failure); 2 usage error; 3 a run was flown but its verdict \
                  failed (hard landing, touchdown when a hover was expected, ...)."
)]
struct Cli {
    /// Directory holding the FMUs named by the scenario (relative `fmu` paths).
    #[arg(
        long,
        global = true,
        default_value = "target/fmu",
        env = "LANDER_FMU_DIR"
    )]
    fmu_dir: PathBuf,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run one scenario (built-in name, .toml or .ssd) and write its results as CSV.
    Run {
        /// paper, upright, descent-roll, landing, or a path to a .toml/.ssd scenario.
        scenario: String,
        /// CSV output (header: time, instance.variable...).
        #[arg(long, short, default_value = "target/harness/run.csv")]
        out: PathBuf,
        /// Override a parameter, e.g. --set gnc.phi_cmd=0.5 (repeatable).
        #[arg(long = "set", value_name = "INSTANCE.VAR=VALUE")]
        sets: Vec<String>,
        /// Record only these columns (instance.variable, vectors allowed); default all outputs.
        #[arg(long)]
        record: Vec<String>,
        /// Exchange ordering, overriding the scenario's.
        #[arg(long, value_enum)]
        ordering: Option<OrderingArg>,
    },
    /// Fly a scenario with the coupled, decoupled and reduced laws: table, CSVs and plots.
    Paper {
        /// Scenario (default: the paper's).
        #[arg(default_value = "paper")]
        scenario: String,
        /// Where CSVs and PNG plots go.
        #[arg(long, default_value = "target/paper")]
        out_dir: PathBuf,
        /// Skip the PNG plots.
        #[arg(long)]
        no_plots: bool,
    },
    // Monte Carlo subcommands (harness/src/montecarlo/cli.rs).
    /// Monte Carlo campaign over phi_cmd x laws x dispersed runs: manifest.csv, campaign.toml
    /// and the paper's Monte Carlo figure.
    #[command(
        name = "monte-carlo",
        long_about = "Flies the scenario for every phi_cmd of the grid, every law and --runs \
                      dispersed runs (initial position, velocity, attitude, body rates, mass, \
                      plant inertia, thrust misalignment; ranges below).\n\
                      Run j's dispersions are a pure function of the campaign seed and j, and \
                      the same draw is flown by every law at every phi_cmd, so laws and \
                      phi_cmd points are compared on identical conditions. Results do not \
                      depend on --workers or --shard; any flight can be replayed bit-exactly \
                      with `harness replay`."
    )]
    MonteCarlo(harness::montecarlo::cli::MonteCarloArgs),
    /// Merge `monte-carlo --shard k/N` directories, checking for duplicate and missing flights.
    #[command(name = "merge-mc")]
    MergeMc(harness::montecarlo::cli::MergeArgs),
    /// Re-fly one Monte Carlo flight from its seed (or a manifest row) and write its full
    /// trajectory; from a manifest, check its metrics bit for bit.
    Replay(harness::montecarlo::cli::ReplayArgs),
    /// Write DIR/report.html: one self-contained page with the figures, tables and verdicts
    /// of a `paper` or `monte-carlo` output directory (merged or Dask campaigns too).
    Report {
        /// The output directory of `harness paper`, `monte-carlo` or `merge-mc`.
        dir: PathBuf,
    },
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum OrderingArg {
    GaussSeidel,
    Jacobi,
}

fn parse_set(text: &str) -> anyhow::Result<(String, String, ParamValue)> {
    let (path, value) = text
        .split_once('=')
        .with_context(|| format!("--set {text}: expected INSTANCE.VAR=VALUE"))?;
    let (instance, variable) =
        split_path(path).with_context(|| format!("--set {text}: expected INSTANCE.VAR=VALUE"))?;
    let value = if let Ok(i) = value.parse::<i64>() {
        ParamValue::Integer(i)
    } else if let Ok(x) = value.parse::<f64>() {
        ParamValue::Real(x)
    } else if let Ok(b) = value.parse::<bool>() {
        ParamValue::Boolean(b)
    } else {
        ParamValue::String(value.to_owned())
    };
    Ok((instance.to_owned(), variable.to_owned(), value))
}

fn main() -> anyhow::Result<()> {
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn")).init();
    let cli = Cli::parse();
    // 0, or harness::verdict::EXIT_FAILED_VERDICT when a run did not end as expected; errors
    // return through `?` (exit code 1).
    let mut exit_code = harness::verdict::EXIT_OK;
    match cli.command {
        Command::Run {
            scenario,
            out,
            sets,
            record,
            ordering,
        } => {
            let (mut system, spec) = harness::verdict::scenario::load(&scenario)?;
            for set in &sets {
                let (instance, variable, value) = parse_set(set)?;
                anyhow::ensure!(
                    system.set_parameter(&instance, &variable, value),
                    "--set {set}: no instance '{instance}'"
                );
            }
            if !record.is_empty() {
                system.record = Some(record);
            }
            match ordering {
                Some(OrderingArg::GaussSeidel) => {
                    system.ordering = harness::system::Ordering::GaussSeidel
                }
                Some(OrderingArg::Jacobi) => system.ordering = harness::system::Ordering::Jacobi,
                None => {}
            }
            let mut simulation = Simulation::new(system, &cli.fmu_dir)?;
            let mut trajectory = Trajectory {
                names: simulation.column_names().to_vec(),
                ..Default::default()
            };
            let end = simulation.run(&mut trajectory)?;
            harness::results::write_csv(&out, &trajectory)
                .with_context(|| format!("writing {}", out.display()))?;
            let verdict = harness::verdict::judge(&trajectory, &end, &spec.envelope);
            println!(
                "{}: {} rows x {} columns -> {}\nverdict: {}",
                simulation.system().name,
                trajectory.len(),
                trajectory.names.len() + 1,
                out.display(),
                verdict.describe(spec.expect)
            );
            exit_code = verdict.exit_code(spec.expect);
        }
        Command::Paper {
            scenario,
            out_dir,
            no_plots,
        } => {
            let (system, spec) = harness::verdict::scenario::load(&scenario)?;
            let name = system.name.clone();
            let flights = harness::paper::fly_all(system, &cli.fmu_dir, &Law::ALL, &spec.envelope)?;
            let summary = harness::paper::summary(&name, &flights, spec.expect);
            print!("{summary}");
            for flight in &flights {
                exit_code = exit_code.max(flight.verdict.exit_code(spec.expect));
            }
            for path in
                harness::paper::write_outputs(&flights, &out_dir, &name, &summary, !no_plots)?
            {
                println!("wrote {}", path.display());
            }
        }
        Command::MonteCarlo(args) => {
            exit_code = harness::montecarlo::cli::monte_carlo(&args, &cli.fmu_dir)?
        }
        Command::MergeMc(args) => exit_code = harness::montecarlo::cli::merge_mc(&args)?,
        Command::Replay(args) => harness::montecarlo::cli::replay(&args, &cli.fmu_dir)?,
        Command::Report { dir } => {
            println!("wrote {}", harness::report::for_directory(&dir)?.display())
        }
    }
    if exit_code != harness::verdict::EXIT_OK {
        std::process::exit(exit_code);
    }
    Ok(())
}
