//! What each FMU's library must export, shared by the system tests that list exports
//! (`nm -D` of the ELF libraries, `objdump -p` of the Windows DLL).
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::Command;
use system_tests::{workspace_root, Fmi, FmuCrate, FMI2_CS_FUNCTIONS, FMI2_ME_FUNCTIONS};

fn fmi2_function_names() -> BTreeSet<String> {
    FMI2_CS_FUNCTIONS.iter().map(|s| s.to_string()).collect()
}

/// What the metadata promises: the 34 Co-Simulation functions when FMI 2.0 is shipped, plus
/// the 10 of Model Exchange when it offers ME, plus every function of the official FMI 3.0
/// header when FMI 3.0 is shipped (the FMI 3.0 export has no optional part).
pub fn expected_exports(fmu: &FmuCrate) -> BTreeSet<String> {
    let mut names = BTreeSet::new();
    if fmu.ships(Fmi::V2) {
        names.extend(fmi2_function_names());
    }
    if fmu.ships_model_exchange(Fmi::V2) {
        names.extend(FMI2_ME_FUNCTIONS.iter().map(|s| s.to_string()));
    }
    if fmu.ships(Fmi::V3) {
        names.extend(fmi3_function_names());
    }
    names
}

/// The functions `fmi3Functions.h` declares (`FMI3_Export fmi3XxxTYPE fmi3Xxx;`).
fn fmi3_function_names() -> BTreeSet<String> {
    let header = official_headers("fmi-standard3").join("fmi3Functions.h");
    let text = std::fs::read_to_string(&header).unwrap();
    let names: BTreeSet<String> = text
        .lines()
        .filter_map(|line| line.trim().strip_prefix("FMI3_Export "))
        .filter_map(|rest| rest.split_whitespace().nth(1))
        .map(|name| name.trim_end_matches(';').to_owned())
        .collect();
    assert_eq!(names.len(), 75, "functions of {}", header.display());
    names
}

/// `<folder>/headers` of the fmi-sys crate in the cargo registry.
pub fn official_headers(folder: &str) -> PathBuf {
    let output = Command::new(env!("CARGO"))
        .current_dir(workspace_root())
        .args(["metadata", "--format-version", "1"])
        .output()
        .expect("cannot run cargo metadata");
    assert!(output.status.success(), "cargo metadata failed");
    let metadata: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
    let manifest = metadata["packages"]
        .as_array()
        .unwrap()
        .iter()
        .find(|p| p["name"] == "fmi-sys")
        .and_then(|p| p["manifest_path"].as_str())
        .expect("fmi-sys is not in the dependency graph");
    let headers = Path::new(manifest)
        .parent()
        .unwrap()
        .join(folder)
        .join("headers");
    assert!(headers.is_dir(), "no {}", headers.display());
    headers
}

/// The names `nm -D --defined-only` lists for a library (`nm`: the host's, or a cross
/// binutils' for a foreign ELF).
pub fn dynamic_symbols(nm: &str, library: &Path) -> BTreeSet<String> {
    let output = Command::new(nm)
        .args(["-D", "--defined-only"])
        .arg(library)
        .output()
        .unwrap_or_else(|e| panic!("cannot run {nm} (binutils): {e}"));
    assert!(
        output.status.success(),
        "{nm} failed on {}",
        library.display()
    );
    // Lines read "<address> <type> <name>"; the name is the last field.
    String::from_utf8_lossy(&output.stdout)
        .lines()
        .filter_map(|line| line.split_whitespace().last())
        .map(str::to_owned)
        .collect()
}
