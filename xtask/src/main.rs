//! Build, package and test tasks for the workspace (`cargo xtask <command>`, aliased in
//! `.cargo/config.toml`). Everything a user or CI runs goes through here, so that the
//! README's two commands and `.ci/run` stay one line each.
#![deny(unsafe_code)]

mod bench;
mod campaign_dask;
mod cross;
mod demo;
mod dist;
mod dist_harness;
mod doc_page;
mod fmu_zip;
mod fmus;
mod fuzz_crates;
mod new_fmu;
mod platform;
mod python_env;
mod references;
mod ssp;
mod system_packages;
mod test;
mod workspace;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "xtask",
    about = "Workspace tasks: packaging, demo, the full test run"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Build the release cdylibs and write target/fmu/<modelIdentifier>.fmu for each FMU,
    /// and target/fmu/LanderDescent.ssp (the paper scenario with both lander FMUs).
    Fmus {
        /// Build for this Rust target triple instead of the host (repeat the option to put
        /// the binaries of several targets into each FMU); its standard library must be
        /// installed (`rustup target add TRIPLE`).
        #[arg(long = "target", value_name = "TRIPLE")]
        targets: Vec<String>,
        /// Also build aarch64-unknown-linux-gnu and x86_64-pc-windows-gnu with Debian's Rust
        /// toolchain (its Debian packages are installed first) and write FMUs carrying all
        /// three platforms to target/fmu/.
        #[arg(long, conflicts_with = "targets")]
        all_platforms: bool,
    },
    /// Merge FMUs of one model built on different platforms into one FMU with all their
    /// binaries (everything outside binaries/ must be identical).
    MergeFmus {
        /// The merged FMU to write.
        #[arg(long, value_name = "FMU")]
        out: std::path::PathBuf,
        /// The FMUs to merge.
        #[arg(required = true, value_name = "FMU")]
        inputs: Vec<std::path::PathBuf>,
    },
    /// Build the FMUs for every platform (as `fmus --all-platforms`) and write the release
    /// directory target/dist/lander-fmi-<version>/: FMUs, SSP, documentation, SHA256SUMS.
    Dist,
    /// Run every check in order (fmt, clippy, FMUs, Python venv, cargo tests), stopping at
    /// the first failure.
    Test,
    /// Package the FMUs and run the demonstration job.
    Demo,
    /// Create or update `.venv` with the pinned packages of tests/python/requirements.txt.
    PythonEnv,
    /// Package the FMUs and print the side-by-side speed table (tests/speed): our FMUs,
    /// the paper scenario, a 1,000-run Monte Carlo, fmpy's loop, a pythonfmu plant.
    /// Arguments after `--` go to the measurement, e.g. `-- --quick` or `-- --runs 100`.
    Bench {
        #[arg(trailing_var_arg = true, allow_hyphen_values = true)]
        args: Vec<String>,
    },
    /// A Monte Carlo campaign with its shards as Dask tasks (a LocalCluster of --workers
    /// processes, or --scheduler's cluster), merged into the files `harness monte-carlo`
    /// writes: `cargo xtask campaign-dask --workers 4 -- -n 100 --out-dir target/mc`.
    CampaignDask(campaign_dask::Args),
    /// Write fuzz/<name>/ (a cargo-fuzz crate with the FMI 2.0 and 3.0 targets) for every
    /// FMU crate, from its [package.metadata.fmu].
    FuzzCrates {
        /// Write nothing; fail when a fuzz crate is missing or differs.
        #[arg(long)]
        check: bool,
    },
    /// Write a new FMU crate fmu-<name>/ (a tiny model, its metadata, the conformance
    /// suite) that `cargo xtask fmus` packages as it is.
    NewFmu {
        /// The model identifier, UpperCamelCase (e.g. LanderRadar: crate fmu-lander-radar).
        name: String,
        /// Write the crate folder into DIR instead of the workspace root (to look at it).
        #[arg(long, value_name = "DIR")]
        into: Option<std::path::PathBuf>,
    },
}

fn main() -> ExitCode {
    let command = Cli::parse().command;
    let result = workspace::Workspace::locate().and_then(|ws| match command {
        Command::Fmus {
            all_platforms: true,
            ..
        } => fmus::package_all_platforms(&ws, fmus::Describers::Build(&[])).map(|_| ()),
        Command::Fmus { targets, .. } => fmus::package_for(&ws, &targets).map(|_| ()),
        Command::MergeFmus { out, inputs } => platform::merge_files(&out, &inputs),
        Command::Dist => dist::run(&ws).map(|_| ()),
        Command::Test => test::run_all(&ws),
        Command::Demo => demo::run(&ws),
        Command::PythonEnv => python_env::ensure(&ws),
        Command::Bench { args } => bench::run(&ws, &args),
        Command::CampaignDask(args) => campaign_dask::run(&ws, &args),
        Command::FuzzCrates { check } => fuzz_crates::run(&ws, check),
        Command::NewFmu { name, into } => new_fmu::run(&ws, &name, into.as_deref()).map(|_| ()),
    });
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            // The chain of causes is the whole story; a backtrace of xtask itself is noise.
            eprintln!("xtask: {error:#}");
            ExitCode::FAILURE
        }
    }
}
