//! `harness`: runs the lander FMUs, or any FMI 2.0 and 3.0 FMUs a scenario connects. The
//! command line only: what it flies is `lander`'s and `campaign`'s, what it draws `report`'s;
//! it adds the options, the printing and the exit codes.
use anyhow::Context;
use clap::{Parser, Subcommand};
use cosim::master::{MasterError, Trajectory};
use cosim::supervise::Runner;
use lander::laws::Laws;
use std::path::PathBuf;

mod broken_pipe;
mod dask;
mod fmu_dirs;
mod monte_carlo;
mod reference;
mod saved_runs;
mod scenario_campaign;
mod vars;

#[derive(Parser)]
#[command(
    name = "harness",
    version,
    about = "FMI 2.0 and 3.0 co-simulation master for the lunar-lander GNC and plant FMUs",
    long_about = long_about(),
    after_help = "Exit codes: 0 every run ended as its scenario expects (the `[verdict]` table \
                  of its TOML: completed, or landed inside the touchdown envelope); 1 error \
                  (bad input, FMU failure); 2 usage error; 3 a run was flown but its verdict \
                  failed (hard landing, touchdown when a hover was expected, ...)."
)]
struct Cli {
    /// Directory holding the FMUs named by the scenario (relative `fmu` paths not found
    /// beside the scenario file); repeat it to look in several, in order. Default:
    /// `target/fmu` in a source checkout, else the FMUs of the release the harness came in.
    #[arg(
        long,
        global = true,
        env = "LANDER_FMU_DIR",
        action = clap::ArgAction::Append
    )]
    fmu_dir: Vec<PathBuf>,
    /// Run the FMUs inside this process instead of a supervised worker process (for a
    /// debugger): an FMU that crashes, exits or hangs then takes the harness with it.
    #[arg(long, global = true)]
    in_process: bool,
    /// Longest one FMU call may take, in s, before the worker running it is killed and the
    /// run ends with an error naming the call (default 60, or the scenario's
    /// `[limits] call_timeout_s`).
    #[arg(long, global = true, value_name = "S")]
    call_timeout: Option<f64>,
    /// Longest one run (one flight) may take, in s (default 3600, or the scenario's
    /// `[limits] run_timeout_s`).
    #[arg(long, global = true, value_name = "S")]
    run_timeout: Option<f64>,
    /// Memory one worker process may take, in MB; an allocation beyond it fails (default 80 %
    /// of the memory available, or the scenario's `[limits] memory_mb`).
    #[arg(long, global = true, value_name = "MB")]
    memory_limit: Option<f64>,
    /// The most an FMU or SSP archive may unpack to (e.g. 500M, 8GiB; default 4GiB, or the
    /// HARNESS_MAX_UNPACKED_BYTES environment variable).
    #[arg(long, global = true, value_name = "SIZE", value_parser = fmi_abi::unpack::parse_byte_size)]
    max_unpacked: Option<u64>,
    #[command(subcommand)]
    command: Command,
}

// Every subcommand takes negative numbers as option values (`--phi-cmd-deg -30`), not only
// in the `--phi-cmd-deg=-30` form.
#[derive(Subcommand)]
enum Command {
    /// Run one scenario (built-in name, .toml, .ssd or .ssp package) and write its results
    /// (CSV, or an Arrow IPC file for a .arrow/.feather/.ipc name or --format arrow) as it
    /// runs: memory does not grow with the run's length.
    #[command(allow_negative_numbers = true)]
    Run {
        #[command(flatten)]
        request: RunRequest,
        /// Also write the verdict and every requirement as a JUnit XML report here.
        #[arg(long, value_name = "FILE")]
        junit: Option<PathBuf>,
        /// Fly the FMU over the experiment of its FMI-LS-REF references (their times, their
        /// input signals as --input) and judge each reference signal within its tolerance
        /// tube: a failed signal fails the run (exit code 3).
        #[arg(long)]
        check_reference: bool,
        #[command(flatten)]
        tolerances: reference::ToleranceArgs,
    },
    /// Run every scenario of a folder (.toml, .ssd, .ssp, and each .fmu alone; in name order)
    /// as `run` does and write one JUnit XML report: a test suite per scenario, a test case
    /// for its verdict and one per requirement. An FMU that carries FMI-LS-REF references is
    /// flown over their experiment and judged against them, a test case per signal, as `run
    /// --check-reference` does. Exit code 0 when all pass, 3 when one failed, 1 when one could
    /// not be run.
    Test {
        /// The folder of scenarios.
        dir: PathBuf,
        /// The JUnit XML report.
        #[arg(long, value_name = "FILE", default_value = "target/harness/junit.xml")]
        junit: PathBuf,
        /// Where each scenario's results go (<scenario file stem>.csv).
        #[arg(long, default_value = "target/harness/test")]
        out_dir: PathBuf,
        #[command(flatten)]
        tolerances: reference::ToleranceArgs,
    },
    /// Print a shell completion script, e.g. `harness completions bash >
    /// ~/.local/share/bash-completion/completions/harness`.
    Completions {
        /// bash, zsh, fish, elvish or powershell.
        shell: clap_complete::Shell,
    },
    /// List an FMU's variables: name, causality, variability, type, start, unit,
    /// description (tab-separated, one per line).
    Vars {
        /// The FMU file (a relative path is also looked up in the FMU directory).
        fmu: PathBuf,
        /// Only variables of this causality (parameter, calculatedParameter, input, output,
        /// local, independent).
        #[arg(long)]
        causality: Option<String>,
    },
    /// Fly a scenario with each control law of the GNC FMU: table, CSVs and plots.
    #[command(allow_negative_numbers = true)]
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
        /// Format of the trajectory files (<scenario>-<law>.csv or .arrow).
        #[arg(long, value_enum, default_value = "csv")]
        format: cosim::results::Format,
        /// Override a parameter for every law's flight, e.g. --set gnc.phi_cmd=0.5
        /// (repeatable; gnc.control_law is what the command varies).
        #[arg(long = "set", value_name = "INSTANCE.VAR=VALUE")]
        sets: Vec<String>,
    },
    /// Fly a scenario with a retarget (default: the shipped `retarget`) with the coupled and
    /// decoupled laws, each with the divert re-planned and with the target only moved: the
    /// divert's overshoot, final error, peak tilt and settling time, CSVs and a figure.
    #[command(allow_negative_numbers = true)]
    Retarget {
        /// Scenario: a built-in name or a .toml/.ssd/.ssp that sets gnc.retarget_time.
        #[arg(default_value = "retarget")]
        scenario: String,
        /// Where CSVs, the summary and the PNG figure go.
        #[arg(long, default_value = "target/retarget")]
        out_dir: PathBuf,
        /// Skip the PNG figure.
        #[arg(long)]
        no_plots: bool,
    },
    /// Fly a scenario to a time and linearize it there: every FMU's Jacobians (from its
    /// directional derivatives, or finite differences when it provides none), the closed
    /// loop's eigenvalues, and per attitude axis the gain and phase margins with the loop
    /// broken at the torque command, beside the controller's design values
    /// (docs/linearize.md).
    #[command(allow_negative_numbers = true)]
    Linearize {
        /// Scenario: a built-in name, .toml, .ssd or .ssp.
        scenario: String,
        /// The time to linearize at, s (the communication point nearest it).
        #[arg(long, value_name = "T")]
        at: f64,
        /// Where the Jacobians come from: `fmu` (each FMU's directional derivatives where
        /// its description declares them, else finite differences) or `fd` (finite
        /// differences for every FMU).
        #[arg(long, value_enum, default_value = "fmu")]
        jacobian: JacobianArg,
        /// Override a parameter, e.g. --set plant.inertia_body[2]=450 (repeatable).
        #[arg(long = "set", value_name = "INSTANCE.VAR=VALUE")]
        sets: Vec<String>,
        /// Also write everything (every matrix) as JSON to this file.
        #[arg(short, long, value_name = "FILE")]
        out: Option<PathBuf>,
        /// Print the JSON instead of the summary.
        #[arg(long)]
        json: bool,
    },
    // Monte Carlo subcommands (harness/src/monte_carlo.rs).
    /// Monte Carlo campaign over phi_cmd x laws x dispersed runs: manifest.csv, campaign.toml
    /// and the paper's Monte Carlo figure.
    #[command(
        name = "monte-carlo",
        allow_negative_numbers = true,
        long_about = "Flies the scenario for every phi_cmd of the grid, every law and --runs \
                      dispersed runs (initial position, velocity, attitude, body rates, mass, \
                      plant inertia, thrust misalignment; ranges below). A scenario with \
                      instances `nav`, `sensors` or `filter` also draws per run the navigation \
                      errors' and the sensors' noise seeds, and starts the filter from the \
                      run's dispersed truth off by an error drawn from the covariance it claims \
                      (r0_sigma, v0_sigma, attitude0_sigma).\n\
                      Run j's dispersions are a pure function of the campaign seed and j, and \
                      the same draw is flown by every law at every phi_cmd, so laws and \
                      phi_cmd points are compared on identical conditions. Results do not \
                      depend on --workers or --shard; any flight can be replayed bit-exactly \
                      with `harness replay`."
    )]
    MonteCarlo(monte_carlo::MonteCarloArgs),
    /// The campaign a scenario's [campaign] table declares: its parameters swept and
    /// dispersed, each run judged by its requirements (docs/campaigns.md).
    #[command(allow_negative_numbers = true)]
    Campaign(scenario_campaign::CampaignArgs),
    /// Merge `monte-carlo --shard k/N` (or `campaign --shard k/N`) directories, checking for
    /// duplicate and missing flights.
    #[command(name = "merge-mc", allow_negative_numbers = true)]
    MergeMc(monte_carlo::MergeArgs),
    /// Re-fly one Monte Carlo flight from its seed (or a manifest row) and write its full
    /// trajectory; from a manifest, check its metrics bit for bit.
    #[command(allow_negative_numbers = true)]
    Replay(monte_carlo::ReplayArgs),
    /// Write DIR/report.html: one self-contained page with the figures, tables and verdicts
    /// of a `paper`, `test`, `monte-carlo` or `campaign` output directory (merged or Dask
    /// campaigns too);
    /// or, given the results of `harness run` (X.csv), X.report.html: its verdict,
    /// requirements, FMUs and a figure of each requirement's signals.
    Report {
        /// The output directory of `harness paper`, `test`, `monte-carlo` or `merge-mc`, or
        /// the result file of `harness run`.
        dir: PathBuf,
    },
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum JacobianArg {
    Fmu,
    Fd,
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum OrderingArg {
    GaussSeidel,
    Jacobi,
}

/// Passes records on to env_logger, except the FMU errors: each one comes back in the error
/// that ends the run, with the FMU's log, and printing it here too showed it twice.
struct Logger(env_logger::Logger);

impl log::Log for Logger {
    fn enabled(&self, metadata: &log::Metadata) -> bool {
        self.0.enabled(metadata)
    }
    fn log(&self, record: &log::Record) {
        let carried_by_the_error =
            record.target() == "harness::fmu" && record.level() == log::Level::Error;
        if !carried_by_the_error {
            self.0.log(record);
        }
    }
    fn flush(&self) {
        self.0.flush();
    }
}

/// The most values (communication points x columns, `time` included) one `harness run`
/// records without `--force`: about 12 GB of CSV (11.8 bytes a value, measured on the
/// paper scenario) or 8 GB of Arrow. The paper scenario records 1.55e6.
const MAX_RECORDED_VALUES: f64 = 1e9;
/// Bytes a recorded value takes in a CSV, on average (the paper scenario's 18,247,268
/// bytes for 17,201 rows of 90 columns).
const CSV_BYTES_PER_VALUE: f64 = 11.8;

/// `harness run` streams its rows to the results file and holds only the requirements'
/// signals up to their horizon (and one Arrow batch). Refused before the run, with the
/// estimate: a run that would record more than [`MAX_RECORDED_VALUES`] (unless `force`),
/// and one whose held rows could not fit in this machine's memory (even with `force`: it
/// would abort).
fn check_run_size(
    simulation: &Runner,
    kept: &cosim::requirements::Kept,
    format: cosim::results::Format,
    force: bool,
) -> anyhow::Result<()> {
    let system = simulation.system();
    let duration = system.stop_time - system.start_time;
    let points = (duration / system.step_size).ceil() + 1.0;
    let columns = simulation.column_names().len() + 1;
    let values = points * columns as f64;
    let steps = format!(
        "{duration} s in steps of {} s is {points:.3e} communication points",
        system.step_size
    );
    if values > MAX_RECORDED_VALUES && !force {
        let size = match format {
            cosim::results::Format::Csv => {
                format!("{:.3e} bytes of CSV", values * CSV_BYTES_PER_VALUE)
            }
            cosim::results::Format::Arrow => format!("{:.3e} bytes of Arrow", values * 8.0),
        };
        anyhow::bail!(
            "{steps}; recording {columns} columns of each is {values:.3e} values, about \
             {size}, beyond the {MAX_RECORDED_VALUES:.0e} values one run may record \
             without --force: use a larger step_size or record fewer columns (`record = \
             [...]` in the scenario, or --record), or give --force to run it anyway"
        );
    }
    let kept_rows = points.min((kept.horizon_s() / system.step_size).ceil() + 1.0);
    let held = 8.0
        * (kept_rows * kept.width() as f64
            + cosim::results::Stream::buffered_values(format, columns - 1) as f64);
    if let Some(available) = cosim::memory::available_bytes() {
        if held > cosim::memory::USABLE_FRACTION * available {
            anyhow::bail!(
                "{steps}; judging the scenario's requirements keeps {} values (the time and \
                 the signals they read) of each of the first {kept_rows:.3e} (their {} s \
                 horizon), {held:.3e} bytes of memory, more than the {:.1} GB this machine \
                 has available, with --force or without: use a larger step_size",
                kept.width(),
                kept.horizon_s(),
                available / 1e9
            );
        }
    }
    Ok(())
}

/// What `harness run` records: every row streamed to the results file, the rows its
/// requirements read (up to their horizon) and the last row, which the verdict reads.
struct RunRecorder {
    out: cosim::results::Stream,
    kept: cosim::requirements::Kept,
    last_time: Option<f64>,
    last: Vec<f64>,
    /// Simulated time on a terminal's stderr (none when stderr is a file or a pipe), and the
    /// time of its next update (every 0.5 % of the run).
    progress: Option<(indicatif::ProgressBar, f64, f64)>,
}

impl cosim::master::Recorder for RunRecorder {
    fn record(&mut self, time: f64, values: &[f64]) {
        self.out.record(time, values);
        self.kept.record(time, values);
        self.last_time = Some(time);
        self.last.copy_from_slice(values);
        if let Some((bar, next, every)) = &mut self.progress {
            if time >= *next {
                // Milliseconds of simulated time: the bar's unit.
                bar.set_position((time * 1e3) as u64);
                bar.set_message(format!("{time:.1} s"));
                *next = time + *every;
            }
        }
    }

    fn failure(&self) -> Option<String> {
        self.out.failure()
    }

    fn record_text(&mut self, column: usize, text: &str) {
        self.out.record_text(column, text);
    }
}

/// A progress bar of simulated time for a run on a terminal.
fn run_progress(
    system: &cosim::system::SystemDescription,
) -> Option<(indicatif::ProgressBar, f64, f64)> {
    use std::io::IsTerminal;
    if !std::io::stderr().is_terminal() {
        return None;
    }
    let bar = indicatif::ProgressBar::new((system.stop_time * 1e3) as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{prefix} [{bar:40}] t = {msg} ({elapsed} elapsed, {eta} left)",
        )
        .ok()?
        .progress_chars("=> "),
    );
    bar.set_prefix(system.name.clone());
    bar.set_position((system.start_time * 1e3) as u64);
    let every = (system.stop_time - system.start_time) / 200.0;
    Some((bar, system.start_time, every))
}

impl RunRecorder {
    /// The run's last row as a one-row trajectory with every column's name: all that
    /// [`lander::verdict::judge`] reads.
    fn last_row(&self, names: &[String]) -> Trajectory {
        Trajectory {
            names: names.to_vec(),
            times: self.last_time.into_iter().collect(),
            values: if self.last_time.is_some() {
                self.last.clone()
            } else {
                Vec::new()
            },
        }
    }
}

/// The columns the landing verdict reads that a `record` list left out, where the instance
/// `plant` declares them: read once, at the end of the run, so that recording a few signals
/// does not leave a landing unjudged. Nothing for a system without that instance or list.
fn set_verdict_columns(simulation: &mut Runner) -> anyhow::Result<()> {
    let system = simulation.system();
    let Some(plant) = system.instances.iter().position(|i| i.name == "plant") else {
        return Ok(());
    };
    if system.record.is_none() {
        return Ok(());
    }
    let (_, description) = simulation.description(plant);
    let recorded = simulation.column_names();
    let wanted: Vec<String> = lander::verdict::VERDICT_COLUMNS
        .iter()
        .chain(&["plant.tipped_over"])
        .filter(|column| {
            !recorded.iter().any(|r| {
                r == *column || r.strip_prefix(*column).is_some_and(|i| i.starts_with('['))
            })
        })
        .filter(|column| {
            let name = column.strip_prefix("plant.").unwrap_or(column);
            description.variable(name).is_some()
                || description.variable(&format!("{name}[1]")).is_some()
        })
        .map(|column| column.to_string())
        .collect();
    simulation.set_final_columns(&wanted)?;
    Ok(())
}

/// `path` with `.partial` appended: where a run writes until it has finished.
fn partial_path(path: &std::path::Path) -> PathBuf {
    let mut name = path.as_os_str().to_owned();
    name.push(".partial");
    PathBuf::from(name)
}

fn init_logging() {
    let logger =
        env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn")).build();
    let max_level = logger.filter();
    if log::set_boxed_logger(Box::new(Logger(logger))).is_ok() {
        log::set_max_level(max_level);
    }
}

fn main() {
    broken_pipe::end_quietly_when_stdout_closes();
    // Warnings (an allowed non-finite value, say) go to stderr, which a worker's parent
    // passes on.
    init_logging();
    // Started as a supervised worker: serve the parent and exit.
    cosim::supervise::serve_if_worker();
    dask::know_command_line(<Cli as clap::CommandFactory>::command());
    let cli = Cli::parse();
    match run(cli) {
        Ok(code) => std::process::exit(code),
        Err(error) => {
            // A user's mistake is said in words: `main` returning the error would print its
            // backtrace too whenever RUST_BACKTRACE is set. Internal panics keep theirs.
            eprintln!("Error: {error}");
            let causes: Vec<_> = error.chain().skip(1).collect();
            if !causes.is_empty() {
                eprintln!("\nCaused by:");
                for cause in causes {
                    eprintln!("    {cause}");
                }
            }
            std::process::exit(1);
        }
    }
}

/// The command's exit code, or the error that stopped it (exit code 1).
fn run(cli: Cli) -> anyhow::Result<i32> {
    // 0, or lander::verdict::EXIT_FAILED_VERDICT when a run did not end as expected; errors
    // return through `?` (exit code 1).
    let mut exit_code = lander::verdict::EXIT_OK;
    set_execution(&cli)?;
    // The first directory is the one every command is given; the others are searched after
    // it wherever a relative FMU path is resolved.
    let fmu_dirs = if cli.fmu_dir.is_empty() {
        fmu_dirs::default_fmu_dirs()
    } else {
        cli.fmu_dir.clone()
    };
    let fmu_dir = fmu_dirs.first().cloned().unwrap_or_default();
    cosim::master::set_more_fmu_dirs(fmu_dirs.iter().skip(1).cloned().collect());
    match cli.command {
        Command::Run {
            request,
            junit,
            check_reference,
            tolerances,
        } => {
            let started = std::time::Instant::now();
            let flown = if check_reference {
                reference::run_checked(&request, &tolerances, true, |r| run_scenario(r, &fmu_dir))
            } else {
                run_scenario(&request, &fmu_dir)
            };
            let flown = match flown {
                Ok(flown) => flown,
                Err(error) => {
                    // A CI job reads the report: it says why there is no run.
                    if let Some(path) = &junit {
                        let suite = cosim::requirements::junit::error_suite(
                            &suite_name(&request.scenario),
                            started.elapsed().as_secs_f64(),
                            &format!("could not be run: {error:#}"),
                        );
                        cosim::requirements::junit::write(path, &[suite])?;
                    }
                    return Err(error);
                }
            };
            exit_code = flown.exit_code;
            // Beside the results, what `harness report` makes a page of.
            let verdict = verdict_path(&request.out);
            cosim::requirements::junit::write_verdicts(
                &verdict,
                std::slice::from_ref(&flown.suite),
            )?;
            if let Some(path) = junit {
                cosim::requirements::junit::write(&path, &[flown.suite])?;
                println!("wrote {}", path.display());
            }
        }
        Command::Test {
            dir,
            junit,
            out_dir,
            tolerances,
        } => exit_code = test_folder(&dir, &junit, &out_dir, &fmu_dir, &tolerances)?,
        Command::Completions { shell } => {
            use clap::CommandFactory;
            clap_complete::generate(
                shell,
                &mut Cli::command(),
                "harness",
                &mut std::io::stdout(),
            );
        }
        Command::Vars { fmu, causality } => {
            let only = match causality.as_deref() {
                None => None,
                Some(text) => Some(vars::parse_causality(text).ok_or_else(|| {
                    anyhow::anyhow!(
                        "--causality {text}: not a causality (parameter, calculatedParameter, \
                         input, output, local, independent)"
                    )
                })?),
            };
            let path = if fmu.exists() || fmu.is_absolute() {
                fmu.clone()
            } else {
                cosim::master::fmu_path(&fmu_dir, &fmu)
            };
            // The description alone: listing variables runs no FMU code.
            let (_, description, declared) = fmi_import::read_description_typed(&path)
                .with_context(|| format!("loading {}", fmu.display()))?;
            print!("{}", vars::table(&description, &declared, only));
        }
        Command::Paper {
            scenario,
            out_dir,
            no_plots,
            format,
            sets,
        } => {
            let (mut system, spec) = lander::scenarios::spec::load(&scenario)?;
            let (problems, _) = lander::overrides::apply_sets(
                &mut system,
                &sets,
                &[(
                    "gnc.control_law",
                    "it flies each law of the GNC FMU in turn",
                )],
            );
            if !problems.is_empty() {
                anyhow::bail!("{}", problems.join("\n"));
            }
            let requirements = lander::scenarios::spec::requirements(&scenario)?;
            let name = system.name.clone();
            let laws = Laws::of_instance(&system, "gnc", &fmu_dir)?;
            let own = lander::paper::scenario_law(&system, &laws);
            let flights = lander::paper::fly_all(
                system,
                &fmu_dir,
                &laws.all(),
                &spec.envelope,
                &requirements,
            )?;
            let summary = lander::paper::summary(&name, &flights, spec.expect, own);
            print!("{summary}");
            exit_code = exit_code.max(lander::paper::exit_code(&flights, spec.expect, own));
            let mut written =
                lander::paper::write_results(&flights, &out_dir, &name, &summary, format)?;
            if !no_plots {
                written.extend(report::plots::paper_figures(&flights, &out_dir, &name)?);
            }
            written.extend(lander::paper::write_provenance(&flights, &out_dir)?);
            written.push(report::html::write(
                &out_dir,
                &format!("lander-fmi: scenario '{name}' flown with each control law"),
                &[],
            )?);
            for path in written {
                println!("wrote {}", path.display());
            }
        }
        Command::Retarget {
            scenario,
            out_dir,
            no_plots,
        } => {
            let (system, spec) = lander::scenarios::spec::load(&scenario)?;
            let name = system.name.clone();
            let (command, flights) = lander::retarget::fly_all(
                system,
                &fmu_dir,
                &lander::retarget::LAWS,
                &spec.envelope,
            )?;
            let summary = lander::retarget::table(&name, &command, &flights);
            print!("{summary}");
            let mut written = lander::retarget::write_results(&flights, &out_dir, &name, &summary)?;
            if !no_plots {
                written.extend(report::plots::retarget::figures(
                    &flights, &command, &out_dir, &name,
                )?);
            }
            for path in written {
                println!("wrote {}", path.display());
            }
        }
        Command::Linearize {
            scenario,
            at,
            jacobian,
            sets,
            out,
            json,
        } => {
            let request = lander::linearize::Request {
                scenario: &scenario,
                at_s: at,
                sets: &sets,
                jacobians: match jacobian {
                    JacobianArg::Fmu => cosim::master::Jacobians::Fmu,
                    JacobianArg::Fd => cosim::master::Jacobians::Differences,
                },
            };
            let linearized = lander::linearize::linearize(&request, &fmu_dir)?;
            let document = serde_json::to_string_pretty(&linearized.to_json())?;
            if json {
                println!("{document}");
            } else {
                print!("{}", linearized.summary());
            }
            if let Some(path) = out {
                std::fs::write(&path, format!("{document}\n"))
                    .with_context(|| format!("cannot write {}", path.display()))?;
                if !json {
                    println!("wrote {}", path.display());
                }
            }
        }
        Command::MonteCarlo(args) => exit_code = monte_carlo::monte_carlo(&args, &fmu_dir)?,
        Command::Campaign(args) => exit_code = scenario_campaign::campaign(&args, &fmu_dir)?,
        Command::MergeMc(args) if scenario_campaign::is_scenario_campaign(&args.inputs) => {
            exit_code = scenario_campaign::merge(&args.inputs, &args.out_dir, args.allow_missing)?
        }
        Command::MergeMc(args) => exit_code = monte_carlo::merge_mc(&args)?,
        Command::Replay(args) => monte_carlo::replay(&args, &fmu_dir)?,
        Command::Report { dir } => {
            let page = if dir.is_file() {
                report::html::for_run(&dir)?
            } else {
                report::html::for_directory(&dir)?
            };
            println!("wrote {}", page.display())
        }
    }
    Ok(exit_code)
}

/// Where flights run: a supervised worker (this program again) unless `--in-process`.
fn set_execution(cli: &Cli) -> anyhow::Result<()> {
    let limits = cosim::supervise::Limits {
        call_timeout_s: cli.call_timeout,
        run_timeout_s: cli.run_timeout,
        memory_mb: cli.memory_limit,
    };
    let problems = limits.problems("command line");
    if !problems.is_empty() {
        anyhow::bail!("{}", problems.join("\n"));
    }
    if let Some(bytes) = cli.max_unpacked {
        fmi_abi::unpack::set_max_unpacked_bytes(bytes);
    }
    let execution = if cli.in_process {
        cosim::supervise::Execution::InProcess
    } else {
        let program = std::env::current_exe()
            .context("finding the harness's own program to start its worker processes")?;
        cosim::supervise::Execution::Supervised { program, limits }
    };
    cosim::supervise::set_default(execution);
    Ok(())
}

/// `harness test DIR`: see its help.
fn test_folder(
    dir: &std::path::Path,
    junit: &std::path::Path,
    out_dir: &std::path::Path,
    fmu_dir: &std::path::Path,
    tolerances: &reference::ToleranceArgs,
) -> anyhow::Result<i32> {
    let entries =
        std::fs::read_dir(dir).with_context(|| format!("reading the folder {}", dir.display()))?;
    let mut scenarios: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            matches!(
                p.extension().and_then(|e| e.to_str()),
                Some("toml" | "ssd" | "ssp" | "fmu")
            )
        })
        .collect();
    scenarios.sort();
    if scenarios.is_empty() {
        anyhow::bail!(
            "{}: no scenario (.toml, .ssd, .ssp) or FMU (.fmu) in it",
            dir.display()
        );
    }
    let (mut failed, mut broken) = (0, 0);
    let mut suites = Vec::new();
    for path in &scenarios {
        let stem = path
            .file_stem()
            .map_or_else(String::new, |s| s.to_string_lossy().into_owned());
        // An FMU beside the scenario of the same name gets results of its own.
        let out = match path.extension().and_then(|e| e.to_str()) {
            Some("fmu") => format!("{stem}.fmu.csv"),
            _ => format!("{stem}.csv"),
        };
        let request = RunRequest {
            scenario: path.to_string_lossy().into_owned(),
            out: out_dir.join(out),
            sets: Vec::new(),
            record: Vec::new(),
            ordering: None,
            format: None,
            force: false,
            stop_time: None,
            step_size: None,
            start_time: None,
            interface: Vec::new(),
            input: None,
            state: Default::default(),
        };
        let started = std::time::Instant::now();
        // An FMU without references is flown as any scenario is.
        match reference::run_checked(&request, tolerances, false, |r| run_scenario(r, fmu_dir)) {
            Ok(flown) => {
                match flown.exit_code {
                    lander::verdict::EXIT_OK => {}
                    lander::verdict::EXIT_ERROR => broken += 1,
                    _ => failed += 1,
                }
                suites.push(flown.suite);
            }
            Err(error) => {
                broken += 1;
                let message = format!("could not be run: {error:#}");
                eprintln!("{}: {message}", path.display());
                suites.push(cosim::requirements::junit::error_suite(
                    &suite_name(&path.to_string_lossy()),
                    started.elapsed().as_secs_f64(),
                    &message,
                ));
            }
        }
    }
    cosim::requirements::junit::write(junit, &suites)?;
    cosim::requirements::junit::write_verdicts(
        &out_dir.join(cosim::requirements::junit::VERDICTS_FILE),
        &suites,
    )?;
    println!(
        "{} scenarios: {} passed, {failed} failed, {broken} could not be run -> {}",
        scenarios.len(),
        scenarios.len() - failed - broken,
        junit.display()
    );
    Ok(if broken > 0 {
        lander::verdict::EXIT_ERROR
    } else if failed > 0 {
        lander::verdict::EXIT_FAILED_VERDICT
    } else {
        lander::verdict::EXIT_OK
    })
}

/// `DIR/x.verdict.toml` for the results `DIR/x.csv`: the run's verdict, requirements and
/// FMUs, which `harness report DIR/x.csv` reads.
fn verdict_path(out: &std::path::Path) -> PathBuf {
    out.with_extension("verdict.toml")
}

/// The FMUs of a run as a report shows them.
fn fmu_facts(simulation: &Runner) -> Vec<cosim::requirements::junit::FmuFacts> {
    lander::provenance::Provenance::of(simulation)
        .instance
        .into_iter()
        .map(|i| cosim::requirements::junit::FmuFacts {
            instance: i.name,
            fmu: i.fmu,
            model_name: i.model_name,
            fmi_version: i.fmi_version,
            model_version: i.version,
            generation_tool: i.generation_tool,
            generation_date: i.generation_date,
        })
        .collect()
}

/// The built-in scenarios' names, comma-separated.
fn built_in_names() -> String {
    let names: Vec<&str> = lander::scenarios::BUILT_IN
        .iter()
        .map(|(n, _)| *n)
        .collect();
    names.join(", ")
}

fn long_about() -> String {
    format!(
        "Loads FMI 2.0 and 3.0 FMUs (Co-Simulation and Model Exchange) through their C ABI, in a \
         supervised worker process, connects them as a scenario describes (TOML, SSP .ssd or \
         .ssp package), flies it and judges it.\nBuilt-in scenarios: {}.",
        built_in_names()
    )
}

/// What `harness run` flies.
#[derive(clap::Args, Clone)]
struct RunRequest {
    #[arg(help = format!(
        "{} (the files of harness/scenarios/), or a path to a .toml/.ssd scenario, an .ssp \
         package, or one .fmu run alone over its DefaultExperiment",
        built_in_names()
    ))]
    scenario: String,
    /// Output file (columns: time, instance.variable...), written row by row under
    /// OUT.partial and renamed to OUT when the run has ended.
    #[arg(long, short, default_value = "target/harness/run.csv")]
    out: PathBuf,
    /// Output format; default: by the output's extension (.csv or none: CSV; .arrow,
    /// .feather, .ipc: Arrow IPC file); any other extension needs --format.
    #[arg(long, value_enum)]
    format: Option<cosim::results::Format>,
    /// Override a parameter, e.g. --set gnc.phi_cmd=0.5 (repeatable).
    #[arg(long = "set", value_name = "INSTANCE.VAR=VALUE")]
    sets: Vec<String>,
    /// Record only these columns (instance.variable, vectors allowed; comma-separated or
    /// repeated; the bare variable for one FMU run alone); default all outputs.
    #[arg(long, value_delimiter = ',')]
    record: Vec<String>,
    /// Exchange ordering, overriding the scenario's.
    #[arg(long, value_enum)]
    ordering: Option<OrderingArg>,
    /// Run even if it would record more than 1e9 values (communication points x columns),
    /// which is refused by default with the estimate of its size.
    #[arg(long)]
    force: bool,
    /// Stop time in s, overriding the scenario's.
    #[arg(long, value_name = "S")]
    stop_time: Option<f64>,
    /// Communication step in s, overriding the scenario's.
    #[arg(long, value_name = "S")]
    step_size: Option<f64>,
    /// Drive inputs from a CSV table: a first column `time`, one column per input
    /// (instance.variable, or the bare variable for one FMU run alone), as fmpy and fmusim
    /// read it. Real inputs are interpolated linearly, others held.
    #[arg(long, value_name = "FILE.csv")]
    input: Option<PathBuf>,
    /// Start time in s, overriding the scenario's.
    #[arg(long, value_name = "S", allow_negative_numbers = true)]
    start_time: Option<f64>,
    /// The FMI interface to run through: co-simulation or model-exchange, for every instance
    /// or, as INSTANCE=KIND, for one (repeatable). Default: the scenario's, else the one the
    /// FMU declares when it has one only, else co-simulation.
    #[arg(long, value_name = "[INSTANCE=]KIND")]
    interface: Vec<String>,
    #[command(flatten)]
    state: saved_runs::StateArgs,
}

/// A scenario's JUnit suite name: its file stem (a built-in's name), the same whether it
/// could be run or not, so that a CI system's history of it survives a fix.
fn suite_name(scenario: &str) -> String {
    std::path::Path::new(scenario)
        .file_stem()
        .map_or_else(|| scenario.to_owned(), |s| s.to_string_lossy().into_owned())
}

/// A flown scenario: the exit code its verdict and requirements give, and its JUnit suite.
struct Flown {
    exit_code: i32,
    suite: cosim::requirements::junit::Suite,
}

/// `harness run`: every problem refused before the run, the run, its results written, the
/// verdict and the requirements printed.
fn run_scenario(request: &RunRequest, fmu_dir: &std::path::Path) -> anyhow::Result<Flown> {
    let RunRequest {
        scenario,
        out,
        sets,
        record,
        ordering,
        format,
        force,
        stop_time,
        step_size,
        start_time,
        interface,
        input,
        state,
    } = request;
    let started = std::time::Instant::now();
    // A saved run to continue is read whole before anything is loaded.
    let checkpoints = state.checkpoints()?;
    let (mut system, spec) = lander::scenarios::spec::load(scenario)?;
    let requirements = lander::scenarios::spec::requirements(scenario)?;
    let (mut problems, seen) = lander::overrides::apply_sets(&mut system, sets, &[]);
    problems.extend(lander::overrides::apply_interfaces(&mut system, interface));
    if let Some(path) = input {
        match cosim::system::InputTable::read_csv(path) {
            Ok(mut table) => {
                table.names = lander::overrides::qualified(&system, &table.names);
                system.inputs = Some(table);
            }
            Err(error) => problems.push(format!("--input: {error}")),
        }
    }
    if let Some(start) = start_time {
        system.start_time = *start;
    }
    if let Some(stop) = stop_time {
        system.stop_time = *stop;
    }
    if let Some(step) = step_size {
        system.step_size = *step;
    }
    if start_time.is_some() || stop_time.is_some() || step_size.is_some() {
        if let Err(error) = system.validate() {
            problems.push(format!("--start-time/--stop-time/--step-size: {error}"));
        }
    }

    let format = cosim::results::Format::for_output(out, *format)
        .map_err(|problem| problems.push(format!("-o/--format: {problem}")))
        .ok();
    if !record.is_empty() {
        system.record = Some(lander::overrides::qualified(&system, record));
    }
    if let Some(list) = system.record.as_mut() {
        cosim::requirements::record_signals(list, &requirements);
    }
    match ordering {
        Some(OrderingArg::GaussSeidel) => system.ordering = cosim::system::Ordering::GaussSeidel,
        Some(OrderingArg::Jacobi) => system.ordering = cosim::system::Ordering::Jacobi,
        None => {}
    }
    if let Some(note) = system.partial_last_step() {
        eprintln!("harness: warning: {note}");
    }
    let simulation = Runner::new(system, fmu_dir);
    if let Err(MasterError::Resolve { problems: more, .. }) = &simulation {
        // Say which problems come from the command line, not the scenario file.
        problems.extend(more.iter().map(|problem| {
            let from = seen.iter().find(|(instance, variable, _)| {
                problem.starts_with(&format!("instance '{instance}': "))
                    && problem.contains(&format!("'{variable}'"))
            });
            match from {
                Some((_, _, text)) => format!("{problem} (from --set {text})"),
                None => problem.clone(),
            }
        }));
    }
    if let Ok(simulation) = &simulation {
        problems.extend(cosim::requirements::unrecorded(
            &requirements,
            simulation.column_names(),
        ));
        problems.extend(cosim::requirements::not_numbers(
            &requirements,
            simulation.column_names(),
            &simulation.column_types(),
        ));
    }
    if !problems.is_empty() {
        match &simulation {
            Err(MasterError::Resolve { system, .. }) => anyhow::bail!(
                "system '{system}' does not match its FMUs:\n  {}",
                problems.join("\n  ")
            ),
            _ => anyhow::bail!("{}", problems.join("\n")),
        }
    }
    let simulation = simulation?;
    let format = format.expect("refused before the run");
    let kept = cosim::requirements::Kept::new(&requirements, simulation.column_names());
    check_run_size(&simulation, &kept, format, *force)?;
    let mut simulation = simulation;
    set_verdict_columns(&mut simulation)?;
    state.set_checkpoints(&mut simulation, &checkpoints)?;
    let kept = state.continue_requirements(kept, &checkpoints)?;
    // Rows go to the file as they are recorded, under a temporary name until the run has
    // ended: a failed or interrupted run never leaves a truncated file under `out`.
    let partial = partial_path(out);
    let mut recorder = RunRecorder {
        out: cosim::results::Stream::create_typed(
            &partial,
            simulation.column_names(),
            simulation.column_units(),
            &simulation.column_types(),
            format,
        )
        .with_context(|| format!("writing {}", out.display()))?,
        kept,
        last_time: None,
        last: vec![0.0; simulation.column_names().len()],
        progress: run_progress(simulation.system()),
    };
    let finished = simulation.run(&mut recorder);
    if let Some((bar, _, _)) = recorder.progress.take() {
        bar.finish_and_clear();
    }
    let last = recorder.last_row(simulation.column_names());
    let RunRecorder {
        out: stream, kept, ..
    } = recorder;
    let end = match finished {
        Ok(end) => end,
        Err(error) => {
            // The rows recorded before stay, under the partial name, for the user to see
            // where the run went.
            let kept_rows = stream.finish().ok();
            let message = format!("{:#}", anyhow::Error::from(error));
            let name = &simulation.system().name;
            match (kept_rows, last.times.last()) {
                (Some(rows), Some(t)) => println!(
                    "{name}: the run failed; its {rows} rows up to t = {t} s are in {}",
                    partial.display()
                ),
                (None, Some(_)) => {
                    let _ = std::fs::remove_file(&partial);
                    println!("{name}: the run failed, and so did writing its rows");
                }
                (_, None) => {
                    let _ = std::fs::remove_file(&partial);
                    println!("{name}: the run failed before its first row");
                }
            }
            println!("verdict: error: {message}");
            let mut suite = cosim::requirements::junit::error_suite(
                &suite_name(scenario),
                started.elapsed().as_secs_f64(),
                &message,
            );
            suite.system_err = Some(simulation.take_stderr()).filter(|e| !e.is_empty());
            return Ok(Flown {
                exit_code: lander::verdict::EXIT_ERROR,
                suite,
            });
        }
    };
    let written = (|| {
        let rows = stream
            .finish()
            .with_context(|| format!("writing {}", out.display()))?;
        std::fs::rename(&partial, out).with_context(|| format!("writing {}", out.display()))?;
        if format == cosim::results::Format::Csv {
            let units = cosim::results::units_path(out);
            cosim::results::write_units(&units, &last.names, simulation.column_units())
                .with_context(|| format!("writing {}", units.display()))?;
        }
        anyhow::Ok(rows)
    })();
    let rows = match written {
        Ok(rows) => rows,
        Err(error) => {
            let _ = std::fs::remove_file(&partial);
            return Err(error);
        }
    };
    let mut last = last;
    if !last.values.is_empty() {
        last.names
            .extend(simulation.final_column_names().iter().cloned());
        last.values.extend_from_slice(simulation.final_values());
    }
    let verdict = lander::verdict::judge(&last, &end, &spec.envelope);
    println!(
        "{}: {} rows x {} columns -> {}\nverdict: {}",
        simulation.system().name,
        rows,
        last.names.len() + 1,
        out.display(),
        verdict.describe(spec.expect)
    );
    for (instance, events) in &simulation.model_exchange_events() {
        println!(
            "{instance} (Model Exchange): {} state, {} time and {} step events",
            events.state, events.time, events.step
        );
    }
    for line in cosim::master::event_outcomes(simulation.system(), &end) {
        println!("{line}");
    }
    let mut exit_code = verdict.exit_code(spec.expect);
    if let Some(note) = state.continued_note(&checkpoints) {
        println!("{note}");
    }
    let judged = kept.judge(&requirements);
    for j in &judged {
        println!("{}", j.describe());
        if !j.holds() {
            exit_code = exit_code.max(lander::verdict::EXIT_FAILED_VERDICT);
        }
    }
    match state.saved_note(simulation.saved_at(), &end, &kept) {
        Some(Ok(note)) => println!("{note}"),
        Some(Err(problem)) => {
            eprintln!("harness: {problem}");
            exit_code = exit_code.max(lander::verdict::EXIT_ERROR);
        }
        None => {}
    }
    let system_err = simulation.take_stderr();
    let mut suite = cosim::requirements::junit::suite(
        &suite_name(scenario),
        started.elapsed().as_secs_f64(),
        (verdict.exit_code(spec.expect) == lander::verdict::EXIT_OK).then(String::new),
        &verdict.describe(spec.expect),
        &judged,
    );
    suite.system_err = Some(system_err).filter(|e| !e.is_empty());
    suite.results = out
        .file_name()
        .map(|name| name.to_string_lossy().into_owned());
    suite.fmus = fmu_facts(&simulation);
    Ok(Flown { exit_code, suite })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn negative_option_values_need_no_equals_sign() {
        let cli = Cli::try_parse_from([
            "harness",
            "replay",
            "--seed",
            "1",
            "--run",
            "2",
            "--phi-cmd-deg",
            "-30",
        ])
        .unwrap_or_else(|e| panic!("{e}"));
        let Command::Replay(args) = cli.command else {
            panic!("not replay")
        };
        assert_eq!(args.phi_cmd_deg, -30.0);
        let cli =
            Cli::try_parse_from(["harness", "monte-carlo", "--phi-cmd-deg", "-30", "-n", "1"])
                .unwrap_or_else(|e| panic!("{e}"));
        let Command::MonteCarlo(args) = cli.command else {
            panic!("not monte-carlo")
        };
        assert_eq!(args.campaign.phi_cmd_deg, [-30.0]);
    }
}

/// What the Dask tasks are given of a command line: tested here, where the command line is
/// defined.
#[cfg(test)]
mod dask_arguments {
    use std::ffi::OsString;

    fn forwarded_args(
        argv: &[OsString],
        subcommand: &str,
        scenario_id: &str,
        scenario: &str,
    ) -> anyhow::Result<Vec<String>> {
        let definition = <crate::Cli as clap::CommandFactory>::command();
        crate::dask::forwarded_args(&definition, argv, subcommand, scenario_id, scenario)
    }

    fn argv(args: &[&str]) -> Vec<OsString> {
        args.iter().map(OsString::from).collect()
    }

    #[test]
    fn the_tasks_get_the_options_given_less_those_kept_here() {
        let args = forwarded_args(
            &argv(&[
                "harness",
                "--call-timeout",
                "30",
                "monte-carlo",
                "-n",
                "8",
                "--phi-cmd-deg",
                "-30,150",
                "--law",
                "decoupled",
                "--set",
                "plant.m0=850",
                "--dask",
                "tcp://h:8786",
                "--out-dir",
                "x",
                "-q",
                "--resume",
                "--no-plots",
                "--fmu-dir",
                "f",
            ]),
            "monte-carlo",
            "scenario",
            "paper",
        )
        .unwrap();
        let mut sorted = args.clone();
        sorted.sort();
        assert_eq!(
            sorted,
            [
                "--call-timeout=30",
                "--law=decoupled",
                "--phi-cmd-deg=-30",
                "--phi-cmd-deg=150",
                "--runs=8",
                "--set=plant.m0=850",
            ]
        );
    }

    #[test]
    fn a_scenario_file_is_renamed_and_a_built_in_one_kept() {
        let args = |scenario: &str| {
            forwarded_args(
                &argv(&[
                    "harness",
                    "monte-carlo",
                    "--scenario",
                    scenario,
                    "--dask",
                    "a",
                ]),
                "monte-carlo",
                "scenario",
                scenario,
            )
            .unwrap()
        };
        assert_eq!(args("flight"), ["--scenario=flight"]);
        assert_eq!(args("../my/short.toml"), ["--scenario=scenario/short.toml"]);
    }

    #[test]
    fn a_scenario_campaign_gets_its_scenario_as_a_positional_after_the_options() {
        let args = forwarded_args(
            &argv(&[
                "harness",
                "campaign",
                "../my/osc.toml",
                "-n",
                "6",
                "--seed",
                "3",
                "--dask",
                "local:2",
                "--out-dir",
                "x",
            ]),
            "campaign",
            "scenario",
            "../my/osc.toml",
        )
        .unwrap();
        assert_eq!(args, ["--seed=3", "--runs=6", "scenario/osc.toml"]);
    }

    #[test]
    fn options_a_dask_campaign_cannot_honour_are_refused_by_name() {
        let error = forwarded_args(
            &argv(&[
                "harness",
                "monte-carlo",
                "--dask",
                "a",
                "--shard",
                "1/2",
                "--workers",
                "2",
            ]),
            "monte-carlo",
            "scenario",
            "paper",
        )
        .unwrap_err()
        .to_string();
        assert!(
            error.contains("--shard:") && error.contains("--workers:"),
            "{error}"
        );
        assert!(!error.contains("--rerun"), "{error}");
    }
}
