//! The shipped scenarios and how a scenario argument is resolved: a built-in name,
//! a TOML file, an SSP `.ssd` or an `.ssp` package.
use cosim::master::{MasterError, Simulation};
use cosim::system::{ssp, PackageDir, SystemDescription, SystemError};
use fmi_abi::unpack::UnpackError;
use std::path::Path;

#[cfg(test)]
mod documented_keys;
pub mod spec;

/// The `--scenario` help of the campaign commands, naming every built-in scenario.
pub fn campaign_scenario_help() -> String {
    let names: Vec<&str> = BUILT_IN.iter().map(|(name, _)| *name).collect();
    format!(
        "Scenario: a built-in one ({}) or a .toml or .ssd scenario or .ssp package with \
         instances named `gnc` and `plant`",
        names.join(", ")
    )
}

/// Built-in scenarios: name, TOML text (the same files as `harness/scenarios/*.toml`, kept
/// beside the command line that users run them with).
pub const BUILT_IN: &[(&str, &str)] = &[
    (
        "paper",
        include_str!("../../../harness/scenarios/paper.toml"),
    ),
    (
        "flight",
        include_str!("../../../harness/scenarios/flight.toml"),
    ),
    (
        "upright",
        include_str!("../../../harness/scenarios/upright.toml"),
    ),
    (
        "descent-roll",
        include_str!("../../../harness/scenarios/descent-roll.toml"),
    ),
    (
        "landing",
        include_str!("../../../harness/scenarios/landing.toml"),
    ),
    (
        "paper-nav",
        include_str!("../../../harness/scenarios/paper-nav.toml"),
    ),
    (
        "paper-thrusters",
        include_str!("../../../harness/scenarios/paper-thrusters.toml"),
    ),
    (
        "retarget",
        include_str!("../../../harness/scenarios/retarget.toml"),
    ),
    (
        "full-fidelity",
        include_str!("../../../harness/scenarios/full-fidelity.toml"),
    ),
    (
        "full-fidelity-flight",
        include_str!("../../../harness/scenarios/full-fidelity-flight.toml"),
    ),
    (
        "landing-model-exchange",
        include_str!("../../../harness/scenarios/landing-model-exchange.toml"),
    ),
    (
        "fault-engine",
        include_str!("../../../harness/scenarios/fault-engine.toml"),
    ),
    (
        "fault-thruster",
        include_str!("../../../harness/scenarios/fault-thruster.toml"),
    ),
    (
        "fault-sensors",
        include_str!("../../../harness/scenarios/fault-sensors.toml"),
    ),
    (
        "fault-campaign",
        include_str!("../../../harness/scenarios/fault-campaign.toml"),
    ),
];

/// The error for a scenario argument that is neither a file nor a built-in name: it lists
/// the built-in names (and the closest one), so a user who typed a name learns the others.
pub fn not_found(name_or_path: &str, source: std::io::Error) -> SystemError {
    if source.kind() != std::io::ErrorKind::NotFound {
        return SystemError::Io {
            path: name_or_path.into(),
            source,
        };
    }
    let names: Vec<&str> = BUILT_IN.iter().map(|(name, _)| *name).collect();
    SystemError::Syntax {
        path: name_or_path.into(),
        message: format!(
            "no such file, and no built-in scenario of that name{}; the built-in scenarios \
             (harness/scenarios/<name>.toml): {}",
            cosim::suggest::hint(name_or_path, names.iter().copied()),
            names.join(", ")
        ),
    }
}

/// The terminal hover target of the shipped timeline (LanderGnc's default descent target).
pub const TERMINAL_TARGET_NUE: [f64; 3] = [0.0, 150.0, 0.0];

/// Where a scenario's flight should end, the point its terminal errors are measured from: the
/// retarget site when the scenario commands a retarget, else the descent target it sets on
/// its `gnc` instance (`descent_target_nue[k]`, each element defaulting to LanderGnc's).
pub fn terminal_target_nue(system: &cosim::system::SystemDescription) -> [f64; 3] {
    if let Ok(command) = crate::retarget::RetargetCommand::of(system) {
        return command.site_nue;
    }
    let mut target = TERMINAL_TARGET_NUE;
    for (k, x) in target.iter_mut().enumerate() {
        if let Some(value) =
            crate::retarget::command::real(system, &format!("descent_target_nue[{}]", k + 1))
        {
            *x = value;
        }
    }
    target
}

/// A built-in scenario by name, a `.toml` or `.ssd` file, an `.ssp` package, or one `.fmu`
/// run alone over its `DefaultExperiment`.
///
/// An SSD's component sources are relative to the SSD (`resources/X.fmu` in an SSP); where that
/// file exists it is used (as an absolute path, so the scenario runs from any directory),
/// otherwise the bare file name is looked up in the master's FMU directory, so the shipped
/// `harness/scenarios/paper.ssd` runs against `target/fmu`. An `.ssp` is unpacked into a
/// temporary directory that lives as long as the returned description.
pub fn load(name_or_path: &str) -> Result<SystemDescription, SystemError> {
    if let Some((name, text)) = BUILT_IN.iter().find(|(name, _)| *name == name_or_path) {
        let origin = format!("<built-in scenario {name}>");
        return spec::parse_toml(text, Path::new(&origin));
    }
    let path = Path::new(name_or_path);
    match path.extension().and_then(|e| e.to_str()) {
        Some("ssd") => read_ssd(path),
        Some("ssp") => read_package(path),
        Some("fmu") => cosim::system::single::of_fmu(path),
        _ => {
            let text = std::fs::read_to_string(path).map_err(|e| not_found(name_or_path, e))?;
            spec::parse_toml(&text, path)
        }
    }
}

fn read_ssd(path: &Path) -> Result<SystemDescription, SystemError> {
    let mut system = ssp::read(path)?;
    let absolute = std::path::absolute(path).map_err(|source| SystemError::Io {
        path: path.to_owned(),
        source,
    })?;
    let base = absolute.parent().unwrap_or(Path::new("/"));
    for instance in &mut system.instances {
        let beside = base.join(&instance.fmu);
        instance.fmu = if beside.is_file() {
            beside
        } else {
            instance.fmu.file_name().map(Into::into).unwrap_or_default()
        };
    }
    Ok(system)
}

/// The SSD file an SSP package must hold at its top level (SSP 1.0, section 3).
const PACKAGE_SSD: &str = "SystemStructure.ssd";

fn read_package(path: &Path) -> Result<SystemDescription, SystemError> {
    let io = |source| SystemError::Io {
        path: path.to_owned(),
        source,
    };
    let syntax = |message: String| SystemError::Syntax {
        path: path.to_owned(),
        message,
    };
    let dir = fmi_abi::unpack::unpack_archive(path, "harness-ssp-").map_err(|e| match e {
        UnpackError::Io { source, .. } => io(source),
        UnpackError::Zip { source, .. } => {
            syntax(format!("not an SSP package (a zip archive): {source}"))
        }
        UnpackError::Entry { entry, problem, .. } => syntax(format!("entry '{entry}' {problem}")),
        other => syntax(other.to_string()),
    })?;
    if !dir.path().join(PACKAGE_SSD).is_file() {
        return Err(syntax(format!(
            "the package has no {PACKAGE_SSD} at its top level"
        )));
    }
    // Named inside the package the user gave: the temporary directory is gone when they read it.
    let mut system = read_ssd(&dir.path().join(PACKAGE_SSD)).map_err(|e| match e {
        SystemError::Syntax { message, .. } => SystemError::Syntax {
            path: path.join(PACKAGE_SSD),
            message,
        },
        other => other,
    })?;
    for instance in &system.instances {
        if !instance.fmu.is_absolute() {
            return Err(syntax(format!(
                "component '{}': the package holds no {}",
                instance.name,
                Path::new("resources").join(&instance.fmu).display()
            )));
        }
    }
    system.package = Some(PackageDir(std::sync::Arc::new(dir)));
    Ok(system)
}

/// An SSD has no place for a scenario event: refused rather than dropped from the package.
fn no_events(system: &SystemDescription) -> Result<(), MasterError> {
    if system.events.is_empty() {
        return Ok(());
    }
    Err(MasterError::Resolve {
        system: system.name.clone(),
        problems: system
            .events
            .iter()
            .map(|e| {
                format!(
                    "event '{}' ({}): an SSP system structure cannot carry scenario events",
                    e.name,
                    e.describe()
                )
            })
            .collect(),
    })
}

/// The SSP `SystemStructure.ssd` of a scenario: its connections expanded to scalars and
/// typed from the FMUs in `fmu_dir`, components pointing at `resources/<file>.fmu`.
pub fn ssd_for(system: &SystemDescription, fmu_dir: &Path) -> Result<String, MasterError> {
    no_events(system)?;
    let simulation = Simulation::new(system.clone(), fmu_dir)?;
    Ok(ssp::write(
        system,
        simulation.connectors(),
        simulation.scalar_connections(),
    ))
}

/// The SSP 2.0 `SystemStructure.ssd` of a scenario whose FMUs (in `fmu_dir`) are FMI 3.0:
/// a connector per connected variable, arrays whole, components pointing at
/// `resources/<file>.fmu`.
pub fn ssd2_for(system: &SystemDescription, fmu_dir: &Path) -> Result<String, MasterError> {
    no_events(system)?;
    let simulation = Simulation::new(system.clone(), fmu_dir)?;
    cosim::system::ssp2::write(system, simulation.fmus()).map_err(|e| MasterError::Resolve {
        system: system.name.clone(),
        problems: vec![match e {
            SystemError::Invalid { message, .. } => message,
            other => other.to_string(),
        }],
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use cosim::system::ParamValue;

    #[test]
    fn the_terminal_target_is_the_scenarios_own() {
        // The default is LanderGnc's own descent target.
        let md = std::fs::read_to_string(
            std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("../fmu-gnc/modelDescription.xml"),
        )
        .unwrap();
        let md = model_description::ModelDescription::from_xml(&md).unwrap();
        for (k, expected) in TERMINAL_TARGET_NUE.iter().enumerate() {
            let name = format!("descent_target_nue[{}]", k + 1);
            let start = md.variable(&name).and_then(|v| v.start());
            assert_eq!(
                start,
                Some(model_description::StartValue::Real(*expected)),
                "{name}"
            );
        }
        let mut system = load("paper").unwrap();
        assert_eq!(terminal_target_nue(&system), TERMINAL_TARGET_NUE);
        system.set_parameter("gnc", "descent_target_nue[3]", ParamValue::Real(40.0));
        assert_eq!(terminal_target_nue(&system), [0.0, 150.0, 40.0]);
        let retarget = load("retarget").unwrap();
        let site = crate::retarget::RetargetCommand::of(&retarget)
            .unwrap()
            .site_nue;
        assert_eq!(terminal_target_nue(&retarget), site);
        assert_ne!(site, TERMINAL_TARGET_NUE);
    }

    #[test]
    fn every_built_in_scenario_parses_and_connects_the_contract_signals() {
        for (name, _) in BUILT_IN {
            let system = load(name).unwrap();
            assert!(system.instance("plant").is_some(), "{name}");
            assert!(system.instance("gnc").is_some(), "{name}");
            // Straight from the plant, through the navigation errors (LanderNav), or the
            // navigation state estimated by LanderFilter (the mass still from the plant).
            let nav = system.instance("nav").is_some();
            let filter = system.instance("filter").is_some();
            for signal in ["r_nue", "v_nue", "q_body_to_nue", "omega_body", "mass"] {
                let from = match (nav, filter) {
                    (true, _) => "nav",
                    (false, true) if signal != "mass" => "filter",
                    _ => "plant",
                };
                assert!(
                    system
                        .connections
                        .iter()
                        .any(|c| c.from == format!("{from}.{signal}")
                            && c.to == format!("gnc.{signal}")),
                    "{name}: {signal}"
                );
            }
        }
    }

    #[test]
    fn every_shipped_toml_scenario_is_a_built_in_name_with_the_same_text() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../harness/scenarios");
        let mut shipped = 0;
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_some_and(|e| e == "toml") {
                shipped += 1;
                let stem = path.file_stem().unwrap().to_str().unwrap();
                let built_in = BUILT_IN.iter().find(|(name, _)| *name == stem);
                let text = std::fs::read_to_string(&path).unwrap();
                assert_eq!(built_in.map(|(_, t)| *t), Some(text.as_str()), "{stem}");
            }
        }
        assert_eq!(shipped, BUILT_IN.len());
    }

    #[test]
    fn an_unknown_name_lists_the_built_in_scenarios_and_suggests_the_closest() {
        let message = load("paper-thruster").unwrap_err().to_string();
        assert!(
            message.contains("did you mean 'paper-thrusters'"),
            "{message}"
        );
        for (name, _) in BUILT_IN {
            assert!(message.contains(name), "{message}");
        }
    }

    #[test]
    fn the_tilted_start_is_15_deg_toward_north_with_the_pitch_axis_east() {
        let system = load("paper").unwrap();
        let plant = system.instance("plant").unwrap();
        let q: Vec<f64> = (1..=4)
            .map(|i| {
                match plant
                    .parameters
                    .iter()
                    .find(|(n, _)| *n == format!("q0_body_to_nue[{i}]"))
                {
                    Some((_, ParamValue::Real(x))) => *x,
                    other => panic!("q0[{i}]: {other:?}"),
                }
            })
            .collect();
        // Rotate body y (thrust) and body z (pitch) into NUE with R(q), scalar first.
        let (w, x, y, z) = (q[0], q[1], q[2], q[3]);
        let thrust_nue = [
            2.0 * (x * y - w * z),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z + w * x),
        ];
        let pitch_nue = [
            2.0 * (x * z + w * y),
            2.0 * (y * z - w * x),
            1.0 - 2.0 * (x * x + y * y),
        ];
        let tilt = thrust_nue[1].acos().to_degrees();
        assert!((tilt - 15.0).abs() < 1e-9, "tilt {tilt}");
        assert!(
            thrust_nue[0] > 0.0 && thrust_nue[2].abs() < 1e-12,
            "toward North"
        );
        assert!((pitch_nue[2] - 1.0).abs() < 1e-12, "pitch axis East");
    }
}
