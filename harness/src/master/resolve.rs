//! Resolving a system against its FMUs before anything runs: vector shorthands expanded,
//! every name looked up, every connection type-checked. All problems are reported together,
//! with the names, so a user fixes a scenario in one pass.
use crate::loader::{Fmu, VariableKind};
use crate::system::{split_path, SystemDescription};
use model_description::Causality;

/// A scalar variable of an instance, by value reference and exchange type.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Port {
    pub instance: usize,
    pub name: String,
    pub value_reference: u32,
    /// Real, Integer (enumerations included) or Boolean; strings are not exchanged.
    pub kind: VariableKind,
}

/// Expands `var` to the scalar names it stands for in `fmu`: itself if it exists, else
/// `var[1]`, `var[2]`, ... while they exist.
pub fn expand(fmu: &Fmu, variable: &str) -> Vec<String> {
    if fmu.variable(variable).is_ok() {
        return vec![variable.to_owned()];
    }
    (1..)
        .map(|i| format!("{variable}[{i}]"))
        .take_while(|name| fmu.variable(name).is_ok())
        .collect()
}

fn exchange_kind(kind: VariableKind) -> Option<VariableKind> {
    match kind.accessed_as() {
        VariableKind::String => None,
        other => Some(other),
    }
}

/// Resolves `instance.variable` (vectors allowed) to ports, checking causality with `want`.
pub fn ports(
    system: &SystemDescription,
    fmus: &[Fmu],
    path: &str,
    want: &[Causality],
    problems: &mut Vec<String>,
) -> Vec<Port> {
    let Some((instance_name, variable)) = split_path(path) else {
        problems.push(format!("'{path}' is not of the form instance.variable"));
        return vec![];
    };
    let Some(instance) = system
        .instances
        .iter()
        .position(|i| i.name == instance_name)
    else {
        problems.push(format!("'{path}': no instance named '{instance_name}'"));
        return vec![];
    };
    let fmu = &fmus[instance];
    let names = expand(fmu, variable);
    if names.is_empty() {
        problems.push(format!(
            "'{path}': model '{}' has no variable '{variable}' (nor '{variable}[1]')",
            fmu.model_name()
        ));
        return vec![];
    }
    let mut out = Vec::with_capacity(names.len());
    for name in names {
        let info = *fmu.variable(&name).expect("expanded names exist");
        if !want.is_empty() && !want.contains(&info.causality) {
            problems.push(format!(
                "'{instance_name}.{name}' has causality {:?}, expected one of {want:?}",
                info.causality
            ));
            continue;
        }
        let Some(kind) = exchange_kind(info.kind) else {
            problems.push(format!(
                "'{instance_name}.{name}' is a String; strings are not exchanged or recorded"
            ));
            continue;
        };
        out.push(Port {
            instance,
            name,
            value_reference: info.value_reference,
            kind,
        });
    }
    out
}

/// Resolves every connection to scalar (source, destination) pairs.
pub fn connections(
    system: &SystemDescription,
    fmus: &[Fmu],
    problems: &mut Vec<String>,
) -> Vec<(Port, Port)> {
    let mut pairs = Vec::new();
    for connection in &system.connections {
        let from = ports(
            system,
            fmus,
            &connection.from,
            &[Causality::Output],
            problems,
        );
        let to = ports(system, fmus, &connection.to, &[Causality::Input], problems);
        if from.is_empty() || to.is_empty() {
            continue;
        }
        if from.len() != to.len() {
            problems.push(format!(
                "connection {} -> {}: {} source components but {} destination components",
                connection.from,
                connection.to,
                from.len(),
                to.len()
            ));
            continue;
        }
        for (source, destination) in from.into_iter().zip(to) {
            if source.kind != destination.kind {
                problems.push(format!(
                    "connection {}.{} -> {}.{}: type mismatch ({:?} -> {:?})",
                    system.instances[source.instance].name,
                    source.name,
                    system.instances[destination.instance].name,
                    destination.name,
                    source.kind,
                    destination.kind
                ));
                continue;
            }
            if pairs.iter().any(|(_, d): &(Port, Port)| *d == destination) {
                problems.push(format!(
                    "input {}.{} is connected twice",
                    system.instances[destination.instance].name, destination.name
                ));
                continue;
            }
            pairs.push((source, destination));
        }
    }
    pairs
}

/// The recorded columns: the system's selection, or every output of every instance.
pub fn columns(system: &SystemDescription, fmus: &[Fmu], problems: &mut Vec<String>) -> Vec<Port> {
    match &system.record {
        Some(selection) => selection
            .iter()
            .flat_map(|path| ports(system, fmus, path, &[], problems))
            .collect(),
        None => {
            let mut out = Vec::new();
            for (instance, fmu) in fmus.iter().enumerate() {
                for variable in fmu.model_description().outputs() {
                    let Some(kind) = variable.kind().and_then(exchange_kind) else {
                        continue;
                    };
                    out.push(Port {
                        instance,
                        name: variable.name.clone(),
                        value_reference: variable.value_reference,
                        kind,
                    });
                }
            }
            out
        }
    }
}
