//! `harness campaign SCENARIO`: the campaign a scenario's `[campaign]` table declares (any
//! FMUs), its shards merged by `merge-mc` or flown on a Dask cluster (`--dask`), one run
//! replayed with `--replay`.
use campaign::generic::campaign::Overrides;
use campaign::generic::{config, merge, runner, summary};
use campaign::Shard;
use std::path::{Path, PathBuf};

mod dask;

#[derive(Debug, Clone, clap::Args)]
pub struct CampaignArgs {
    /// A TOML scenario with a [campaign] table, or an SSP scenario or FMU whose sidecar
    /// NAME.campaign.toml holds it (docs/campaigns.md).
    pub scenario: String,
    /// Campaign seed, instead of the table's `seed`.
    #[arg(long)]
    pub seed: Option<u64>,
    /// Runs (draws) per sweep point, instead of the table's `runs`.
    #[arg(long, short = 'n')]
    pub runs: Option<u64>,
    /// Where manifest.csv, campaign.toml, summary.csv and sensitivity.csv go.
    #[arg(long, default_value = "target/campaign")]
    pub out_dir: PathBuf,
    /// Worker threads, each with its own loaded FMUs (default: the available cores).
    #[arg(long)]
    pub workers: Option<usize>,
    /// Run only the runs whose index is k-1 modulo N (k = 1..N); join the shards' directories
    /// with `merge-mc`.
    #[arg(long, value_name = "k/N")]
    pub shard: Option<Shard>,
    /// Continue the campaign already in --out-dir (same definition and shard): keep its
    /// finished runs, run the others. Without a campaign there, start one.
    #[arg(long)]
    pub resume: bool,
    /// No progress bar and no summary printed.
    #[arg(long, short)]
    pub quiet: bool,
    /// Accepted for `monte-carlo`'s callers (a scenario campaign draws no figure).
    #[arg(long)]
    pub no_plots: bool,
    /// Run this index again (the manifest's `index` column), write its trajectory (every
    /// output) to --out, and compare its row with --out-dir's manifest bit for bit when it
    /// holds that run.
    #[arg(
        long,
        value_name = "INDEX",
        conflicts_with_all = ["shard", "resume", "workers", "dask"]
    )]
    pub replay: Option<u64>,
    /// With --replay: the trajectory's file (CSV, or Arrow IPC for .arrow, .feather, .ipc)
    /// [default: OUT_DIR/replay-INDEX.csv].
    #[arg(long, requires = "replay")]
    pub out: Option<PathBuf>,
    #[command(flatten)]
    pub dask: crate::dask::DaskArgs,
}

/// Prints and writes the summary of the campaign in `dir`; the exit code: an error when a
/// run failed, a failed verdict when one did not pass.
fn summarise(dir: &Path, quiet: bool) -> anyhow::Result<i32> {
    let (plan, summary) = summary::of_directory(dir)?;
    if !quiet {
        print!("{}", summary.text(&plan));
    }
    for path in summary.write(&plan, dir)? {
        println!("wrote {}", path.display());
    }
    let whole = &summary.whole;
    Ok(if whole.errors > 0 {
        lander::verdict::EXIT_ERROR
    } else if whole.passed < whole.runs {
        lander::verdict::EXIT_FAILED_VERDICT
    } else {
        lander::verdict::EXIT_OK
    })
}

pub fn campaign(args: &CampaignArgs, fmu_dir: &Path) -> anyhow::Result<i32> {
    let overrides = Overrides {
        seed: args.seed,
        runs: args.runs,
    };
    if let Some(index) = args.replay {
        return replay(args, overrides, index, fmu_dir);
    }
    if args.dask.dask.is_some() {
        return dask::campaign(args, overrides, fmu_dir);
    }
    let options = runner::RunOptions {
        fmu_dir: fmu_dir.to_owned(),
        out_dir: args.out_dir.clone(),
        workers: args
            .workers
            .unwrap_or_else(campaign::runner::default_workers),
        shard: args.shard.unwrap_or(Shard::WHOLE),
        resume: args.resume,
        progress: !args.quiet,
    };
    let (_, outcome) = runner::run(&args.scenario, overrides, &options)?;
    println!(
        "ran {} runs{} -> {}",
        outcome.ran,
        match outcome.kept {
            0 => String::new(),
            kept => format!(" ({kept} kept from before)"),
        },
        outcome.manifest.display()
    );
    summarise(&args.out_dir, args.quiet)
}

fn replay(
    args: &CampaignArgs,
    overrides: Overrides,
    index: u64,
    fmu_dir: &Path,
) -> anyhow::Result<i32> {
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| args.out_dir.join(format!("replay-{index}.csv")));
    let format = cosim::results::Format::for_output(&out, None).map_err(anyhow::Error::msg)?;
    let (campaign, row, trajectory) = runner::replay(&args.scenario, overrides, index, fmu_dir)?;
    if let Some(parent) = out.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(parent)?;
    }
    cosim::results::write(&out, &trajectory, format)?;
    let manifest = args.out_dir.join(campaign::manifest::FILE_NAME);
    let recorded = if manifest.is_file() {
        let (rows, _) = campaign.layout.read_complete(&manifest)?;
        rows.into_iter().find(|r| r.id.index == index)
    } else {
        None
    };
    println!(
        "run {index} (run {}, point {}, seed {}): {}; {}",
        row.id.run,
        row.id.point,
        row.id.run_seed,
        campaign.layout.describe_inputs(&row),
        row.verdict
    );
    match recorded {
        Some(recorded) if recorded.bit_equal(&row) => {
            println!(
                "identical to {} row {index}, bit for bit",
                manifest.display()
            )
        }
        Some(recorded) => anyhow::bail!(
            "run {index} does not reproduce {}: recorded {recorded:?}, replayed {row:?}",
            manifest.display()
        ),
        None => println!(
            "({} holds no run {index} to compare with)",
            manifest.display()
        ),
    }
    println!("wrote {}", out.display());
    Ok(if row.passed() {
        lander::verdict::EXIT_OK
    } else {
        lander::verdict::EXIT_FAILED_VERDICT
    })
}

/// `merge-mc` of scenario campaign shards.
pub fn merge(inputs: &[PathBuf], out_dir: &Path, allow_missing: bool) -> anyhow::Result<i32> {
    let merged = merge::merge(inputs, allow_missing)?;
    let path = merge::write(&merged, out_dir)?;
    println!(
        "{} runs from {} inputs -> {}",
        merged.rows.len(),
        inputs.len(),
        path.display()
    );
    if !merged.missing.is_empty() {
        println!("missing: {} runs", merged.missing.len());
    }
    summarise(out_dir, false)
}

/// Whether the first of `inputs` (a directory or its manifest) is a scenario campaign.
pub fn is_scenario_campaign(inputs: &[PathBuf]) -> bool {
    inputs.first().is_some_and(|input| {
        let dir = if input.is_dir() {
            input.as_path()
        } else {
            input.parent().unwrap_or(Path::new("."))
        };
        config::is_scenario_campaign(dir)
    })
}
