//! `--dask ADDRESS`: a campaign's shards flown as tasks of a Dask cluster whose workers share
//! no file system with this machine (docs/dask.md). The harness runs the plain-Python driver
//! `harness_dask.py` (a release's `python/`, a checkout's `harness/python/`) with `python3`
//! or `$HARNESS_PYTHON`; each task carries the harness for its worker's platform, the FMUs
//! and the scenario file, flies `SUBCOMMAND ARGS --shard k/S` in a temporary directory of its
//! worker and returns the shard's files, which the driver writes into a store beside the
//! output directory. [`campaign`] merges the stored shards as `merge-mc` does, through the
//! subcommand's [`Format`].
//!
//! Generic over the subcommand: the arguments the tasks get are those given on this command
//! line (re-read from it), less the options this side sets or honours itself.
use anyhow::{bail, Context};
use clap::parser::ValueSource;
use std::collections::BTreeMap;
use std::ffi::OsString;
use std::path::{Component, Path, PathBuf};
use std::process::{Command, Stdio};

mod merge;
pub use merge::{campaign, Format};

/// The options a subcommand that can fly on Dask adds (`#[command(flatten)]`).
#[derive(Debug, Clone, clap::Args)]
pub struct DaskArgs {
    /// Fly the campaign's shards as tasks of the Dask scheduler at tcp://HOST:PORT, or of
    /// a cluster of N local worker processes for local:N; the shards are merged into
    /// --out-dir. Each task carries the harness, the FMUs and the scenario file: the
    /// workers need Python with dask and distributed, no shared file system
    /// (docs/dask.md).
    #[arg(long, value_name = "ADDRESS")]
    pub dask: Option<String>,
    /// Shards (Dask tasks) of a --dask campaign (default: 4 per worker, at most one per
    /// flight; with --resume, the count of the shards already flown).
    #[arg(long, value_name = "S", requires = "dask", value_parser = clap::value_parser!(u64).range(1..))]
    pub dask_shards: Option<u64>,
}

/// Options the tasks do not get: this side honours them (`--out-dir`, `--resume`, `--quiet`,
/// `--no-plots`) or the task sets them (`--fmu-dir`).
const KEPT_HERE: [&str; 7] = [
    "dask",
    "dask_shards",
    "out_dir",
    "resume",
    "quiet",
    "no_plots",
    "fmu_dir",
];

/// Options a Dask campaign cannot honour, with why.
const REFUSED: [(&str, &str); 3] = [
    (
        "shard",
        "--shard: a --dask campaign cuts itself into --dask-shards shards",
    ),
    (
        "rerun",
        "--rerun: a --dask campaign resumes whole shards (--resume)",
    ),
    (
        "workers",
        "--workers: each Dask task flies with one thread; a worker's threads are \
         `dask worker --nthreads`",
    ),
];

/// What one campaign subcommand asks of the cluster.
pub struct Job<'a> {
    /// The subcommand the tasks run, e.g. `monte-carlo`.
    pub subcommand: &'a str,
    /// The clap id of its scenario argument (an option or a positional).
    pub scenario_id: &'a str,
    /// The scenario as given: a built-in name or a file.
    pub scenario: &'a str,
    /// The file beside the scenario that declares its campaign when the scenario cannot (an
    /// SSP's or FMU's `NAME.campaign.toml`); it travels beside the scenario.
    pub declaration: Option<&'a Path>,
    pub fmu_dir: &'a Path,
    pub out_dir: &'a Path,
    pub flights: u64,
    /// What the progress lines call the campaign's rows: `flights`, `runs`.
    pub unit: &'a str,
    pub resume: bool,
    pub quiet: bool,
}

/// The shards flown, in order, stored beside the output directory until merged.
pub struct Shards {
    pub dirs: Vec<PathBuf>,
    /// Per shard, where it was flown: `shard k/S: dask worker tcp://...`.
    pub provenance: Vec<String>,
    store: PathBuf,
}

impl Shards {
    /// Removes the store once its shards are merged.
    pub fn remove(self) -> anyhow::Result<()> {
        std::fs::remove_dir_all(&self.store)
            .with_context(|| format!("removing {}", self.store.display()))
    }
}

/// Where a Dask campaign keeps its finished shards until they are merged: `<out>.dask-shards`.
pub fn store_of(out_dir: &Path) -> PathBuf {
    let mut name = out_dir.as_os_str().to_owned();
    name.push(".dask-shards");
    PathBuf::from(name)
}

/// How a scenario file is named on a worker: inside the task's directory, the same for every
/// task, so that every shard records the same campaign. A built-in name stays as it is.
pub fn worker_scenario(scenario: &str) -> String {
    if is_built_in(scenario) {
        return scenario.to_owned();
    }
    let name = Path::new(scenario)
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    format!("scenario/{name}")
}

fn is_built_in(scenario: &str) -> bool {
    lander::scenarios::BUILT_IN
        .iter()
        .any(|(name, _)| *name == scenario)
}

/// The harness's command line as clap defines it, given by the binary at its start: the
/// tasks get the options given, which only the definition can tell from their values.
static COMMAND_LINE: std::sync::OnceLock<clap::Command> = std::sync::OnceLock::new();

/// Gives this module the command line's definition (once, at the start of `main`).
pub fn know_command_line(definition: clap::Command) {
    let _ = COMMAND_LINE.set(definition);
}

/// Flies the shards not yet stored and returns every stored shard. `check_stored` is given a
/// stored shard's directory on `--resume`: it refuses shards of another campaign.
pub fn fly(
    dask: &DaskArgs,
    job: &Job,
    check_stored: &dyn Fn(&Path) -> anyhow::Result<()>,
) -> anyhow::Result<Shards> {
    let Some(address) = &dask.dask else {
        bail!("no --dask address");
    };
    let argv: Vec<OsString> = std::env::args_os().collect();
    let Some(definition) = COMMAND_LINE.get() else {
        bail!("--dask: the command line's definition was not given (know_command_line)");
    };
    let args = forwarded_args(
        definition,
        &argv,
        job.subcommand,
        job.scenario_id,
        job.scenario,
    )?;
    let files = shipped_files(job.scenario, job.declaration, job.fmu_dir)?;
    let harnesses = harnesses()?;
    let driver = driver()?;

    let store = std::path::absolute(store_of(job.out_dir))?;
    if !job.resume {
        clear_store(job.out_dir)?;
    }
    let (shards, done) = stored_shards(&store, dask.dask_shards, check_stored)?;
    if let Some(shards) = shards {
        anyhow::ensure!(
            shards <= job.flights.max(1),
            "--dask-shards {shards}: the campaign has {} flights",
            job.flights
        );
    }
    std::fs::create_dir_all(&store).with_context(|| format!("creating {}", store.display()))?;
    let job_file = serde_json::json!({
        "scheduler": address,
        "subcommand": job.subcommand,
        "args": args,
        "files": files,
        "harnesses": harnesses,
        "store": store,
        "flights": job.flights,
        "unit": job.unit,
        "shards": shards,
        "done": done,
        "quiet": job.quiet,
    });
    let job_path = tempfile::Builder::new()
        .prefix("harness-dask-job-")
        .suffix(".json")
        .tempfile()?;
    std::fs::write(job_path.path(), serde_json::to_vec_pretty(&job_file)?)?;
    run_driver(&driver, job_path.path())?;

    let (Some(shards), _) = stored_shards(&store, shards, &|_| Ok(()))? else {
        bail!("the Dask run stored no shard in {}", store.display());
    };
    let mut dirs = Vec::new();
    let mut provenance = Vec::new();
    for k in 1..=shards {
        let dir = store.join(shard_name(k, shards));
        anyhow::ensure!(
            dir.is_dir(),
            "shard {k}/{shards} is missing from {}",
            store.display()
        );
        // A shard stored by other means (copied in for --resume) names no worker.
        let worker = std::fs::read_to_string(dir.join("dask.txt")).unwrap_or_default();
        provenance.push(match worker.trim() {
            "" => format!("shard {k}/{shards}"),
            worker => format!("shard {k}/{shards}: dask worker {worker}"),
        });
        dirs.push(dir);
    }
    Ok(Shards {
        dirs,
        provenance,
        store,
    })
}

fn shard_name(k: u64, shards: u64) -> String {
    format!("shard-{k}-of-{shards}")
}

/// The shard count and the shards already in the store (checked by `check_stored`): their
/// count is the campaign's, `asked` must agree with it.
fn stored_shards(
    store: &Path,
    asked: Option<u64>,
    check_stored: &dyn Fn(&Path) -> anyhow::Result<()>,
) -> anyhow::Result<(Option<u64>, Vec<u64>)> {
    let mut found: Vec<(u64, u64)> = Vec::new();
    if let Ok(entries) = std::fs::read_dir(store) {
        for entry in entries {
            let name = entry?.file_name().to_string_lossy().into_owned();
            let parsed = name
                .strip_prefix("shard-")
                .and_then(|rest| rest.split_once("-of-"))
                .and_then(|(k, n)| Some((k.parse().ok()?, n.parse().ok()?)));
            if let Some(kn) = parsed {
                found.push(kn);
            }
        }
    }
    found.sort();
    let counts: std::collections::BTreeSet<u64> = found.iter().map(|(_, n)| *n).collect();
    anyhow::ensure!(
        counts.len() <= 1,
        "{} holds shards of different counts ({counts:?}): remove it",
        store.display()
    );
    let stored = counts.into_iter().next();
    Ok(match (stored, asked) {
        (Some(n), Some(s)) if n != s => bail!(
            "--dask-shards {s}: the shards in {} are of {n} (resume with --dask-shards {n}, or \
             without --resume start again)",
            store.display()
        ),
        (Some(n), _) => {
            if let Some((k, _)) = found.first() {
                check_stored(&store.join(shard_name(*k, n)))?;
            }
            (Some(n), found.into_iter().map(|(k, _)| k).collect())
        }
        (None, asked) => (asked, Vec::new()),
    })
}

/// Clears the store of an earlier Dask run: a campaign without `--resume` starts again.
fn clear_store(out_dir: &Path) -> anyhow::Result<()> {
    let store = store_of(out_dir);
    if store.exists() {
        std::fs::remove_dir_all(&store).with_context(|| format!("removing {}", store.display()))?;
    }
    Ok(())
}

/// The arguments the tasks get: every option of `subcommand` given on `argv` (the global
/// ones too), as `--name=value`, less those kept here; the scenario renamed as a worker sees
/// it. An option the tasks cannot honour is refused.
pub(crate) fn forwarded_args(
    definition: &clap::Command,
    argv: &[OsString],
    subcommand: &str,
    scenario_id: &str,
    scenario: &str,
) -> anyhow::Result<Vec<String>> {
    let mut command = definition.clone();
    command.build();
    let matches = command.clone().try_get_matches_from(argv)?;
    let (Some(sub), Some(sub_matches)) = (
        command.find_subcommand(subcommand),
        matches.subcommand_matches(subcommand),
    ) else {
        bail!("--dask: not a `{subcommand}` command line");
    };
    let has = |id: &str| sub.get_arguments().any(|arg| arg.get_id() == id);
    let refused: Vec<&str> = REFUSED
        .iter()
        .filter(|(id, _)| has(id) && sub_matches.value_source(id) == Some(ValueSource::CommandLine))
        .map(|(_, why)| *why)
        .collect();
    if !refused.is_empty() {
        bail!("--dask cannot honour {}", refused.join("; "));
    }
    let mut options = Vec::new();
    let mut positionals = Vec::new();
    for arg in sub.get_arguments() {
        let id = arg.get_id().as_str();
        if KEPT_HERE.contains(&id) || sub_matches.value_source(id) != Some(ValueSource::CommandLine)
        {
            continue;
        }
        let values: Vec<String> = if id == scenario_id {
            vec![worker_scenario(scenario)]
        } else if arg.get_action().takes_values() {
            sub_matches
                .get_raw(id)
                .into_iter()
                .flatten()
                .map(|v| {
                    v.to_str()
                        .map(str::to_owned)
                        .ok_or_else(|| anyhow::anyhow!("--dask: {v:?} is not UTF-8"))
                })
                .collect::<anyhow::Result<_>>()?
        } else {
            Vec::new()
        };
        match arg.get_long() {
            None => positionals.extend(values),
            Some(long) if values.is_empty() => {
                let times = match arg.get_action() {
                    clap::ArgAction::Count => sub_matches.get_count(id) as usize,
                    _ => 1,
                };
                options.extend(std::iter::repeat_n(format!("--{long}"), times));
            }
            Some(long) => options.extend(values.iter().map(|v| format!("--{long}={v}"))),
        }
    }
    options.extend(positionals);
    Ok(options)
}

/// The files a task writes into its directory, by the path relative to it, from where they
/// are here: the scenario file (`scenario/NAME`) and the file declaring its campaign, the
/// FMUs found beside it (under `scenario/`) and those of the FMU directory (under `fmu/`, the
/// task's `--fmu-dir`). An `.ssp` package carries its FMUs.
fn shipped_files(
    scenario: &str,
    declaration: Option<&Path>,
    fmu_dir: &Path,
) -> anyhow::Result<BTreeMap<String, PathBuf>> {
    let mut files = BTreeMap::new();
    let system = lander::scenarios::load(scenario)?;
    let beside = if is_built_in(scenario) {
        None
    } else {
        let path = std::path::absolute(scenario)?;
        files.insert(worker_scenario(scenario), path.clone());
        path.parent().map(Path::to_owned)
    };
    if let Some(declaration) = declaration {
        let path = std::path::absolute(declaration)?;
        anyhow::ensure!(
            beside.is_some() && path.parent() == beside.as_deref() && path.is_file(),
            "--dask: the campaign's declaration {} is not a file beside the scenario {scenario}",
            declaration.display()
        );
        files.insert(worker_scenario(&path.to_string_lossy()), path);
    }
    if system.package.is_some() {
        return Ok(files);
    }
    for instance in &system.instances {
        let (relative, from) = if instance.fmu.is_absolute() {
            let inside = beside
                .as_deref()
                .and_then(|dir| instance.fmu.strip_prefix(dir).ok());
            let Some(relative) = inside else {
                bail!(
                    "--dask: instance '{}' names its FMU by the path {}, which a Dask worker \
                     does not have: name it relative to the scenario file or to the FMU \
                     directory",
                    instance.name,
                    instance.fmu.display()
                );
            };
            (
                Path::new("scenario").join(relative),
                instance.fmu.to_owned(),
            )
        } else {
            (
                Path::new("fmu").join(&instance.fmu),
                cosim::master::fmu_path(fmu_dir, &instance.fmu),
            )
        };
        anyhow::ensure!(
            relative
                .components()
                .all(|c| matches!(c, Component::Normal(_))),
            "--dask: instance '{}': the FMU path {} leaves its folder",
            instance.name,
            relative.display()
        );
        anyhow::ensure!(
            from.is_file(),
            "--dask: instance '{}': no FMU at {}",
            instance.name,
            from.display()
        );
        let relative: Vec<String> = relative
            .components()
            .map(|c| c.as_os_str().to_string_lossy().into_owned())
            .collect();
        files.insert(relative.join("/"), std::path::absolute(from)?);
    }
    Ok(files)
}

/// This machine as the release's `bin/` folders name platforms (x86_64-linux,
/// aarch64-linux, x86_64-windows), as the driver names its workers'.
fn host_platform() -> String {
    format!("{}-{}", std::env::consts::ARCH, std::env::consts::OS)
}

/// The harness binaries the tasks can be given, by platform: every `bin/<platform>/` of the
/// release this harness came in, else this harness alone.
fn harnesses() -> anyhow::Result<BTreeMap<String, PathBuf>> {
    let exe = std::env::current_exe().context("finding the harness's own program")?;
    let mut found = BTreeMap::new();
    if let Some(release) = crate::fmu_dirs::release_of(&exe) {
        for entry in std::fs::read_dir(release.join("bin"))? {
            let dir = entry?.path();
            let platform = dir.file_name().map(|n| n.to_string_lossy().into_owned());
            let program = ["harness", "harness.exe"]
                .into_iter()
                .map(|name| dir.join(name))
                .find(|p| p.is_file());
            if let (Some(platform), Some(program)) = (platform, program) {
                found.insert(platform, program);
            }
        }
    }
    found.entry(host_platform()).or_insert(exe);
    Ok(found)
}

/// The driver script: a release's `python/harness_dask.py`, else the checkout's.
fn driver() -> anyhow::Result<PathBuf> {
    const NAME: &str = "harness_dask.py";
    let exe = std::env::current_exe().context("finding the harness's own program")?;
    let mut tried = Vec::new();
    if let Some(release) = crate::fmu_dirs::release_of(&exe) {
        tried.push(release.join("python").join(NAME));
    }
    tried.push(
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("python")
            .join(NAME),
    );
    match tried.iter().find(|p| p.is_file()) {
        Some(found) => Ok(found.clone()),
        None => bail!(
            "--dask: the driver {NAME} is not at {}",
            tried
                .iter()
                .map(|p| p.display().to_string())
                .collect::<Vec<_>>()
                .join(" nor at ")
        ),
    }
}

/// Runs the driver: its progress goes to stdout; its stderr is kept and, if it fails, its
/// message (the lines from its `harness-dask: ` one, else the end) becomes the error.
fn run_driver(driver: &Path, job: &Path) -> anyhow::Result<()> {
    let python = std::env::var_os("HARNESS_PYTHON")
        .unwrap_or_else(|| if cfg!(windows) { "python" } else { "python3" }.into());
    let mut command = Command::new(&python);
    command.arg(driver).arg(job).stderr(Stdio::piped());
    let output = command
        .spawn()
        .and_then(|child| child.wait_with_output())
        .with_context(|| {
            format!(
                "--dask: cannot run {} (a Python 3 with dask and distributed; name it in \
                 HARNESS_PYTHON)",
                python.to_string_lossy()
            )
        })?;
    if output.status.success() {
        return Ok(());
    }
    let stderr = String::from_utf8_lossy(&output.stderr);
    let message = match stderr.find("harness-dask: ") {
        Some(at) => stderr[at + "harness-dask: ".len()..].trim().to_owned(),
        None => {
            let lines: Vec<&str> = stderr.trim().lines().collect();
            lines[lines.len().saturating_sub(20)..].join("\n")
        }
    };
    bail!(
        "the Dask run stopped ({} {} ended with {}): {message}",
        python.to_string_lossy(),
        driver.display(),
        output.status
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The paper scenario in a folder of its own, with `LanderGnc.fmu` beside it and
    /// `LanderPlant.fmu` in an FMU directory (empty files: only their paths matter here).
    fn scenario_with_fmus(plant_fmu: &str) -> (tempfile::TempDir, PathBuf, PathBuf) {
        let dir = tempfile::tempdir().unwrap();
        let scenarios = dir.path().join("scenarios");
        let fmus = dir.path().join("fmus");
        std::fs::create_dir_all(&scenarios).unwrap();
        std::fs::create_dir_all(&fmus).unwrap();
        let paper = lander::scenarios::BUILT_IN[0]
            .1
            .replace("LanderPlant.fmu", plant_fmu);
        std::fs::write(scenarios.join("mine.toml"), paper).unwrap();
        std::fs::write(scenarios.join("LanderGnc.fmu"), b"").unwrap();
        std::fs::write(fmus.join("LanderPlant.fmu"), b"").unwrap();
        (dir, scenarios.join("mine.toml"), fmus)
    }

    #[test]
    fn the_scenario_file_and_its_fmus_travel_beside_it_or_from_the_fmu_directory() {
        let (_dir, scenario, fmus) = scenario_with_fmus("LanderPlant.fmu");
        let files = shipped_files(scenario.to_str().unwrap(), None, &fmus).unwrap();
        let names: Vec<&str> = files.keys().map(String::as_str).collect();
        assert_eq!(
            names,
            [
                "fmu/LanderPlant.fmu",
                "scenario/LanderGnc.fmu",
                "scenario/mine.toml"
            ]
        );
        assert_eq!(files["fmu/LanderPlant.fmu"], fmus.join("LanderPlant.fmu"));
    }

    #[test]
    fn an_ssd_travels_with_the_sidecar_declaring_its_campaign() {
        let dir = tempfile::tempdir().unwrap();
        let ssd = dir.path().join("osc.ssd");
        std::fs::write(
            &ssd,
            r#"<?xml version="1.0" encoding="UTF-8"?>
<ssd:SystemStructureDescription xmlns:ssd="http://ssp-standard.org/SSP1/SystemStructureDescription" version="1.0" name="osc">
  <ssd:System name="osc"><ssd:Elements>
    <ssd:Component name="osc" type="application/x-fmu-sharedlibrary" source="Oscillator.fmu"/>
  </ssd:Elements></ssd:System>
  <ssd:DefaultExperiment startTime="0" stopTime="1"/>
</ssd:SystemStructureDescription>
"#,
        )
        .unwrap();
        let sidecar = dir.path().join("osc.campaign.toml");
        std::fs::write(&sidecar, "[campaign]\n").unwrap();
        std::fs::write(dir.path().join("Oscillator.fmu"), b"").unwrap();
        let files = shipped_files(ssd.to_str().unwrap(), Some(&sidecar), dir.path()).unwrap();
        let names: Vec<&str> = files.keys().map(String::as_str).collect();
        assert_eq!(
            names,
            [
                "scenario/Oscillator.fmu",
                "scenario/osc.campaign.toml",
                "scenario/osc.ssd"
            ]
        );
        let elsewhere = tempfile::tempdir().unwrap();
        let apart = elsewhere.path().join("osc.campaign.toml");
        std::fs::write(&apart, "").unwrap();
        let error = shipped_files(ssd.to_str().unwrap(), Some(&apart), dir.path())
            .unwrap_err()
            .to_string();
        assert!(error.contains("not a file beside the scenario"), "{error}");
    }

    #[test]
    fn an_fmu_named_by_a_path_no_worker_has_is_refused_by_instance() {
        let (_dir, scenario, fmus) = scenario_with_fmus("/opt/elsewhere/LanderPlant.fmu");
        let error = shipped_files(scenario.to_str().unwrap(), None, &fmus)
            .unwrap_err()
            .to_string();
        assert!(
            error.contains("instance 'plant'") && error.contains("/opt/elsewhere"),
            "{error}"
        );
    }

    #[test]
    fn the_store_is_beside_the_output_directory() {
        assert_eq!(
            store_of(Path::new("runs/mc")),
            PathBuf::from("runs/mc.dask-shards")
        );
    }

    #[test]
    fn the_host_is_named_as_the_release_names_its_folders() {
        let name = host_platform();
        assert!(
            [
                "x86_64-linux",
                "aarch64-linux",
                "x86_64-windows",
                "aarch64-macos",
                "x86_64-macos"
            ]
            .contains(&name.as_str()),
            "{name}"
        );
    }
}
