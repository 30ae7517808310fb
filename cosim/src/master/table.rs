//! The inputs a system's input table drives: each column resolved to an input of an
//! instance, refused when it names no input or an input a connection already drives.
use super::resolve::{self, Port};
use fmi_import::Fmu;
use model_description::{Causality, Variability, VariableKind};

use crate::system::SystemDescription;

/// One input driven by one column of the table.
#[derive(Debug, Clone)]
pub struct TableInput {
    pub port: Port,
    /// Its slot among its unit's input buffers of its type.
    pub slot: usize,
    pub column: usize,
    /// A continuous Real input is interpolated; any other holds its last row.
    pub interpolate: bool,
}

/// Every column of the system's input table as an input, every problem pushed.
pub fn resolve(
    system: &SystemDescription,
    fmus: &[Fmu],
    pairs: &[(Port, Port)],
    problems: &mut Vec<String>,
) -> Vec<TableInput> {
    let Some(table) = &system.inputs else {
        return Vec::new();
    };
    let mut driven = Vec::new();
    for (column, name) in table.names.iter().enumerate() {
        let mut found = Vec::new();
        resolve::ports(system, fmus, name, &[Causality::Input], &mut found)
            .into_iter()
            .for_each(|port| {
                if port.name != name.split_once('.').map_or("", |(_, v)| v) {
                    // A vector name: the table has one column per element.
                    problems.push(format!(
                        "input table column '{name}': name each element ('{}.{}') in a \
                         column of its own",
                        system.instances[port.instance].name, port.name
                    ));
                    return;
                }
                if pairs.iter().any(|(_, destination)| *destination == port) {
                    problems.push(format!(
                        "input table column '{name}': a connection already drives this input"
                    ));
                    return;
                }
                if port.word.is_some() || port.is_text() {
                    problems.push(format!(
                        "input table column '{name}': the input is {}; an input table drives \
                         Real, Integer and Boolean inputs",
                        port.type_name()
                    ));
                    return;
                }
                let info = fmus[port.instance]
                    .variable(&port.name)
                    .expect("resolved ports exist");
                let interpolate =
                    port.kind == VariableKind::Real && info.variability == Variability::Continuous;
                driven.push(TableInput {
                    port,
                    slot: 0,
                    column,
                    interpolate,
                });
            });
        problems.extend(
            found
                .into_iter()
                .map(|problem| format!("input table column '{name}': {problem}")),
        );
    }
    driven
}
