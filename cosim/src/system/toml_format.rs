//! The TOML scenario format (see `harness/scenarios/paper.toml` for a commented example).
use super::{Connection, InstanceDesc, Ordering, ParamValue, SystemDescription, SystemError};
use serde::Deserialize;
use std::path::Path;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct File {
    name: String,
    #[serde(default)]
    start_time: f64,
    stop_time: f64,
    #[serde(default = "default_step")]
    step_size: f64,
    #[serde(default)]
    ordering: Ordering,
    #[serde(rename = "instance")]
    instances: Vec<Instance>,
    #[serde(default, rename = "connection")]
    connections: Vec<ConnectionEntry>,
    #[serde(default)]
    record: Option<Vec<String>>,
}

fn default_step() -> f64 {
    0.01
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Instance {
    name: String,
    fmu: String,
    #[serde(default)]
    parameters: toml::Table,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ConnectionEntry {
    from: String,
    to: String,
}

/// Parses a TOML scenario; `origin` names the file in errors.
pub fn parse(text: &str, origin: &Path) -> Result<SystemDescription, SystemError> {
    let syntax = |message: String| SystemError::Syntax {
        path: origin.to_owned(),
        message,
    };
    let file: File = toml::from_str(text).map_err(|e| syntax(e.to_string()))?;
    let mut instances = Vec::with_capacity(file.instances.len());
    for instance in file.instances {
        let mut parameters = Vec::with_capacity(instance.parameters.len());
        for (name, value) in instance.parameters {
            let value = match value {
                toml::Value::Float(x) => ParamValue::Real(x),
                toml::Value::Integer(i) => ParamValue::Integer(i),
                toml::Value::Boolean(b) => ParamValue::Boolean(b),
                toml::Value::String(s) => ParamValue::String(s),
                other => {
                    return Err(syntax(format!(
                        "instance '{}': parameter '{name}' has unsupported value {other} \
                         (use a number, boolean or string)",
                        instance.name
                    )))
                }
            };
            parameters.push((name, value));
        }
        instances.push(InstanceDesc {
            name: instance.name,
            fmu: instance.fmu.into(),
            parameters,
            connectors: None,
        });
    }
    let system = SystemDescription {
        name: file.name,
        start_time: file.start_time,
        stop_time: file.stop_time,
        step_size: file.step_size,
        ordering: file.ordering,
        instances,
        connections: file
            .connections
            .into_iter()
            .map(|c| Connection {
                from: c.from,
                to: c.to,
            })
            .collect(),
        record: file.record,
        package: None,
    };
    system.validate()?;
    Ok(system)
}

/// Reads a TOML scenario file.
pub fn read(path: &Path) -> Result<SystemDescription, SystemError> {
    let text = std::fs::read_to_string(path).map_err(|source| SystemError::Io {
        path: path.to_owned(),
        source,
    })?;
    parse(&text, path)
}

#[cfg(test)]
mod tests {
    use super::*;

    const SAMPLE: &str = r#"
        name = "demo"
        stop_time = 2.0
        [[instance]]
        name = "a"
        fmu = "A.fmu"
        parameters = { k = 2.5, n = 3, on = true, label = "x" }
        [[instance]]
        name = "b"
        fmu = "B.fmu"
        [[connection]]
        from = "a.y"
        to = "b.u"
    "#;

    #[test]
    fn a_scenario_reads_with_defaults_and_typed_parameters() {
        let system = parse(SAMPLE, Path::new("demo.toml")).unwrap();
        assert_eq!(system.step_size, 0.01);
        assert_eq!(system.start_time, 0.0);
        assert_eq!(system.ordering, Ordering::GaussSeidel);
        let a = system.instance("a").unwrap();
        assert!(a.parameters.contains(&("k".into(), ParamValue::Real(2.5))));
        assert!(a.parameters.contains(&("n".into(), ParamValue::Integer(3))));
        assert!(a
            .parameters
            .contains(&("on".into(), ParamValue::Boolean(true))));
        assert!(a
            .parameters
            .contains(&("label".into(), ParamValue::String("x".into()))));
        assert_eq!(system.connections[0].from, "a.y");
    }

    #[test]
    fn a_connection_to_an_unknown_instance_is_refused_by_name() {
        let text = SAMPLE.replace("b.u", "c.u");
        let error = parse(&text, Path::new("demo.toml"))
            .unwrap_err()
            .to_string();
        assert!(error.contains("'c.u'") && error.contains("'c'"), "{error}");
    }

    #[test]
    fn every_invalid_connection_end_and_time_is_reported_at_once() {
        let text = SAMPLE
            .replace("b.u", "bb.u")
            .replace("a.y", "ay")
            .replace("stop_time = 2.0", "stop_time = -1.0");
        let error = parse(&text, Path::new("demo.toml"))
            .unwrap_err()
            .to_string();
        assert!(error.contains("'ay' is not of the form"), "{error}");
        assert!(
            error.contains("unknown instance 'bb' (did you mean 'b'?)"),
            "{error}"
        );
        assert!(error.contains("stop_time (-1)"), "{error}");
    }

    #[test]
    fn an_unknown_key_is_a_syntax_error_naming_the_file() {
        let text = SAMPLE.replace("stop_time", "stop_tme");
        let error = parse(&text, Path::new("demo.toml"))
            .unwrap_err()
            .to_string();
        assert!(
            error.contains("demo.toml") && error.contains("stop_tme"),
            "{error}"
        );
    }

    #[test]
    fn a_non_positive_step_is_refused() {
        let text = SAMPLE.replace("stop_time = 2.0", "stop_time = 2.0\nstep_size = 0.0");
        let error = parse(&text, Path::new("demo.toml"))
            .unwrap_err()
            .to_string();
        assert!(error.contains("step_size"), "{error}");
    }
}
