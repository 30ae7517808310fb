//! `cargo xtask campaign-dask --workers N [--scheduler tcp://HOST:PORT] -- <monte-carlo args>`:
//! a Monte Carlo campaign with its shards run as Dask tasks, then merged.
//!
//! The campaign is cut into `--shards` shards (default: one per worker); each is the command
//! `harness monte-carlo <args> --shard k/S --out-dir <out>.dask-shards/k --quiet --no-plots`
//! (with `--workers 1` unless the arguments set it),
//! run by a Dask worker (`campaign_dask.py`): a LocalCluster of N single-threaded worker
//! processes on loopback, or the cluster of `--scheduler`. `harness merge-mc` then joins the
//! shards into `<out>` and removes them. A flight's result depends only on the campaign seed
//! and its index, and the manifest is written sorted by index, so `<out>` holds the files
//! `harness monte-carlo <args>` writes, `manifest.csv` byte for byte.
use crate::workspace::{self, Workspace};
use crate::{fmus, python_env};
use anyhow::{bail, ensure, Context, Result};
use std::path::{Path, PathBuf};
use std::process::Command;

const SCRIPT: &str = include_str!("campaign_dask.py");

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Dask workers: LocalCluster worker processes (one thread each) without --scheduler.
    #[arg(long)]
    pub workers: usize,
    /// An existing Dask scheduler (tcp://HOST:PORT); its workers must see the harness, the
    /// FMUs and the output directory at the same paths.
    #[arg(long)]
    pub scheduler: Option<String>,
    /// Shards (Dask tasks); default: --workers.
    #[arg(long)]
    pub shards: Option<u64>,
    /// The harness binary to run (default: build it, release profile).
    #[arg(long)]
    pub harness: Option<PathBuf>,
    /// `harness monte-carlo` arguments, after `--`.
    #[arg(last = true, allow_hyphen_values = true)]
    pub campaign: Vec<String>,
}

/// The value of option `name` in `args` (`--name v` or `--name=v`).
fn option<'a>(args: &'a [String], name: &str) -> Option<&'a str> {
    let with_equals = format!("{name}=");
    args.iter().enumerate().find_map(|(i, a)| {
        if a == name {
            args.get(i + 1).map(String::as_str)
        } else {
            a.strip_prefix(&with_equals)
        }
    })
}

/// The monte-carlo options the Dask run sets itself (or cannot honour) are refused.
fn check_campaign_args(args: &[String]) -> Result<()> {
    let refused: Vec<&str> = ["--shard", "--resume", "--rerun", "--quiet", "-q"]
        .into_iter()
        .filter(|name| {
            args.iter()
                .any(|a| a == name || a.starts_with(&format!("{name}=")))
        })
        .collect();
    ensure!(
        refused.is_empty(),
        "campaign-dask sets or cannot honour {}: leave them out of the monte-carlo arguments",
        refused.join(", ")
    );
    Ok(())
}

/// The shard commands, as `campaign_dask.py` reads them: one per line, arguments separated
/// by tabs.
fn shard_commands(
    harness: &Path,
    campaign: &[String],
    fmu_dir: &Path,
    shards_dir: &Path,
    shards: u64,
) -> Result<String> {
    let commands: Vec<Vec<String>> = (1..=shards)
        .map(|k| {
            let mut argv = vec![
                harness.display().to_string(),
                "--fmu-dir".into(),
                fmu_dir.display().to_string(),
                "monte-carlo".into(),
            ];
            argv.extend(campaign.iter().cloned());
            // One thread per task: Dask's workers are the parallelism.
            if option(campaign, "--workers").is_none() {
                argv.extend(["--workers".into(), "1".into()]);
            }
            argv.extend([
                "--shard".into(),
                format!("{k}/{shards}"),
                "--out-dir".into(),
                shards_dir.join(k.to_string()).display().to_string(),
                "--quiet".into(),
                "--no-plots".into(),
            ]);
            argv
        })
        .collect();
    let mut text = String::new();
    for argv in commands {
        if let Some(bad) = argv.iter().find(|a| a.contains(['\t', '\n'])) {
            bail!("argument {bad:?} holds a tab or a newline");
        }
        text += &argv.join("\t");
        text.push('\n');
    }
    Ok(text)
}

pub fn run(ws: &Workspace, args: &Args) -> Result<()> {
    ensure!(args.workers > 0, "--workers must be at least 1");
    check_campaign_args(&args.campaign)?;
    let shards = args.shards.unwrap_or(args.workers as u64);
    ensure!(shards > 0, "--shards must be at least 1");
    let cwd = std::env::current_dir()?;
    let out_dir = cwd.join(option(&args.campaign, "--out-dir").unwrap_or("target/monte-carlo"));
    let fmu_dir = match std::env::var_os("LANDER_FMU_DIR") {
        Some(dir) => cwd.join(dir),
        None => ws.fmu_dir(),
    };
    // --out-dir is replaced per shard; the rest goes to every shard unchanged.
    let mut campaign = Vec::new();
    let mut skip = false;
    for a in &args.campaign {
        if std::mem::take(&mut skip) {
            continue;
        }
        if a == "--out-dir" {
            skip = true;
        } else if !a.starts_with("--out-dir=") && a != "--no-plots" {
            campaign.push(a.clone());
        }
    }
    let harness = match &args.harness {
        Some(path) => cwd.join(path),
        None => {
            workspace::run(ws.cargo().args(["build", "--release", "-p", "harness"]))?;
            ws.target_dir.join("release").join("harness")
        }
    };
    if !fmu_dir.join("LanderGnc.fmu").is_file() {
        fmus::package_all(ws)?;
    }
    python_env::ensure(ws)?;
    let python = python_env::venv_dir(ws).join("bin").join("python");

    let shards_dir = PathBuf::from(format!("{}.dask-shards", out_dir.display()));
    if shards_dir.exists() {
        std::fs::remove_dir_all(&shards_dir)
            .with_context(|| format!("removing {}", shards_dir.display()))?;
    }
    std::fs::create_dir_all(&shards_dir)?;
    let commands = shards_dir.join("commands.tsv");
    let script = shards_dir.join("campaign_dask.py");
    std::fs::write(
        &commands,
        shard_commands(&harness, &campaign, &fmu_dir, &shards_dir, shards)?,
    )?;
    std::fs::write(&script, SCRIPT)?;
    let mut dask = Command::new(&python);
    dask.arg(&script)
        .arg("--workers")
        .arg(args.workers.to_string())
        .arg("--commands")
        .arg(&commands);
    if let Some(scheduler) = &args.scheduler {
        dask.arg("--scheduler").arg(scheduler);
    }
    workspace::run(&mut dask)?;

    let mut merge = Command::new(&harness);
    merge.arg("merge-mc");
    merge.args((1..=shards).map(|k| shards_dir.join(k.to_string())));
    merge.arg("--out-dir").arg(&out_dir);
    if args.campaign.iter().any(|a| a == "--no-plots") {
        merge.arg("--no-plots");
    }
    let status = merge
        .status()
        .with_context(|| format!("could not start {}", workspace::describe(&merge)))?;
    match status.code() {
        Some(0) | Some(3) => {}
        _ => bail!("{} failed ({status})", workspace::describe(&merge)),
    }
    std::fs::remove_dir_all(&shards_dir)
        .with_context(|| format!("removing {}", shards_dir.display()))?;
    if status.code() == Some(3) {
        // The campaign ran; some flights failed their verdict: the harness's exit code.
        std::process::exit(3);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn strings(args: &[&str]) -> Vec<String> {
        args.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn out_dir_is_found_in_both_spellings() {
        assert_eq!(
            option(&strings(&["-n", "3", "--out-dir", "x"]), "--out-dir"),
            Some("x")
        );
        assert_eq!(option(&strings(&["--out-dir=y"]), "--out-dir"), Some("y"));
        assert_eq!(option(&strings(&["-n", "3"]), "--out-dir"), None);
    }

    #[test]
    fn options_the_dask_run_sets_are_refused_by_name() {
        let e = check_campaign_args(&strings(&["--shard", "1/2", "--resume"])).unwrap_err();
        assert!(e.to_string().contains("--shard, --resume"), "{e}");
        assert!(check_campaign_args(&strings(&["-n", "4", "--seed", "3"])).is_ok());
    }

    #[test]
    fn each_shard_is_one_command_with_its_shard_and_directory() {
        let text = shard_commands(
            Path::new("/h"),
            &strings(&["-n", "2"]),
            Path::new("/fmu"),
            Path::new("/o.dask-shards"),
            3,
        )
        .unwrap();
        let list: Vec<&str> = text.lines().collect();
        assert_eq!(list.len(), 3);
        let second: Vec<&str> = list[1].split('\t').collect();
        assert_eq!(
            second,
            [
                "/h",
                "--fmu-dir",
                "/fmu",
                "monte-carlo",
                "-n",
                "2",
                "--workers",
                "1",
                "--shard",
                "2/3",
                "--out-dir",
                "/o.dask-shards/2",
                "--quiet",
                "--no-plots"
            ]
        );
    }

    #[test]
    fn an_argument_with_a_tab_is_refused() {
        let bad = strings(&["--scenario", "a\tb.toml"]);
        let e = shard_commands(Path::new("/h"), &bad, Path::new("/f"), Path::new("/o"), 1);
        assert!(e.is_err());
    }
}
