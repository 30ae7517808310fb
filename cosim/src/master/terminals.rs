//! Connections between terminals (FMI 3.0 §2.4.9): `plant.navigation -> gnc.navigation`,
//! where both ends name a terminal of their FMU, stands for one connection per matching
//! member. Members are matched by `memberName` (`plug`, `bus`) or by position
//! (`sequence`); a `plug` member that finds no match is an error, unless the scenario
//! connects that input on its own line (a filter's navigation terminal without the mass,
//! say, with the mass taken from the plant); a `bus` member without a match stays
//! unconnected. Only `signal` members are connected: flows (`inflow`, `outflow`) need
//! Kirchhoff's law, which a signal master does not solve.
use crate::system::{split_path, Connection, SystemDescription};
use fmi_import::Fmu;
use model_description::terminals::{Terminal, TerminalMember};

/// The system's connections with every terminal connection replaced by its members'.
pub(super) fn expand(
    system: &SystemDescription,
    fmus: &[Fmu],
    problems: &mut Vec<String>,
) -> Vec<Connection> {
    let mut expanded = Vec::with_capacity(system.connections.len());
    let mut terminal_pairs = Vec::new();
    for connection in &system.connections {
        let from = terminal_of(system, fmus, &connection.from, problems);
        let to = terminal_of(system, fmus, &connection.to, problems);
        match (from, to) {
            (None, None) => expanded.push(connection.clone()),
            (Some(from), Some(to)) => terminal_pairs.push((connection, from, to)),
            (from, _) => {
                let (terminal, other) = if from.is_some() {
                    (&connection.from, &connection.to)
                } else {
                    (&connection.to, &connection.from)
                };
                problems.push(format!(
                    "connection {} -> {}: '{terminal}' is a terminal but '{other}' is not; a \
                     terminal connects to a terminal",
                    connection.from, connection.to
                ));
            }
        }
    }
    // Inputs the scenario connects on lines of their own: a plug member may leave them out.
    let singles: Vec<String> = expanded.iter().map(|c| c.to.clone()).collect();
    for (connection, (from_instance, from), (to_instance, to)) in terminal_pairs {
        let context = format!("connection {} -> {}", connection.from, connection.to);
        let Some(pairs) = match_members(&from, &to, &context, problems) else {
            continue;
        };
        for (side, terminal, instance, matched, inputs) in [
            (
                "source",
                &from,
                from_instance,
                pairs.iter().map(|p| p.0).collect::<Vec<_>>(),
                false,
            ),
            (
                "destination",
                &to,
                to_instance,
                pairs.iter().map(|p| p.1).collect(),
                true,
            ),
        ] {
            if terminal.matching_rule != "plug" {
                continue;
            }
            let missing: Vec<&str> = terminal
                .members
                .iter()
                .filter(|m| !matched.iter().any(|x| std::ptr::eq(*x, *m)))
                .filter(|m| {
                    !(inputs && singles.contains(&format!("{instance}.{}", m.variable_name)))
                })
                .map(|m| m.member_name.as_deref().unwrap_or(&m.variable_name))
                .collect();
            if !missing.is_empty() {
                problems.push(format!(
                    "{context}: the {side} terminal '{}' is a plug, and its members {} find \
                     no match in the other terminal{}",
                    terminal.name,
                    missing.join(", "),
                    if inputs {
                        " (connect them on lines of their own to take them from elsewhere)"
                    } else {
                        ""
                    }
                ));
            }
        }
        for (source, destination) in pairs {
            for member in [source, destination] {
                if member.variable_kind != "signal" {
                    problems.push(format!(
                        "{context}: member {} is a {} variable; the harness connects signals \
                         only (flows need a master that sums them)",
                        member.variable_name, member.variable_kind
                    ));
                }
            }
            expanded.push(Connection {
                from: format!("{from_instance}.{}", source.variable_name),
                to: format!("{to_instance}.{}", destination.variable_name),
            });
        }
    }
    expanded
}

/// `(instance, terminal)` if `path` names a terminal and no variable of its FMU.
fn terminal_of<'a>(
    system: &'a SystemDescription,
    fmus: &[Fmu],
    path: &str,
    problems: &mut Vec<String>,
) -> Option<(&'a str, Terminal)> {
    let (instance_name, name) = split_path(path)?;
    let index = system
        .instances
        .iter()
        .position(|i| i.name == instance_name)?;
    let fmu = &fmus[index];
    if !super::resolve::expand(fmu, name).is_empty() {
        return None;
    }
    let terminals = match fmu.terminals() {
        Ok(terminals) => terminals,
        Err(e) => {
            problems.push(format!("'{path}': {e}"));
            return None;
        }
    };
    let terminal = terminals.into_iter().find(|t| t.name == name)?;
    Some((&system.instances[index].name, terminal))
}

/// The (source, destination) member pairs of two terminals, by their matching rules.
fn match_members<'t>(
    from: &'t Terminal,
    to: &'t Terminal,
    context: &str,
    problems: &mut Vec<String>,
) -> Option<Vec<(&'t TerminalMember, &'t TerminalMember)>> {
    for terminal in [from, to] {
        if !matches!(terminal.matching_rule.as_str(), "plug" | "bus" | "sequence") {
            problems.push(format!(
                "{context}: terminal '{}' has matchingRule '{}'; the harness matches plug, bus \
                 and sequence terminals",
                terminal.name, terminal.matching_rule
            ));
            return None;
        }
    }
    if from.matching_rule == "sequence" || to.matching_rule == "sequence" {
        if from.members.len() != to.members.len() {
            problems.push(format!(
                "{context}: terminals matched in sequence need as many members on each side \
                 ({} has {}, {} has {})",
                from.name,
                from.members.len(),
                to.name,
                to.members.len()
            ));
            return None;
        }
        return Some(from.members.iter().zip(&to.members).collect());
    }
    let pairs: Vec<_> = from
        .members
        .iter()
        .filter_map(|source| {
            let name = source.member_name.as_deref()?;
            to.members
                .iter()
                .find(|d| d.member_name.as_deref() == Some(name))
                .map(|destination| (source, destination))
        })
        .collect();
    if pairs.is_empty() {
        problems.push(format!(
            "{context}: terminals '{}' and '{}' share no member name",
            from.name, to.name
        ));
        return None;
    }
    Some(pairs)
}
