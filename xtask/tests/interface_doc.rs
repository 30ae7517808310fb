//! docs/interface.md quotes the FMUs' defaults; each FMU carries the page in its
//! documentation. Every default the page's tables quote must be the start value the FMU's
//! model description declares, so the page cannot go stale.
use model_description::{ModelDescription, StartValue};
use std::path::Path;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap()
}

fn description(crate_dir: &str) -> ModelDescription {
    let xml = std::fs::read_to_string(root().join(crate_dir).join("modelDescription.xml")).unwrap();
    ModelDescription::from_xml(&xml).unwrap()
}

/// `r0_nue[1..3]` -> ("r0_nue", 3); `m0` -> ("m0", 0).
fn name_and_length(cell: &str) -> (String, usize) {
    let name = cell.trim().trim_matches('`');
    match name.split_once('[') {
        Some((base, range)) => {
            let last = range.trim_end_matches(']').split("..").last().unwrap();
            (base.to_owned(), last.parse().unwrap())
        }
        None => (name.to_owned(), 0),
    }
}

/// The numbers of a default cell: `0, 800, 0 m` -> [0, 800, 0]; `720 N` -> [720]; `1 (true)`
/// -> [1].
fn numbers(cell: &str) -> Vec<f64> {
    cell.split(',')
        .map(|piece| {
            let first = piece.split_whitespace().next().unwrap_or("");
            first
                .parse()
                .unwrap_or_else(|_| panic!("no number in {piece:?} of {cell:?}"))
        })
        .collect()
}

fn start(md: &ModelDescription, name: &str) -> f64 {
    let v = md
        .variable(name)
        .unwrap_or_else(|| panic!("{name} is not a variable of {}", md.model_name));
    match v.start() {
        Some(StartValue::Real(x)) => x,
        Some(StartValue::Integer(x) | StartValue::Enumeration(x)) => f64::from(x),
        // A Boolean's cell quotes it as 1 (true) or 0 (false).
        Some(StartValue::Boolean(b)) => f64::from(u8::from(b)),
        other => panic!("{name}: start {other:?}"),
    }
}

/// Checks one table row: the names of `names_cell` (one or several, comma-separated) against
/// the values of `default_cell` (one per element, or one for all elements of a vector).
fn check(md: &ModelDescription, names_cell: &str, default_cell: &str) -> usize {
    let names: Vec<(String, usize)> = names_cell.split(',').map(name_and_length).collect();
    let values = numbers(default_cell);
    let mut k = 0;
    let mut checked = 0;
    for (base, length) in names {
        let elements: Vec<String> = if length == 0 {
            vec![base.clone()]
        } else {
            (1..=length).map(|i| format!("{base}[{i}]")).collect()
        };
        let broadcast = values.len() == 1 && elements.len() > 1;
        for element in elements {
            let expected = if broadcast { values[0] } else { values[k] };
            k += usize::from(!broadcast);
            assert_eq!(
                start(md, &element),
                expected,
                "docs/interface.md quotes {element} = {expected}, the FMU declares otherwise"
            );
            checked += 1;
        }
    }
    checked
}

#[test]
fn every_default_the_interface_page_quotes_is_the_declared_start_value() {
    let page = std::fs::read_to_string(root().join("docs/interface.md")).unwrap();
    let gnc = description("fmu-gnc");
    let plant = description("fmu-plant");
    let mut checked = 0;
    let mut in_gnc_table = false;
    for line in page.lines() {
        let cells: Vec<&str> = line.trim().trim_matches('|').split('|').collect();
        if !line.starts_with('|') || cells.iter().all(|c| c.trim().starts_with("--")) {
            in_gnc_table &= line.starts_with('|');
            continue;
        }
        match cells.as_slice() {
            [fmu, name, default, _] if fmu.trim() == "LanderGnc" => {
                checked += check(&gnc, name, default)
            }
            [fmu, name, default, _] if fmu.trim() == "LanderPlant" => {
                checked += check(&plant, name, default)
            }
            [header, ..] if header.trim() == "LanderGnc parameter" => in_gnc_table = true,
            [name, default, _] if in_gnc_table => checked += check(&gnc, name, default),
            _ => {}
        }
    }
    // The tables quote 3 + 5 rows of single defaults and vectors, and 4 GNC rows to match.
    assert!(
        checked >= 20,
        "only {checked} values found in the page's tables"
    );
}
