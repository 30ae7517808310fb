//! `cargo xtask new-fmu NAME`: a new FMU crate, `fmu-<name>/`, that packages, validates and
//! passes the conformance suite as written: its `[package.metadata.fmu]`, a tiny model with
//! its declaration table, the two binaries `cargo xtask fmus` prints the model descriptions
//! with, the one-line conformance suite and a README; in the workspace, also its generated
//! fuzz crate (`cargo xtask fuzz-crates`). The workspace takes it in through its
//! `fmu-*` members; every list of FMUs (packaging, system tests, robustness, fuzz crates)
//! reads the metadata, so nothing outside the new folder changes.
use crate::workspace::Workspace;
use anyhow::{bail, Context, Result};
use std::path::{Path, PathBuf};

/// `LanderRadar` -> `lander-radar`.
fn kebab(name: &str) -> String {
    let mut out = String::new();
    for (i, c) in name.chars().enumerate() {
        if c.is_ascii_uppercase() {
            if i > 0 && !out.ends_with('-') {
                out.push('-');
            }
            out.push(c.to_ascii_lowercase());
        } else if c == '_' {
            out.push('-');
        } else {
            out.push(c);
        }
    }
    out
}

/// The files of the crate for model identifier `name`, relative to the crate's folder.
pub fn files(name: &str) -> Result<(String, Vec<(PathBuf, String)>)> {
    let valid = name.starts_with(|c: char| c.is_ascii_uppercase())
        && name.chars().all(|c| c.is_ascii_alphanumeric());
    if !valid {
        bail!(
            "{name:?}: the model identifier names the model's Rust type and the FMU's \
             library, so it must be an UpperCamelCase C identifier (e.g. LanderRadar)"
        );
    }
    let package = format!("fmu-{}", kebab(name));
    let lib = package.replace('-', "_");
    let cargo_toml = format!(
        r#"[package]
name = "{package}"
description = "{name}: a first-order lag as an FMI 2.0 and 3.0 Co-Simulation FMU"
version.workspace = true
edition.workspace = true
license.workspace = true

[lib]
name = "{lib}"
crate-type = ["cdylib", "rlib"]

# What this crate ships: `cargo xtask fmus` packages it and every test that lists the FMUs
# finds it here (fmu-metadata/src/lib.rs).
[package.metadata.fmu]
model-identifier = "{name}"
fmi2 = ["co-simulation"]
fmi3 = ["co-simulation"]

[dependencies]
fmi-model.workspace = true
fmi2-export.workspace = true
fmi3-export.workspace = true
serde.workspace = true

[dev-dependencies]
fmi-testkit.workspace = true

[lints]
workspace = true

# Print the generated model descriptions (xtask packages from them); no unit tests inside.
[[bin]]
name = "{lib}_model_description"
path = "src/bin/{lib}_model_description.rs"
test = false
bench = false
doc = false

[[bin]]
name = "{lib}_model_description_fmi3"
path = "src/bin/{lib}_model_description_fmi3.rs"
test = false
bench = false
doc = false
"#
    );
    let lib_rs = format!(
        r#"//! {name}: a first-order lag, y' = (gain u - y) / tau, exported as an FMI 2.0 and 3.0
//! Co-Simulation FMU. Written by `cargo xtask new-fmu`: replace the model, keep the shape
//! (one declaration table, the model type named as the model identifier, both exports).
#![deny(unsafe_code)]

use fmi_model::{{decl, Declaration, Experiment, Log, Model, ModelError, StepEnd}};
use serde::{{Deserialize, Serialize}};

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct {name} {{
    pub gain: f64,
    pub tau_s: f64,
    pub y0: f64,
    pub u: f64,
    pub y: f64,
}}

impl Default for {name} {{
    fn default() -> Self {{
        {name} {{
            gain: 1.0,
            tau_s: 1.0,
            y0: 0.0,
            u: 0.0,
            y: 0.0,
        }}
    }}
}}

#[rustfmt::skip]
pub static DECLARATIONS: [Declaration<{name}>; 5] = [
    decl!(0, parameter y0: y0, "1", "Output at the start"),
    decl!(1, tunable gain: gain, "1", "Static gain from u to y", min = -1e6, max = 1e6),
    decl!(2, tunable tau: tau_s, "s", "Time constant", above = 0.0, max = 1e6),
    decl!(3, input u: u, "1", "Input, held over each communication step"),
    decl!(4, output y: y, "1", "Output"),
];

impl Model for {name} {{
    const MODEL_IDENTIFIER: &'static str = "{name}";
    const MODEL_NAME: &'static str = "{name}";
    const VERSION: &'static str = env!("CARGO_PKG_VERSION");
    const DESCRIPTION: &'static str = "A first-order lag";
    const DEFAULT_EXPERIMENT: Experiment = Experiment {{
        start_time: 0.0,
        stop_time: 10.0,
        step_size: 0.1,
        tolerance: None,
    }};

    fn declarations() -> &'static [Declaration<Self>] {{
        &DECLARATIONS
    }}

    fn exit_initialization(&mut self, _start_time: f64, _log: &mut Log) -> Result<(), ModelError> {{
        self.y = self.y0;
        Ok(())
    }}

    fn do_step(&mut self, _t: f64, h: f64, _log: &mut Log) -> Result<StepEnd, ModelError> {{
        // Implicit Euler: stable for any step, and no std exp, whose last bits differ
        // between platforms (the workspace clippy.toml forbids it).
        let decay = 1.0 / (1.0 + h / self.tau_s);
        self.y = self.gain * self.u + (self.y - self.gain * self.u) * decay;
        Ok(StepEnd::Complete)
    }}
}}

fmi2_export::export_fmi2!(crate::{name});
fmi3_export::export_fmi3!(crate::{name});
"#
    );
    let bin2 = format!(
        "//! Prints {name}'s FMI 2.0 modelDescription.xml (packaged by `cargo xtask fmus`).\n\
         fn main() {{\n    print!(\"{{}}\", fmi2_export::model_description_xml::<{lib}::{name}>());\n}}\n"
    );
    let bin3 = format!(
        "//! Prints {name}'s FMI 3.0 modelDescription.xml, or with `terminals-and-icons` its\n\
         //! terminalsAndIcons.xml (both packaged by `cargo xtask fmus`).\n\
         fn main() {{\n    fmi3_export::describe::<{lib}::{name}>(fmi3_export::model_description_xml::<{lib}::{name}>);\n}}\n"
    );
    let conformance = format!(
        "//! The workspace's conformance suite (fmi-testkit), derived from the declaration table and\n\
         //! [package.metadata.fmu].\n\
         fmi_testkit::conformance!({lib}, {name});\n"
    );
    let readme = format!(
        "# {package}: the {name} FMU\n\n\
         Written by `cargo xtask new-fmu {name}`. `cargo xtask fmus` packages it as\n\
         `target/fmu/{name}.fmu` (FMI 2.0) and `target/fmu/fmi3/{name}.fmu` (FMI 3.0);\n\
         `cargo test -p {package}` runs the conformance suite every FMU of the workspace passes\n\
         (`tests/conformance.rs`). The system, robustness and fuzz lists of FMUs read\n\
         `[package.metadata.fmu]` in `Cargo.toml`, so they include it already\n\
         (`cargo xtask fuzz-crates` writes its fuzz crate).\n"
    );
    let files = vec![
        (PathBuf::from("Cargo.toml"), cargo_toml),
        (PathBuf::from("src/lib.rs"), lib_rs),
        (
            PathBuf::from(format!("src/bin/{lib}_model_description.rs")),
            bin2,
        ),
        (
            PathBuf::from(format!("src/bin/{lib}_model_description_fmi3.rs")),
            bin3,
        ),
        (PathBuf::from("tests/conformance.rs"), conformance),
        (PathBuf::from("README.md"), readme),
    ];
    Ok((package, files))
}

/// Writes the crate into `ws.root/fmu-<name>` (or `into/fmu-<name>`); refuses an existing
/// folder or a model identifier another FMU crate has.
pub fn run(ws: &Workspace, name: &str, into: Option<&Path>) -> Result<PathBuf> {
    let (package, files) = files(name)?;
    let dir = into.unwrap_or(&ws.root).join(&package);
    if dir.exists() {
        bail!("{} exists already", dir.display());
    }
    let fmus = fmu_metadata::workspace_fmus(&ws.root).map_err(anyhow::Error::msg)?;
    if let Some(other) = fmus.iter().find(|f| f.model_identifier == name) {
        bail!("{} declares model-identifier {name} already", other.package);
    }
    let members = fmu_metadata::workspace_members(&ws.root).map_err(anyhow::Error::msg)?;
    write(&dir, &files)?;
    if into.is_none()
        && !fmu_metadata::workspace_members(&ws.root)
            .map_err(anyhow::Error::msg)?
            .contains(&PathBuf::from(&package))
    {
        eprintln!(
            "note: no member of the workspace Cargo.toml matches {package} ({} members): \
             add it, or a member `fmu-*`",
            members.len()
        );
    }
    println!(
        "wrote {} ({} files); next: cargo test -p {package}, cargo xtask fmus",
        dir.display(),
        files.len()
    );
    if into.is_none() {
        // Its fuzz crate is generated from the metadata just written, as every FMU's is.
        crate::fuzz_crates::run(ws, false)?;
    }
    Ok(dir)
}

fn write(dir: &Path, files: &[(PathBuf, String)]) -> Result<()> {
    for (path, text) in files {
        let full = dir.join(path);
        std::fs::create_dir_all(full.parent().expect("a file in a folder"))?;
        std::fs::write(&full, text).with_context(|| format!("write {}", full.display()))?;
    }
    Ok(())
}
