//! `--set INSTANCE.VAR=VALUE` on the command line: parsed, checked and applied to a system
//! description, every problem at once, each naming the option it came from.
use anyhow::Context;
use cosim::system::{split_path, ParamValue, SystemDescription};

/// `INSTANCE.VAR=VALUE`, the value typed as integer, real, boolean or else string.
pub fn parse_set(text: &str) -> anyhow::Result<(String, String, ParamValue)> {
    let (path, value) = text
        .split_once('=')
        .with_context(|| format!("--set {text}: expected INSTANCE.VAR=VALUE"))?;
    let (instance, variable) =
        split_path(path).with_context(|| format!("--set {text}: expected INSTANCE.VAR=VALUE"))?;
    let value = if let Ok(i) = value.parse::<i64>() {
        ParamValue::Integer(i)
    } else if let Ok(x) = value.parse::<f64>() {
        ParamValue::Real(x)
    } else if let Ok(b) = value.parse::<bool>() {
        ParamValue::Boolean(b)
    } else {
        ParamValue::String(value.to_owned())
    };
    Ok((instance.to_owned(), variable.to_owned(), value))
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
        match parse_set(set) {
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
