//! The TOML scenario format (see `harness/scenarios/paper.toml` for a commented example).
use super::{Connection, InstanceDesc, Ordering, ParamValue, SystemDescription, SystemError};
use serde::Deserialize;
use std::path::{Path, PathBuf};

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
    /// `[limits]`: call_timeout_s, run_timeout_s, memory_mb of a supervised run.
    #[serde(default)]
    limits: crate::limits::Limits,
    #[serde(default)]
    allow_non_finite: Vec<String>,
    /// `[campaign]`: read by `harness campaign`, checked here for its keys only.
    #[serde(default)]
    #[allow(dead_code)]
    campaign: Option<super::campaign_table::Declaration>,
    #[serde(default, rename = "event")]
    events: Vec<EventEntry>,
}

/// `[[event]]`: `set = value` at `time` (see `system/event.rs`).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct EventEntry {
    name: String,
    /// s.
    time: f64,
    /// `instance.variable`.
    set: String,
    value: toml::Value,
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
    /// "co-simulation" (default) or "model-exchange".
    interface: Option<String>,
    /// Model Exchange only: "tsit45" (non-stiff, default) or "bdf" (stiff).
    solver: Option<String>,
    relative_tolerance: Option<f64>,
    absolute_tolerance: Option<f64>,
    /// Width of the time bracket a state event is located to, in seconds.
    event_tolerance: Option<f64>,
    /// BDF's Jacobian: "fmu" (directional derivatives when declared, default) or
    /// "differences".
    jacobian: Option<String>,
}

/// The instance's interface and solver, every problem named at once.
fn solver_settings(instance: &Instance) -> Result<Option<super::SolverSettings>, Vec<String>> {
    let name = &instance.name;
    let mut problems = Vec::new();
    let model_exchange = match instance.interface.as_deref() {
        None | Some("co-simulation") => false,
        Some("model-exchange") => true,
        Some(other) => {
            problems.push(format!(
                "instance '{name}': interface = \"{other}\" is neither \"co-simulation\" nor \
                 \"model-exchange\""
            ));
            false
        }
    };
    let solver_keys = [
        ("solver", instance.solver.is_some()),
        ("relative_tolerance", instance.relative_tolerance.is_some()),
        ("absolute_tolerance", instance.absolute_tolerance.is_some()),
        ("event_tolerance", instance.event_tolerance.is_some()),
        ("jacobian", instance.jacobian.is_some()),
    ];
    if !model_exchange {
        for (key, given) in solver_keys {
            if given {
                problems.push(format!(
                    "instance '{name}': {key} is a Model Exchange setting; add interface = \
                     \"model-exchange\" or remove it"
                ));
            }
        }
        return if problems.is_empty() {
            Ok(None)
        } else {
            Err(problems)
        };
    }
    let mut settings = super::SolverSettings::default();
    match instance.solver.as_deref() {
        None | Some("tsit45") => settings.method = ode_solver::Method::Tsit45,
        Some("bdf") => settings.method = ode_solver::Method::Bdf,
        Some(other) => problems.push(format!(
            "instance '{name}': solver = \"{other}\" is neither \"tsit45\" (non-stiff) nor \
             \"bdf\" (stiff)"
        )),
    }
    match instance.jacobian.as_deref() {
        None | Some("fmu") => settings.jacobian = super::JacobianSource::Fmu,
        Some("differences") => settings.jacobian = super::JacobianSource::Differences,
        Some(other) => problems.push(format!(
            "instance '{name}': jacobian = \"{other}\" is neither \"fmu\" (the FMU's \
             directional derivatives) nor \"differences\""
        )),
    }
    for (key, value, slot) in [
        (
            "relative_tolerance",
            instance.relative_tolerance,
            &mut settings.tolerances.relative,
        ),
        (
            "absolute_tolerance",
            instance.absolute_tolerance,
            &mut settings.tolerances.absolute,
        ),
        (
            "event_tolerance",
            instance.event_tolerance,
            &mut settings.tolerances.event_time,
        ),
    ] {
        match value {
            Some(v) if v.is_finite() && v > 0.0 => *slot = v,
            Some(v) => problems.push(format!(
                "instance '{name}': {key} = {v} must be a positive number"
            )),
            None => {}
        }
    }
    if problems.is_empty() {
        Ok(Some(settings))
    } else {
        Err(problems)
    }
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
    let mut problems = Vec::new();
    for instance in file.instances {
        let interface_named = instance.interface.is_some();
        let model_exchange = solver_settings(&instance).unwrap_or_else(|p| {
            problems.extend(p);
            None
        });
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
            fmu: beside(origin, instance.fmu.into()),
            parameters,
            connectors: None,
            model_exchange,
            interface_named,
        });
    }
    let mut events = Vec::with_capacity(file.events.len());
    for event in file.events {
        let value = match event.value {
            toml::Value::Float(x) => ParamValue::Real(x),
            toml::Value::Integer(i) => ParamValue::Integer(i),
            toml::Value::Boolean(b) => ParamValue::Boolean(b),
            other => {
                problems.push(format!(
                    "event '{}': value {other} is not a number, an integer or a boolean",
                    event.name
                ));
                continue;
            }
        };
        let Some((instance, variable)) = super::event::target(&event.set) else {
            problems.push(format!(
                "event '{}': set = \"{}\" is not of the form instance.variable",
                event.name, event.set
            ));
            continue;
        };
        events.push(super::Event {
            name: event.name,
            time_s: event.time,
            instance,
            variable,
            value,
        });
    }
    problems.extend(file.limits.problems("[limits]"));
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
        limits: file.limits,
        allow_non_finite: file.allow_non_finite,
        inputs: None,
        events,
        package: None,
    };
    if !problems.is_empty() {
        // With the checks of the whole system, so that every problem is named at once.
        if let Err(SystemError::Invalid { message, .. }) = system.validate() {
            problems.push(message);
        }
        return Err(syntax(problems.join("; ")));
    }
    system.validate()?;
    Ok(system)
}

/// A relative `fmu` that exists beside the scenario file is taken from there, as an absolute
/// path so the run works from any directory (as an SSD's are); otherwise it stays relative
/// and the master looks it up in its FMU directory.
fn beside(origin: &Path, fmu: PathBuf) -> PathBuf {
    if fmu.is_absolute() || !origin.is_file() {
        return fmu;
    }
    match std::path::absolute(origin) {
        Ok(scenario) => match scenario.parent().map(|dir| dir.join(&fmu)) {
            Some(path) if path.is_file() => path,
            _ => fmu,
        },
        Err(_) => fmu,
    }
}

/// The keys of each table of the format the system reads, by table (`""` the top level), as
/// the reader accepts them; `[verdict]` and `[[requirement]]` are read elsewhere.
pub fn keys() -> Vec<(&'static str, &'static [&'static str])> {
    vec![
        ("", super::fields::of::<File>()),
        ("instance", super::fields::of::<Instance>()),
        ("connection", super::fields::of::<ConnectionEntry>()),
        ("limits", super::fields::of::<crate::limits::Limits>()),
        ("event", super::fields::of::<EventEntry>()),
    ]
    .into_iter()
    .chain(super::campaign_table::keys())
    .collect()
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
    fn an_fmu_beside_the_scenario_is_taken_from_there_and_others_stay_for_the_fmu_dir() {
        let dir = tempfile::tempdir().unwrap();
        let scenario = dir.path().join("demo.toml");
        std::fs::write(&scenario, SAMPLE).unwrap();
        std::fs::write(dir.path().join("A.fmu"), b"not read here").unwrap();
        let system = read(&scenario).unwrap();
        let a = &system.instance("a").unwrap().fmu;
        assert!(a.is_absolute(), "{}", a.display());
        assert_eq!(
            std::fs::canonicalize(a).unwrap(),
            std::fs::canonicalize(dir.path().join("A.fmu")).unwrap()
        );
        // Not beside the scenario: left to the master's FMU directory.
        assert_eq!(system.instance("b").unwrap().fmu, Path::new("B.fmu"));
        // A scenario that is no file (a built-in one) has no "beside".
        let built_in = parse(SAMPLE, Path::new("<built-in scenario demo>")).unwrap();
        assert_eq!(built_in.instance("a").unwrap().fmu, Path::new("A.fmu"));
    }

    #[test]
    fn allow_non_finite_is_a_top_level_list_of_paths_empty_by_default() {
        assert!(parse(SAMPLE, Path::new("demo.toml"))
            .unwrap()
            .allow_non_finite
            .is_empty());
        let text = format!("allow_non_finite = [\"a.y\", \"b.v\"]\n{SAMPLE}");
        let system = parse(&text, Path::new("demo.toml")).unwrap();
        assert_eq!(system.allow_non_finite, ["a.y", "b.v"]);
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

// A scenario's events read here, then changed as a campaign changes them.
#[cfg(test)]
mod event_changes {
    use crate::system::event::Change;
    use crate::system::ParamValue;

    fn system() -> crate::system::SystemDescription {
        let text = "name = \"s\"\nstop_time = 10.0\nstep_size = 0.5\n\
            [[instance]]\nname = \"osc\"\nfmu = \"Oscillator.fmu\"\n\
            [[event]]\nname = \"stiffen\"\ntime = 2.0\nset = \"osc.k\"\nvalue = 4.0\n\
            [[event]]\nname = \"damp\"\ntime = 3.0\nset = \"osc.c\"\nvalue = 1.0\n";
        super::parse(text, std::path::Path::new(".")).unwrap()
    }

    #[test]
    fn a_changed_event_takes_its_new_time_or_value_and_a_refused_one_stays() {
        let mut s = system();
        s.change_event("stiffen", &Change::Time(7.25)).unwrap();
        s.change_event("damp", &Change::Value(ParamValue::Real(0.5)))
            .unwrap();
        assert_eq!(s.events[0].time_s, 7.25);
        assert_eq!(s.events[1].value, ParamValue::Real(0.5));
        let before = s.events.clone();
        for (name, change, expected) in [
            (
                "nope",
                Change::Time(1.0),
                "no event named 'nope' (the scenario has stiffen, damp)",
            ),
            (
                "stiffen",
                Change::Time(10.5),
                "time 10.5 s is outside [start_time, stop_time]",
            ),
            (
                "stiffen",
                Change::Time(9.75),
                "after the last communication point a step starts",
            ),
            (
                "stiffen",
                Change::Time(f64::NAN),
                "time NaN is not a number",
            ),
            (
                "damp",
                Change::Value(ParamValue::Integer(2)),
                "is not of the event's type",
            ),
            (
                "damp",
                Change::Value(ParamValue::Real(f64::INFINITY)),
                "value inf is not a finite",
            ),
        ] {
            let refused = s.change_event(name, &change).unwrap_err();
            assert!(refused.contains(expected), "{change:?}: {refused}");
        }
        assert_eq!(s.events, before);
    }
}

#[cfg(test)]
mod campaign_table {
    #[test]
    fn the_system_reader_accepts_the_table_and_refuses_a_misspelt_key_in_it() {
        let scenario = "name = 'x'\nstop_time = 1.0\n[[instance]]\nname = 'a'\nfmu = 'A.fmu'\n\
                        [campaign]\nruns = 2\n[[campaign.sweep]]\nparameter = 'a.b'\n\
                        values = [1.0]\n";
        let origin = std::path::Path::new("x.toml");
        let system = super::parse(scenario, origin).unwrap();
        assert_eq!(system.instances[0].name, "a");
        let misspelt = scenario.replace("parameter = 'a.b'", "paramter = 'a.b'");
        let e = super::parse(&misspelt, origin).unwrap_err();
        assert!(e.to_string().contains("paramter"), "{e}");
    }
}
