//! What a Python user would otherwise run: fmpy's master loop, and a plant packaged with
//! pythonfmu. Both run with the workspace venv (`cargo xtask python-env`), whose fmpy and
//! pythonfmu versions are pinned in tests/python/requirements.txt.
use crate::record::{PaperRecord, COMMANDS, GNC, NAVIGATION, PLANT};
use anyhow::{bail, ensure, Context, Result};
use serde::Deserialize;
use std::collections::HashMap;
use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The venv's interpreter and the scripts this crate runs with it.
#[derive(Debug, Clone)]
pub struct PythonEnv {
    python: PathBuf,
    root: PathBuf,
}

impl PythonEnv {
    pub fn locate(workspace_root: &Path) -> Result<Self> {
        let python = workspace_root.join(".venv/bin/python");
        ensure!(
            python.is_file(),
            "{} is missing: run `cargo xtask python-env` (or pass --no-python)",
            python.display()
        );
        Ok(Self {
            python,
            root: workspace_root.to_owned(),
        })
    }

    /// The interoperability tests' scripts (fmpy_master.py, the Python plant, embedding_env.py).
    fn interop_dir(&self) -> PathBuf {
        self.root.join("tests/interop/python")
    }

    /// `python args...` with `envs`; its stdout, or an error carrying both streams.
    fn run<I, S>(&self, args: I, envs: &[(&str, &OsStr)]) -> Result<String>
    where
        I: IntoIterator<Item = S>,
        S: AsRef<OsStr>,
    {
        let mut command = Command::new(&self.python);
        command.args(args).envs(envs.iter().copied());
        let output = command
            .output()
            .with_context(|| format!("cannot start {}", self.python.display()))?;
        if !output.status.success() {
            bail!(
                "{:?} failed ({}):\n{}{}",
                command,
                output.status,
                String::from_utf8_lossy(&output.stdout),
                String::from_utf8_lossy(&output.stderr)
            );
        }
        String::from_utf8(output.stdout).context("Python printed non-UTF-8")
    }
}

/// fmpy's master loop on the paper scenario.
#[derive(Debug, Clone)]
pub struct FmpyTiming {
    pub steps: usize,
    /// Wall time of the stepping loop, one per flight.
    pub loop_seconds: Vec<f64>,
}

#[derive(Deserialize)]
struct FmpyReport {
    steps: usize,
    loop_seconds: Vec<f64>,
    final_bits: HashMap<String, u64>,
}

/// Flies the system of `record` `repeats` times in fmpy's master loop
/// (tests/speed/python/fmpy_timed.py) and checks that its last row equals the harness's
/// flight `record` bit for bit: the same system, flown the same way, so the two figures time
/// the same work.
pub fn fmpy_flights(
    env: &PythonEnv,
    fmu_dir: &Path,
    record: &PaperRecord,
    repeats: usize,
) -> Result<FmpyTiming> {
    let mut system = record.system.clone();
    for instance in &mut system.instances {
        // Absolute, so the JSON names the FMUs measured here whatever the default folder.
        instance.fmu = cosim::master::fmu_path(fmu_dir, &instance.fmu).canonicalize()?;
    }
    let scratch = tempfile::Builder::new().prefix("speed-fmpy-").tempdir()?;
    let spec = interop_tests::write_system_json(&system, scratch.path());
    let script = env.root.join("tests/speed/python/fmpy_timed.py");
    let stdout = env.run(
        [
            script.as_os_str(),
            spec.as_os_str(),
            OsStr::new(&repeats.to_string()),
        ],
        &[("PYTHONPATH", env.interop_dir().as_os_str())],
    )?;
    let report: FmpyReport =
        serde_json::from_str(stdout.trim()).context("fmpy_timed.py printed no report")?;
    ensure!(
        report.steps == record.steps(),
        "fmpy took {} steps, the harness {}",
        report.steps,
        record.steps()
    );
    let expected = NAVIGATION
        .iter()
        .map(|name| format!("{PLANT}.{name}"))
        .zip(record.navigation[record.steps()])
        .chain(
            COMMANDS
                .iter()
                .map(|name| format!("{GNC}.{name}"))
                .zip(record.commands[record.steps()]),
        );
    for (name, value) in expected {
        let bits = report
            .final_bits
            .get(&name)
            .with_context(|| format!("fmpy recorded no {name}"))?;
        ensure!(
            *bits == value.to_bits(),
            "fmpy ended with {name} = {}, the harness with {value}: not the same flight",
            f64::from_bits(*bits)
        );
    }
    Ok(FmpyTiming {
        steps: report.steps,
        loop_seconds: report.loop_seconds,
    })
}

/// Packages the interoperability tests' rigid-body plant (LanderPlantPy.py: the equations
/// of docs/interface.md in plain Python) with pythonfmu into `dir`; returns the FMU.
pub fn build_python_plant(env: &PythonEnv, dir: &Path) -> Result<PathBuf> {
    let source = env.interop_dir().join("plant/LanderPlantPy.py");
    env.run(
        [
            OsStr::new("-m"),
            OsStr::new("pythonfmu"),
            OsStr::new("build"),
            OsStr::new("-f"),
            source.as_os_str(),
            OsStr::new("-d"),
            dir.as_os_str(),
        ],
        &[],
    )?;
    let fmu = dir.join("LanderPlantPy.fmu");
    ensure!(fmu.is_file(), "pythonfmu wrote no {}", fmu.display());
    Ok(fmu)
}

/// What a native process needs to host pythonfmu's binary (LD_PRELOAD of libpython,
/// PYTHONHOME), as tests/interop/python/embedding_env.py prints it.
pub fn embedding_env(env: &PythonEnv) -> Result<Vec<(String, String)>> {
    let stdout = env.run([env.interop_dir().join("embedding_env.py")], &[])?;
    let pairs: Vec<(String, String)> = stdout
        .lines()
        .filter_map(|line| line.split_once('='))
        .map(|(k, v)| (k.to_owned(), v.to_owned()))
        .collect();
    ensure!(
        pairs.iter().any(|(k, _)| k == "LD_PRELOAD"),
        "embedding_env.py named no library to preload:\n{stdout}"
    );
    Ok(pairs)
}
