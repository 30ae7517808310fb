//! The FMI-LS-REF references every packaged FMU carries
//! (`extra/org.fmi-standard.fmi-ls-ref/`: manifest, experiments file, `<Model>_out.csv`,
//! `<Model>_in.csv`), written from runs of the FMUs just packaged, so that a reference
//! cannot drift from the code: cosim's `fmu_reference` binary (built in the dev profile with
//! the description binaries) flies the scenarios below and runs each FMU alone over its
//! DefaultExperiment, in a few seconds; the files then go into both FMI versions' archives.
use crate::fmu_zip::{self, Entry};
use crate::workspace::{self, Workspace};
use anyhow::{Context, Result};
use std::path::{Path, PathBuf};

/// The folder the layered standard gives its files inside an FMU.
const DIR: &str = "extra/org.fmi-standard.fmi-ls-ref";

/// The flights whose signals an FMU's inputs are taken from, the first that connects it:
/// the paper's for LanderGnc and LanderPlant (the GNC's inputs are the plant signals of the
/// paper flight), then the scenarios that add LanderNav, and LanderSensors and
/// LanderFilter. An FMU none connects gets a unit step on its continuous inputs.
const SCENARIOS: [&str; 3] = [
    "harness/scenarios/paper.toml",
    "harness/scenarios/paper-nav.toml",
    "harness/scenarios/full-fidelity.toml",
];

/// The generator's name, as cargo names the binary of `cosim/src/bin/fmu_reference.rs`.
pub const GENERATOR: &str = "fmu_reference";

pub fn generator_path(ws: &Workspace) -> PathBuf {
    ws.target_dir.join("debug").join(GENERATOR)
}

/// Writes the references of the FMUs `fmus` (each `(model identifier, its FMU files)`, the
/// first of which is run) into each of their files.
pub fn add(ws: &Workspace, fmus: &[(String, Vec<PathBuf>)]) -> Result<()> {
    let started = std::time::Instant::now();
    let scratch = ws.target_dir.join("fmu-references");
    if scratch.exists() {
        std::fs::remove_dir_all(&scratch)
            .with_context(|| format!("cannot clear {}", scratch.display()))?;
    }
    let mut generate = std::process::Command::new(generator_path(ws));
    generate
        .current_dir(&ws.root)
        .arg("--out-dir")
        .arg(&scratch);
    for scenario in SCENARIOS {
        generate.arg("--scenario").arg(ws.root.join(scenario));
    }
    generate.args(fmus.iter().filter_map(|(_, files)| files.first()));
    workspace::run(&mut generate)?;
    let mut bytes = 0;
    for (identifier, files) in fmus {
        let entries = entries(&scratch.join(identifier))?;
        bytes += entries.iter().map(|e| e.bytes.len()).sum::<usize>();
        for file in files {
            fmu_zip::add(file, entries_copy(&entries))?;
        }
    }
    println!(
        "xtask fmus: FMI-LS-REF references of {} FMUs ({bytes} bytes each in both FMI \
         versions) in {:.1} s",
        fmus.len(),
        started.elapsed().as_secs_f64()
    );
    Ok(())
}

/// The files the generator wrote for one FMU, as archive entries under [`DIR`].
fn entries(dir: &Path) -> Result<Vec<Entry>> {
    let mut entries = Vec::new();
    for file in std::fs::read_dir(dir).with_context(|| format!("cannot read {}", dir.display()))? {
        let path = file?.path();
        let name = path
            .file_name()
            .context("a file has a name")?
            .to_string_lossy()
            .into_owned();
        let bytes =
            std::fs::read(&path).with_context(|| format!("cannot read {}", path.display()))?;
        entries.push(Entry::file(format!("{DIR}/{name}"), bytes));
    }
    anyhow::ensure!(
        entries
            .iter()
            .any(|e| e.path.ends_with("fmi-ls-manifest.xml")),
        "{}: the generator wrote no manifest",
        dir.display()
    );
    Ok(entries)
}

fn entries_copy(entries: &[Entry]) -> Vec<Entry> {
    entries
        .iter()
        .map(|e| Entry::file(e.path.clone(), e.bytes.clone()))
        .collect()
}
