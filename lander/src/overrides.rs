//! `--set INSTANCE.VAR=VALUE` on the command line: parsed, checked and applied to a system
//! description, every problem at once, each naming the option it came from.
use anyhow::Context;
use cosim::system::{split_path, ParamValue, SystemDescription};

/// `INSTANCE.VAR=VALUE`, the value typed as integer, real, boolean or else string (an integer
/// beyond i64 stays a string).
pub fn parse_set(text: &str) -> anyhow::Result<(String, String, ParamValue)> {
    let (path, value) = text
        .split_once('=')
        .with_context(|| format!("--set {text}: expected INSTANCE.VAR=VALUE"))?;
    let (instance, variable) =
        split_path(path).with_context(|| format!("--set {text}: expected INSTANCE.VAR=VALUE"))?;
    let value = if let Ok(i) = value.parse::<i64>() {
        ParamValue::Integer(i)
    } else if value.parse::<u64>().is_ok() {
        // Beyond i64 (a UInt64 above 2^63 - 1): kept as its text, which a UInt64 variable
        // reads exactly; as a number it would round.
        ParamValue::String(value.to_owned())
    } else if let Ok(x) = value.parse::<f64>() {
        ParamValue::Real(x)
    } else if let Ok(b) = value.parse::<bool>() {
        ParamValue::Boolean(b)
    } else {
        ParamValue::String(value.to_owned())
    };
    Ok((instance.to_owned(), variable.to_owned(), value))
}

/// [`parse_set`], where a system of one instance (one FMU run alone) also takes `VAR=VALUE`:
/// naming the instance would be a formality, and `VAR` may itself hold dots (`sub.x`).
fn parse_set_for(
    system: &SystemDescription,
    text: &str,
) -> anyhow::Result<(String, String, ParamValue)> {
    let parsed = parse_set(text);
    if let [only] = system.instances.as_slice() {
        let names_it = matches!(&parsed, Ok((instance, _, _)) if *instance == only.name);
        if !names_it {
            if let Some((variable, _)) = text.split_once('=') {
                if let Ok((_, _, value)) = parse_set(&format!("{}.{text}", only.name)) {
                    return Ok((only.name.clone(), variable.to_owned(), value));
                }
            }
        }
    }
    parsed
}

/// Column names as `instance.variable`: for a system of one instance (one FMU run alone) a
/// bare variable name is that instance's.
pub fn qualified(system: &SystemDescription, names: &[String]) -> Vec<String> {
    match system.instances.as_slice() {
        [only] => names
            .iter()
            .map(|name| match name.strip_prefix(&only.name) {
                Some(rest) if rest.starts_with('.') => name.clone(),
                _ => format!("{}.{name}", only.name),
            })
            .collect(),
        _ => names.to_vec(),
    }
}

/// `--interface [INSTANCE=]KIND`: every instance (or the one named) runs through
/// Co-Simulation or Model Exchange (with the default solver), whatever its scenario says.
/// Every problem at once.
pub fn apply_interfaces(system: &mut SystemDescription, interfaces: &[String]) -> Vec<String> {
    let mut problems = Vec::new();
    for text in interfaces {
        let (instance, kind) = match text.split_once('=') {
            Some((instance, kind)) => (Some(instance), kind),
            None => (None, text.as_str()),
        };
        let model_exchange = match kind {
            "co-simulation" => false,
            "model-exchange" => true,
            other => {
                problems.push(format!(
                    "--interface {text}: '{other}' is neither co-simulation nor model-exchange"
                ));
                continue;
            }
        };
        if let Some(name) = instance {
            if system.instance(name).is_none() {
                let names = system.instances.iter().map(|i| i.name.as_str());
                problems.push(format!(
                    "--interface {text}: no instance '{name}'{}",
                    cosim::suggest::hint(name, names)
                ));
                continue;
            }
        }
        for desc in &mut system.instances {
            if instance.is_none_or(|name| name == desc.name) {
                desc.interface_named = true;
                desc.model_exchange = match (model_exchange, desc.model_exchange) {
                    (false, _) => None,
                    (true, Some(settings)) => Some(settings),
                    (true, None) => Some(Default::default()),
                };
            }
        }
    }
    problems
}

/// Applies every `--set` to `system`: the problems (all of them, each naming its --set) and
/// what was set, `(instance, variable, the --set text)`, so that later errors about a value
/// can say it came from the command line. `reserved` lists variables the command sets
/// itself, with what to use instead.
pub fn apply_sets<'a>(
    system: &mut SystemDescription,
    sets: &'a [String],
    reserved: &[(&str, &str)],
) -> (Vec<String>, Vec<(String, String, &'a str)>) {
    let mut problems = Vec::new();
    let mut seen: Vec<(String, String, &str)> = Vec::new();
    for set in sets {
        match parse_set_for(system, set) {
            Ok((instance, variable, value)) => {
                let path = format!("{instance}.{variable}");
                if let Some((_, instead)) = reserved.iter().find(|(name, _)| *name == path) {
                    problems.push(format!(
                        "--set {set}: this command sets {path} itself; {instead}"
                    ));
                    continue;
                }
                // Two values for one variable: which one was meant is not ours to
                // guess (a last-wins rule would drop one silently).
                if let Some((_, _, first)) = seen
                    .iter()
                    .find(|(i, v, _)| *i == instance && *v == variable)
                {
                    problems.push(format!(
                        "--set {set}: {instance}.{variable} is already set by --set \
                         {first}"
                    ));
                    continue;
                }
                seen.push((instance.clone(), variable.clone(), set.as_str()));
                if !system.set_parameter(&instance, &variable, value) {
                    let names = system.instances.iter().map(|i| i.name.as_str());
                    problems.push(format!(
                        "--set {set}: no instance '{instance}'{}",
                        cosim::suggest::hint(&instance, names)
                    ));
                }
            }
            Err(error) => problems.push(error.to_string()),
        }
    }
    (problems, seen)
}
