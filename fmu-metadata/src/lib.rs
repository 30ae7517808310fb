//! The one place that says which FMU ships which FMI version and interface: the
//! `[package.metadata.fmu]` table of each FMU crate's Cargo.toml,
//!
//! ```toml
//! [package.metadata.fmu]
//! model-identifier = "LanderPlant"
//! fmi2 = ["co-simulation", "model-exchange"]
//! fmi3 = ["co-simulation", "model-exchange"]
//! ```
//!
//! A version left out is not shipped. `cargo xtask fmus` packages exactly what the tables
//! list and the system tests check each packaged FMU against them (exported symbols,
//! the interfaces of its model description, the export macros of its `src/lib.rs`).
//!
//! `awaiting-export = ["fmi3"]` marks a version the crate promises but whose export macro
//! is not on this branch yet: it is neither packaged nor expected until the macro lands,
//! and then the marker must go (the consistency test fails while both are there).
#![deny(unsafe_code)]

use serde::Deserialize;
use std::collections::BTreeMap;
use std::fmt;
use std::path::{Path, PathBuf};

/// An FMI version an FMU crate can ship.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Deserialize)]
pub enum Fmi {
    #[serde(rename = "fmi2")]
    V2,
    #[serde(rename = "fmi3")]
    V3,
}

impl Fmi {
    pub const ALL: [Fmi; 2] = [Fmi::V2, Fmi::V3];

    /// The key of the metadata table (`fmi2`, `fmi3`).
    pub fn key(self) -> &'static str {
        match self {
            Fmi::V2 => "fmi2",
            Fmi::V3 => "fmi3",
        }
    }

    /// The export macro of this version (`export_fmi2!`, `export_fmi3!`).
    pub fn export_macro(self) -> &'static str {
        match self {
            Fmi::V2 => "export_fmi2!",
            Fmi::V3 => "export_fmi3!",
        }
    }
}

impl fmt::Display for Fmi {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Fmi::V2 => "FMI 2.0",
            Fmi::V3 => "FMI 3.0",
        })
    }
}

/// An FMI interface. The export macros always export Co-Simulation; `model_exchange` adds
/// Model Exchange, so an offered version lists `co-simulation`, with or without ME.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Interface {
    CoSimulation,
    ModelExchange,
}

/// What one version of an FMU offers.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Offer {
    pub model_exchange: bool,
    /// Promised, but the export is not on this branch yet (`awaiting-export`).
    pub awaiting_export: bool,
}

/// One FMU crate and what its metadata promises.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FmuCrate {
    /// Cargo package name (`fmu-plant`).
    pub package: String,
    /// The crate's folder, relative to the workspace root.
    pub dir: PathBuf,
    /// `[lib] name`, so the cdylib is `lib<lib_name>.so`.
    pub lib_name: String,
    pub model_identifier: String,
    pub offers: BTreeMap<Fmi, Offer>,
}

impl FmuCrate {
    /// What `version` offers, `None` when the version is not promised at all.
    pub fn offer(&self, version: Fmi) -> Option<&Offer> {
        self.offers.get(&version)
    }

    /// True when `version` is promised and exported on this branch: it is packaged.
    pub fn ships(&self, version: Fmi) -> bool {
        self.offer(version).is_some_and(|o| !o.awaiting_export)
    }

    /// True when the shipped `version` includes Model Exchange.
    pub fn ships_model_exchange(&self, version: Fmi) -> bool {
        self.ships(version) && self.offer(version).is_some_and(|o| o.model_exchange)
    }
}

#[derive(Debug)]
pub struct Error(String);

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for Error {}

fn error(message: impl Into<String>) -> Error {
    Error(message.into())
}

#[derive(Deserialize)]
#[serde(rename_all = "kebab-case", deny_unknown_fields)]
struct Table {
    model_identifier: String,
    fmi2: Option<Vec<Interface>>,
    fmi3: Option<Vec<Interface>>,
    #[serde(default)]
    awaiting_export: Vec<Fmi>,
}

#[derive(Deserialize)]
struct Manifest {
    package: Option<Package>,
    lib: Option<Lib>,
}

#[derive(Deserialize)]
struct Package {
    name: String,
    metadata: Option<Metadata>,
}

#[derive(Deserialize)]
struct Metadata {
    fmu: Option<toml::Value>,
}

#[derive(Deserialize)]
struct Lib {
    name: Option<String>,
}

#[derive(Deserialize)]
struct WorkspaceManifest {
    workspace: Workspace,
}

#[derive(Deserialize)]
struct Workspace {
    members: Vec<String>,
}

fn read(path: &Path) -> Result<String, Error> {
    std::fs::read_to_string(path).map_err(|e| error(format!("cannot read {}: {e}", path.display())))
}

/// The FMU crates of the workspace `dir` belongs to (`dir` or its nearest ancestor whose
/// Cargo.toml has a `[workspace]`): the one list of FMUs every test, tool and fuzz target
/// derives its own from, e.g. `fmu_metadata::fmus_around(env!("CARGO_MANIFEST_DIR"))`.
pub fn fmus_around(dir: impl AsRef<Path>) -> Result<Vec<FmuCrate>, Error> {
    workspace_fmus(&workspace_root_of(dir.as_ref())?)
}

/// `dir` or its nearest ancestor whose Cargo.toml declares a `[workspace]`.
pub fn workspace_root_of(dir: &Path) -> Result<PathBuf, Error> {
    dir.ancestors()
        .find(|d| {
            std::fs::read_to_string(d.join("Cargo.toml"))
                .ok()
                .and_then(|text| toml::from_str::<toml::Table>(&text).ok())
                .is_some_and(|t| t.contains_key("workspace"))
        })
        .map(Path::to_path_buf)
        .ok_or_else(|| error(format!("no workspace Cargo.toml above {}", dir.display())))
}

/// The member folders of `root/Cargo.toml`, relative to `root`, in the order of
/// `workspace.members`; a member ending in `*` (`fmu-*`) stands for every folder with a
/// Cargo.toml whose path starts with what precedes it, in name order, as cargo reads it.
pub fn workspace_members(root: &Path) -> Result<Vec<PathBuf>, Error> {
    let path = root.join("Cargo.toml");
    let workspace: WorkspaceManifest =
        toml::from_str(&read(&path)?).map_err(|e| error(format!("{}: {e}", path.display())))?;
    let mut members: Vec<PathBuf> = Vec::new();
    for member in workspace.workspace.members {
        let found = match member.strip_suffix('*') {
            None => vec![PathBuf::from(&member)],
            Some(prefix) => {
                let (parent, start) = match prefix.rsplit_once('/') {
                    Some((parent, start)) => (PathBuf::from(parent), start.to_string()),
                    None => (PathBuf::new(), prefix.to_string()),
                };
                if start.contains(['*', '?', '[']) {
                    return Err(error(format!("{member}: only a trailing * is understood")));
                }
                let entries = std::fs::read_dir(root.join(&parent))
                    .map_err(|e| error(format!("{member}: {e}")))?;
                let mut dirs: Vec<PathBuf> = entries
                    .filter_map(Result::ok)
                    .filter(|e| e.file_name().to_string_lossy().starts_with(&start))
                    .filter(|e| e.path().join("Cargo.toml").is_file())
                    .map(|e| parent.join(e.file_name()))
                    .collect();
                dirs.sort();
                dirs
            }
        };
        for dir in found {
            if !members.contains(&dir) {
                members.push(dir);
            }
        }
    }
    Ok(members)
}

/// Every workspace member of `root/Cargo.toml` with a `[package.metadata.fmu]` table, in
/// the order of `workspace.members`.
pub fn workspace_fmus(root: &Path) -> Result<Vec<FmuCrate>, Error> {
    let mut fmus = Vec::new();
    for member in workspace_members(root)? {
        let manifest = root.join(&member).join("Cargo.toml");
        if let Some(fmu) = parse_manifest(&member, &read(&manifest)?)
            .map_err(|e| error(format!("{}: {e}", manifest.display())))?
        {
            fmus.push(fmu);
        }
    }
    let mut identifiers: Vec<&str> = fmus.iter().map(|f| f.model_identifier.as_str()).collect();
    identifiers.sort_unstable();
    if let Some(pair) = identifiers.windows(2).find(|p| p[0] == p[1]) {
        return Err(error(format!(
            "two FMU crates declare model-identifier {:?}",
            pair[0]
        )));
    }
    Ok(fmus)
}

/// The FMU a crate's Cargo.toml describes (`dir` is the crate's folder), `None` when it
/// has no `[package.metadata.fmu]` table.
pub fn parse_manifest(dir: &Path, cargo_toml: &str) -> Result<Option<FmuCrate>, Error> {
    let manifest: Manifest = toml::from_str(cargo_toml).map_err(|e| error(e.to_string()))?;
    let Some(package) = manifest.package else {
        return Ok(None);
    };
    let Some(value) = package.metadata.and_then(|m| m.fmu) else {
        return Ok(None);
    };
    let table: Table = value
        .try_into()
        .map_err(|e| error(format!("[package.metadata.fmu]: {e}")))?;
    if !is_c_identifier(&table.model_identifier) {
        return Err(error(format!(
            "model-identifier {:?} is not a C identifier",
            table.model_identifier
        )));
    }
    let mut offers = BTreeMap::new();
    for (version, interfaces) in [(Fmi::V2, table.fmi2), (Fmi::V3, table.fmi3)] {
        let Some(interfaces) = interfaces else {
            continue;
        };
        if !interfaces.contains(&Interface::CoSimulation) {
            return Err(error(format!(
                "{} = {interfaces:?}: the export macros always export Co-Simulation, \
                 so an offered version lists \"co-simulation\"",
                version.key()
            )));
        }
        let mut unique = interfaces.clone();
        unique.sort();
        unique.dedup();
        if unique.len() != interfaces.len() {
            return Err(error(format!("{} lists an interface twice", version.key())));
        }
        offers.insert(
            version,
            Offer {
                model_exchange: interfaces.contains(&Interface::ModelExchange),
                awaiting_export: table.awaiting_export.contains(&version),
            },
        );
    }
    if offers.is_empty() {
        return Err(error("[package.metadata.fmu] offers neither fmi2 nor fmi3"));
    }
    if let Some(v) = table
        .awaiting_export
        .iter()
        .find(|v| !offers.contains_key(v))
    {
        return Err(error(format!(
            "awaiting-export names {}, which the table does not offer",
            v.key()
        )));
    }
    let lib_name = manifest
        .lib
        .and_then(|l| l.name)
        .unwrap_or_else(|| package.name.replace('-', "_"));
    Ok(Some(FmuCrate {
        package: package.name,
        dir: dir.to_path_buf(),
        lib_name,
        model_identifier: table.model_identifier,
        offers,
    }))
}

/// What a crate's `src/lib.rs` exports, read from its `export_fmi2!`/`export_fmi3!` lines:
/// for each version exported, whether `model_exchange` is passed.
pub fn exports_in_source(lib_rs: &str) -> Result<BTreeMap<Fmi, bool>, Error> {
    let mut exports = BTreeMap::new();
    for line in lib_rs.lines().map(str::trim) {
        if line.starts_with("//") {
            continue;
        }
        for version in Fmi::ALL {
            let Some(at) = line.find(version.export_macro()) else {
                continue;
            };
            let args = line[at + version.export_macro().len()..]
                .trim_start()
                .strip_prefix('(')
                .and_then(|rest| rest.split(')').next())
                .ok_or_else(|| error(format!("cannot read the arguments of `{line}`")))?;
            let model_exchange = args
                .split(',')
                .skip(1)
                .any(|a| a.trim() == "model_exchange");
            if exports.insert(version, model_exchange).is_some() {
                return Err(error(format!(
                    "{} is invoked twice",
                    version.export_macro()
                )));
            }
        }
    }
    Ok(exports)
}

/// A problem for each way `fmu`'s metadata and the exports of its `src/lib.rs` disagree.
pub fn check_exports(fmu: &FmuCrate, exports: &BTreeMap<Fmi, bool>) -> Vec<String> {
    let mut problems = Vec::new();
    let id = &fmu.model_identifier;
    for version in Fmi::ALL {
        let macro_name = version.export_macro();
        match (fmu.offer(version), exports.get(&version)) {
            (None, None) => {}
            (None, Some(_)) => problems.push(format!(
                "{id}: src/lib.rs invokes {macro_name} but the metadata offers no {version} \
                 (add `{}` to [package.metadata.fmu])",
                version.key()
            )),
            (Some(offer), None) if offer.awaiting_export => {}
            (Some(_), None) => problems.push(format!(
                "{id}: the metadata offers {version} but src/lib.rs has no {macro_name}"
            )),
            (Some(offer), Some(_)) if offer.awaiting_export => problems.push(format!(
                "{id}: src/lib.rs now invokes {macro_name}: remove \"{}\" from awaiting-export \
                 in [package.metadata.fmu]",
                version.key()
            )),
            (Some(offer), Some(&me)) if offer.model_exchange != me => problems.push(format!(
                "{id}: the metadata says {version} Model Exchange is {}, but src/lib.rs \
                 invokes {macro_name} {} `model_exchange`",
                if offer.model_exchange {
                    "offered"
                } else {
                    "not offered"
                },
                if me { "with" } else { "without" }
            )),
            (Some(_), Some(_)) => {}
        }
    }
    problems
}

fn is_c_identifier(id: &str) -> bool {
    !id.is_empty()
        && id.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
        && !id.starts_with(|c: char| c.is_ascii_digit())
}

#[cfg(test)]
mod tests {
    use super::*;

    const PLANT: &str = r#"
[package]
name = "fmu-plant"
[lib]
name = "fmu_plant"
[package.metadata.fmu]
model-identifier = "LanderPlant"
fmi2 = ["co-simulation", "model-exchange"]
fmi3 = ["co-simulation"]
"#;

    fn plant() -> FmuCrate {
        parse_manifest(Path::new("fmu-plant"), PLANT)
            .unwrap()
            .unwrap()
    }

    #[test]
    fn a_table_reads_as_the_versions_and_interfaces_it_lists() {
        let fmu = plant();
        assert_eq!(fmu.package, "fmu-plant");
        assert_eq!(fmu.lib_name, "fmu_plant");
        assert_eq!(fmu.model_identifier, "LanderPlant");
        assert!(fmu.ships_model_exchange(Fmi::V2));
        assert!(fmu.ships(Fmi::V3) && !fmu.ships_model_exchange(Fmi::V3));
    }

    #[test]
    fn a_trailing_star_in_the_members_stands_for_each_crate_folder_it_matches() {
        let root = std::env::temp_dir().join(format!("fmu-metadata-{}", std::process::id()));
        let write = |path: &str, text: &str| {
            let path = root.join(path);
            std::fs::create_dir_all(path.parent().unwrap()).unwrap();
            std::fs::write(path, text).unwrap();
        };
        write(
            "Cargo.toml",
            "[workspace]\nmembers = [\"tools\", \"fmu-*\"]\n",
        );
        write("tools/Cargo.toml", "[package]\nname = \"tools\"\n");
        write("fmu-plant/Cargo.toml", PLANT);
        write(
            "fmu-b/Cargo.toml",
            &PLANT
                .replace("LanderPlant", "B")
                .replace("fmu-plant", "fmu-b"),
        );
        write("fmu-empty/README.md", "no crate here");
        write("other/Cargo.toml", "[package]\nname = \"other\"\n");
        let members = workspace_members(&root).unwrap();
        let fmus = fmus_around(root.join("tools")).unwrap();
        std::fs::remove_dir_all(&root).unwrap();
        assert_eq!(
            members,
            ["tools", "fmu-b", "fmu-plant"].map(PathBuf::from).to_vec()
        );
        let ids: Vec<&str> = fmus.iter().map(|f| f.model_identifier.as_str()).collect();
        assert_eq!(ids, ["B", "LanderPlant"]);
    }

    #[test]
    fn a_crate_without_the_table_is_no_fmu() {
        let plain = "[package]\nname = \"x\"\n";
        assert_eq!(parse_manifest(Path::new("x"), plain).unwrap(), None);
    }

    #[test]
    fn bad_tables_are_refused() {
        for (from, to) in [
            ("\"LanderPlant\"", "\"1x\""),
            ("fmi3 = [\"co-simulation\"]", "fmi3 = [\"model-exchange\"]"),
            ("fmi3 = [\"co-simulation\"]", "fmi3 = [\"co-sim\"]"),
            ("fmi3 = [\"co-simulation\"]", "fmi4 = [\"co-simulation\"]"),
            ("fmi3 = [\"co-simulation\"]", "awaiting-export = [\"fmi3\"]"),
        ] {
            let bad = PLANT.replace(from, to);
            assert!(parse_manifest(Path::new("p"), &bad).is_err(), "{to}");
        }
    }

    #[test]
    fn awaiting_export_is_promised_but_not_shipped() {
        let awaiting = format!("{PLANT}awaiting-export = [\"fmi3\"]\n");
        let fmu = parse_manifest(Path::new("p"), &awaiting).unwrap().unwrap();
        assert!(fmu.offer(Fmi::V3).is_some() && !fmu.ships(Fmi::V3));
        let only_fmi2 = exports_in_source("fmi2_export::export_fmi2!(crate::P, model_exchange);");
        assert_eq!(
            check_exports(&fmu, &only_fmi2.unwrap()),
            Vec::<String>::new()
        );
        let both = exports_in_source(
            "fmi2_export::export_fmi2!(crate::P, model_exchange);\n\
             fmi3_export::export_fmi3!(crate::P);",
        );
        let problems = check_exports(&fmu, &both.unwrap());
        assert!(
            problems[0].contains("remove \"fmi3\" from awaiting-export"),
            "{problems:?}"
        );
    }

    #[test]
    fn source_exports_are_compared_with_the_metadata() {
        let fmu = plant();
        let agree = "// export_fmi3!(crate::Commented, model_exchange);\n\
                     fmi2_export::export_fmi2!(crate::LanderPlant, model_exchange);\n\
                     fmi3_export::export_fmi3!(crate::LanderPlant);\n";
        let exports = exports_in_source(agree).unwrap();
        assert_eq!(exports, BTreeMap::from([(Fmi::V2, true), (Fmi::V3, false)]));
        assert!(check_exports(&fmu, &exports).is_empty());
        let no_me = agree.replace(", model_exchange);\nfmi3", ");\nfmi3");
        assert_eq!(
            check_exports(&fmu, &exports_in_source(&no_me).unwrap()).len(),
            1
        );
        let no_fmi3 = agree.replace("fmi3_export::export_fmi3!(crate::LanderPlant);", "");
        assert_eq!(
            check_exports(&fmu, &exports_in_source(&no_fmi3).unwrap()).len(),
            1
        );
    }
}
