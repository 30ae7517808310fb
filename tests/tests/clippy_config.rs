//! One `clippy.toml`, at the workspace root, forbids std's transcendental functions in model
//! code (docs/floating-point.md). clippy reads the file nearest to the crate, so an FMU
//! crate, or a crate compiled into every FMU, with a `clippy.toml` of its own would let a
//! platform's C library back into its FMU unnoticed. Crates that never go into an FMU may
//! opt out with one of their own.
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use system_tests::{fmu_crates, workspace_root};

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn toml(path: &Path) -> toml::Value {
    toml::from_str(&read(path)).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The folder of every workspace crate an FMU crate depends on (`[dependencies]`, through
/// `workspace = true` or a path), transitively: the code that ends up in an FMU.
fn crates_in_fmus() -> BTreeSet<PathBuf> {
    let root = workspace_root();
    let workspace = toml(&root.join("Cargo.toml"));
    let path_of = |name: &str| -> Option<PathBuf> {
        workspace["workspace"]["dependencies"]
            .get(name)?
            .get("path")?
            .as_str()
            .map(PathBuf::from)
    };
    let mut seen = BTreeSet::new();
    let mut todo: Vec<PathBuf> = fmu_crates().into_iter().map(|f| f.dir).collect();
    while let Some(dir) = todo.pop() {
        if !seen.insert(dir.clone()) {
            continue;
        }
        let manifest = toml(&root.join(&dir).join("Cargo.toml"));
        let Some(deps) = manifest.get("dependencies").and_then(|d| d.as_table()) else {
            continue;
        };
        for (name, spec) in deps {
            let path = match spec.get("path").and_then(|p| p.as_str()) {
                Some(p) => Some(dir.join(p)),
                None => path_of(name),
            };
            if let Some(path) = path {
                let normal: PathBuf = path.components().fold(PathBuf::new(), |mut acc, c| {
                    match c {
                        std::path::Component::ParentDir => {
                            acc.pop();
                        }
                        other => acc.push(other),
                    }
                    acc
                });
                todo.push(normal);
            }
        }
    }
    seen
}

#[test]
fn the_root_clippy_toml_forbids_std_transcendental_functions() {
    let config = read(&workspace_root().join("clippy.toml"));
    for method in [
        "f64::sin_cos",
        "f64::atan2",
        "f64::powi",
        "nalgebra::Unit::from_axis_angle",
    ] {
        assert!(
            config.contains(&format!("\"{method}\"")),
            "clippy.toml does not forbid {method}"
        );
    }
}

#[test]
fn no_crate_that_goes_into_an_fmu_has_a_clippy_toml_of_its_own() {
    let in_fmus = crates_in_fmus();
    assert!(
        in_fmus.len() > fmu_crates().len(),
        "the FMU crates' own dependencies were not found: {in_fmus:?}"
    );
    let shadowing: Vec<String> = in_fmus
        .iter()
        .filter(|dir| {
            ["clippy.toml", ".clippy.toml"]
                .iter()
                .any(|f| workspace_root().join(dir).join(f).exists())
        })
        .map(|dir| dir.display().to_string())
        .collect();
    assert!(
        shadowing.is_empty(),
        "a clippy.toml of their own hides the workspace's from {shadowing:?}"
    );
}
