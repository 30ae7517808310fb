//! `fmu_reference --out-dir DIR [--scenario S.toml]... X.fmu...`: writes each FMU's
//! FMI-LS-REF files to `DIR/<model>/`, from runs of the FMUs themselves
//! (`cosim::reference::generate`). The inputs of an FMU are what it received in a flight of
//! the first scenario that connects it; packaging (`cargo xtask fmus`) runs this on the
//! FMUs it has just built and adds the files to them.
use anyhow::{bail, Context};
use cosim::master::Trajectory;
use cosim::reference::generate;
use cosim::system::SystemDescription;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The system of a mission scenario: its `[verdict]` and `[[requirement]]` tables are the
/// mission's, which this master does not read.
fn scenario(path: &Path) -> anyhow::Result<SystemDescription> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    let mut table: toml::Table =
        toml::from_str(&text).with_context(|| format!("reading {}", path.display()))?;
    table.remove("verdict");
    table.remove("requirement");
    Ok(cosim::system::toml_format::parse(
        &toml::to_string(&table)?,
        path,
    )?)
}

/// The instance of `system` that runs the FMU file `file`, if a connection feeds it.
fn fed_instance(system: &SystemDescription, file: &std::ffi::OsStr) -> Option<String> {
    system
        .instances
        .iter()
        .find(|i| {
            i.fmu.file_name() == Some(file)
                && system
                    .connections
                    .iter()
                    .any(|c| c.to.starts_with(&format!("{}.", i.name)))
        })
        .map(|i| i.name.clone())
}

fn main() -> anyhow::Result<()> {
    let mut args = std::env::args().skip(1);
    let (mut out_dir, mut scenarios, mut fmus) = (None, Vec::new(), Vec::new());
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--out-dir" => out_dir = args.next().map(PathBuf::from),
            "--scenario" => scenarios.extend(args.next().map(PathBuf::from)),
            _ => fmus.push(PathBuf::from(arg)),
        }
    }
    let Some(out_dir) = out_dir else {
        bail!("usage: fmu_reference --out-dir DIR [--scenario S.toml]... X.fmu...");
    };
    let systems = scenarios
        .iter()
        .map(|s| scenario(s))
        .collect::<anyhow::Result<Vec<_>>>()?;
    let mut flights: BTreeMap<usize, Trajectory> = BTreeMap::new();
    for fmu in &fmus {
        let started = std::time::Instant::now();
        let model = fmu
            .file_stem()
            .context("an FMU path names a file")?
            .to_string_lossy()
            .into_owned();
        let fmu_dir = fmu.parent().unwrap_or(Path::new("."));
        let fed = systems.iter().enumerate().find_map(|(k, system)| {
            fed_instance(system, fmu.file_name()?).map(|instance| (k, instance))
        });
        let (stimuli, from) = match fed {
            Some((k, instance)) => {
                // One flight per scenario, whichever FMUs it feeds.
                let flight = match flights.entry(k) {
                    std::collections::btree_map::Entry::Occupied(flown) => flown.into_mut(),
                    std::collections::btree_map::Entry::Vacant(slot) => slot.insert(
                        generate::fly(systems[k].clone(), fmu_dir)
                            .with_context(|| format!("flying {}", scenarios[k].display()))?,
                    ),
                };
                let table = generate::inputs_of(&systems[k], &instance, flight);
                let own = cosim::system::single::of_fmu(fmu)?;
                let csv =
                    generate::stimuli_csv(&table, own.start_time, own.stop_time, own.step_size);
                (
                    Some(csv),
                    format!("{} (instance {instance})", scenarios[k].display()),
                )
            }
            None => {
                let system = cosim::system::single::of_fmu(fmu)?;
                let steps =
                    generate::step_csv(fmu, system.start_time, system.stop_time, system.step_size)
                        .map_err(anyhow::Error::msg)?;
                let from = if steps.is_some() {
                    "a unit step"
                } else {
                    "none"
                };
                (steps, from.to_owned())
            }
        };
        let files = generate::references(
            fmu,
            &model,
            stimuli,
            &cosim::reference::Tolerances::default(),
        )
        .map_err(anyhow::Error::msg)
        .with_context(|| format!("running {}", fmu.display()))?;
        let dir = out_dir.join(&model);
        std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
        let mut bytes = 0;
        for (name, text) in &files.files {
            std::fs::write(dir.join(name), text)
                .with_context(|| format!("writing {}", dir.join(name).display()))?;
            bytes += text.len();
        }
        println!(
            "fmu_reference: {model}: inputs from {from}; {} files, {bytes} bytes, in {:.2} s",
            files.files.len(),
            started.elapsed().as_secs_f64()
        );
    }
    Ok(())
}
