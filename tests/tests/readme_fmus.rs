//! The README's statements about the FMUs are the metadata's: its table of FMUs, versions and
//! interfaces says for each crate what its `[package.metadata.fmu]` ships, lists every lander
//! FMU, and the count in the opening paragraph is the number of lander FMUs.
use system_tests::{fmu_crates, workspace_root, Fmi, FmuCrate};

/// What the table's cell for `version` says of `fmu`: "CS", "CS, ME" (every shipped version
/// is Co-Simulation) or "" (not shipped).
fn cell(fmu: &FmuCrate, version: Fmi) -> &'static str {
    match (fmu.ships(version), fmu.ships_model_exchange(version)) {
        (false, _) => "",
        (true, false) => "CS",
        (true, true) => "CS, ME",
    }
}

/// The README's FMU table: (model identifier, crate, FMI 2.0 cell, FMI 3.0 cell) per row.
fn table(readme: &str) -> Vec<(String, String, String, String)> {
    let mut rows = Vec::new();
    let mut inside = false;
    for line in readme.lines() {
        if line.starts_with("| FMU (crate) | FMI 2.0 | FMI 3.0 |") {
            inside = true;
            continue;
        }
        if !inside || line.starts_with("|---") {
            continue;
        }
        if !line.starts_with('|') {
            break;
        }
        let cells: Vec<&str> = line.trim_matches('|').split('|').map(str::trim).collect();
        let (name, rest) = cells[0].split_once(" (`").expect("Name (`crate`...)");
        let krate = rest.split('`').next().unwrap();
        rows.push((
            name.to_owned(),
            krate.to_owned(),
            cells[1].to_owned(),
            cells[2].to_owned(),
        ));
    }
    rows
}

const NUMBERS: [&str; 10] = [
    "zero", "one", "two", "three", "four", "five", "six", "seven", "eight", "nine",
];

#[test]
fn the_readme_table_of_fmus_is_the_metadata() {
    let readme = std::fs::read_to_string(workspace_root().join("README.md")).unwrap();
    let rows = table(&readme);
    assert!(!rows.is_empty(), "the README has no FMU table");
    let fmus = fmu_crates();
    for (name, krate, fmi2, fmi3) in &rows {
        let fmu = fmus
            .iter()
            .find(|f| &f.model_identifier == name)
            .unwrap_or_else(|| panic!("the README lists {name}, which no crate declares"));
        assert_eq!(
            &fmu.dir.file_name().unwrap().to_string_lossy(),
            krate,
            "{name}"
        );
        assert_eq!(fmi2, cell(fmu, Fmi::V2), "{name}, FMI 2.0");
        assert_eq!(fmi3, cell(fmu, Fmi::V3), "{name}, FMI 3.0");
    }
    let landers: Vec<&str> = fmus
        .iter()
        .map(|f| f.model_identifier.as_str())
        .filter(|id| id.starts_with("Lander"))
        .collect();
    for lander in &landers {
        assert!(
            rows.iter().any(|(name, ..)| name == lander),
            "the README's table lacks {lander}"
        );
    }
    let count = NUMBERS[landers.len()];
    assert!(
        readme.contains(&format!("Co-Simulation for all {count}")),
        "the README's opening should say Co-Simulation for all {count} ({landers:?})"
    );
}

/// What a crate description must say of the versions and interfaces `fmu` ships.
fn promised(fmu: &FmuCrate) -> Vec<&'static str> {
    let mut words = Vec::new();
    match (fmu.ships(Fmi::V2), fmu.ships(Fmi::V3)) {
        (true, true) => words.push("FMI 2.0 and 3.0"),
        (true, false) => words.push("FMI 2.0"),
        (false, true) => words.push("FMI 3.0"),
        (false, false) => {}
    }
    words.push("Co-Simulation");
    if fmu.ships_model_exchange(Fmi::V2) || fmu.ships_model_exchange(Fmi::V3) {
        words.push("Model Exchange");
    }
    words
}

#[test]
fn each_fmu_crate_description_states_what_it_ships() {
    let root = workspace_root();
    for fmu in fmu_crates() {
        let manifest: toml::Table = std::fs::read_to_string(root.join(&fmu.dir).join("Cargo.toml"))
            .unwrap()
            .parse()
            .unwrap();
        let description = manifest["package"]["description"].as_str().unwrap_or("");
        for words in promised(&fmu) {
            assert!(
                description.contains(words),
                "{}'s description should say {words:?}: {description:?}",
                fmu.package
            );
        }
    }
}
