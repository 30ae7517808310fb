//! `harness vars FMU`: an FMU's variables as a user wires them (name, causality,
//! variability, type, start, unit, description), optionally of one causality. The type is
//! the one the file declares: an FMI 3.0 `UInt64` or `Binary` is listed as such, not as the
//! FMI 2.0 counterpart its scalar view gives it.
use model_description::{Causality, ModelDescription, StartValue};
use std::fmt::Write;

/// The causality a user asks for, as the standard spells it.
pub fn parse_causality(text: &str) -> Option<Causality> {
    Causality::from_name(text)
}

/// One line per variable (of `only` causality if given), columns separated by tabs, with
/// a header line; `types[i]` is the type of variable `i` as its file declares it (the FMI
/// 2.0 type element where absent).
pub fn table(md: &ModelDescription, types: &[String], only: Option<Causality>) -> String {
    let mut out = String::from("name\tcausality\tvariability\ttype\tstart\tunit\tdescription\n");
    for (i, v) in md.model_variables.variables.iter().enumerate() {
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
        let kind = types.get(i).cloned().unwrap_or_else(|| {
            v.kind()
                .map_or_else(|| "?".to_owned(), |k| format!("{k:?}"))
        });
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
