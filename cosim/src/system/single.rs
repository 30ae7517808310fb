//! One FMU as a system of its own, run the way fmpy's `simulate_fmu` and fmusim run one: an
//! instance named after the file, no connections, every output recorded, the times of its
//! `DefaultExperiment`, and the interface it declares (Co-Simulation when it has both).
use super::{InstanceDesc, Ordering, SystemDescription, SystemError};
use std::path::Path;

/// Output points when the FMU gives no step size: fmpy's default (`stop_time / 500`).
const DEFAULT_POINTS: f64 = 500.0;

/// The system that runs the FMU at `path` alone. Its description is read, no FMU code runs.
pub fn of_fmu(path: &Path) -> Result<SystemDescription, SystemError> {
    let (_, description) = fmi_import::read_description(path).map_err(|e| SystemError::Syntax {
        path: path.to_owned(),
        message: format!("not an FMU the harness can read: {e}"),
    })?;
    let absolute = std::path::absolute(path).map_err(|source| SystemError::Io {
        path: path.to_owned(),
        source,
    })?;
    let experiment = description.default_experiment.clone().unwrap_or_default();
    let start_time = experiment.start_time.unwrap_or(0.0);
    let stop_time = experiment.stop_time.unwrap_or(start_time + 1.0);
    let step_size = experiment
        .step_size
        .unwrap_or((stop_time - start_time) / DEFAULT_POINTS);
    let system = SystemDescription {
        name: description.model_name.clone(),
        start_time,
        stop_time,
        step_size,
        ordering: Ordering::default(),
        instances: vec![InstanceDesc {
            name: instance_name(path),
            fmu: absolute,
            parameters: Vec::new(),
            connectors: None,
            model_exchange: None,
            interface_named: false,
        }],
        connections: Vec::new(),
        record: None,
        limits: Default::default(),
        allow_non_finite: Vec::new(),
        events: Vec::new(),
        inputs: None,
        package: None,
    };
    system.validate().map_err(|error| SystemError::Syntax {
        path: path.to_owned(),
        message: format!("its DefaultExperiment cannot be run: {error}"),
    })?;
    Ok(system)
}

/// The file's stem, with every character a column name could not carry (a dot separates the
/// instance from the variable) replaced by `_`: `Bouncing Ball.fmu` runs as `Bouncing_Ball`.
fn instance_name(path: &Path) -> String {
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let name: String = stem
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' || c == '-' {
                c
            } else {
                '_'
            }
        })
        .collect();
    if name.is_empty() {
        "fmu".into()
    } else {
        name
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_instance_name_carries_no_dot_or_space() {
        assert_eq!(instance_name(Path::new("/x/Oscillator.fmu")), "Oscillator");
        assert_eq!(
            instance_name(Path::new("a/Bouncing Ball.v2.fmu")),
            "Bouncing_Ball_v2"
        );
        assert_eq!(instance_name(Path::new(".fmu")), "_fmu");
    }
}
