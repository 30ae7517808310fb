//! `harness vars FMU`: an FMU's variables as a user wires them (name, causality,
//! variability, type, start, unit, description), optionally of one causality.
use model_description::{Causality, ModelDescription, StartValue};
use std::fmt::Write;

/// The causality a user asks for, as the standard spells it.
pub fn parse_causality(text: &str) -> Option<Causality> {
    Causality::from_name(text)
}

/// One line per variable (of `only` causality if given), columns separated by tabs, with
/// a header line.
pub fn table(md: &ModelDescription, only: Option<Causality>) -> String {
    let mut out = String::from("name\tcausality\tvariability\ttype\tstart\tunit\tdescription\n");
    for v in &md.model_variables.variables {
        let causality = v.causality_or_default();
        if only.is_some_and(|c| c != causality) {
            continue;
        }
        let start = match v.start() {
            Some(StartValue::Real(x)) => x.to_string(),
            Some(StartValue::Integer(x) | StartValue::Enumeration(x)) => x.to_string(),
            Some(StartValue::Boolean(x)) => x.to_string(),
            Some(StartValue::String(x)) => format!("{x:?}"),
            None => String::new(),
        };
        let unit = v
            .real
            .as_ref()
            .and_then(|r| r.unit.clone())
            .unwrap_or_default();
        let kind = v
            .kind()
            .map_or_else(|| "?".to_owned(), |k| format!("{k:?}"));
        let _ = writeln!(
            out,
            "{}\t{}\t{}\t{kind}\t{start}\t{unit}\t{}",
            v.name,
            causality.name(),
            v.variability_or_default().name(),
            v.description.as_deref().unwrap_or("")
        );
    }
    out
}
