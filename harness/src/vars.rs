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
/// a header line; `declared[i]` is variable `i` as its file declares it (type, and a start
/// value the FMI 2.0 view cannot hold exactly), the view's own where absent.
pub fn table(
    md: &ModelDescription,
    declared: &[fmi_import::Declared],
    only: Option<Causality>,
) -> String {
    let mut out = String::from("name\tcausality\tvariability\ttype\tstart\tunit\tdescription\n");
    for (i, v) in md.model_variables.variables.iter().enumerate() {
        let causality = v.causality_or_default();
        if only.is_some_and(|c| c != causality) {
            continue;
        }
        let own = declared
            .get(i)
            .filter(|d| v.start().is_none() || d.type_name == "Float32")
            .and_then(|d| d.start.clone());
        let start = match v.start() {
            // The file's own text where the view has none (an Int64 beyond 32 bits) or
            // holds the f64 of the Float32 it stands for.
            _ if own.is_some() => own.unwrap_or_default(),
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
        let kind = declared
            .get(i)
            .map(|d| d.type_name.clone())
            .unwrap_or_else(|| {
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
