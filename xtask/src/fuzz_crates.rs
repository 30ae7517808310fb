//! `cargo xtask fuzz-crates`: one cargo-fuzz crate per FMU crate, `fuzz/<name>/`, written
//! from the FMU's `[package.metadata.fmu]`: the FMI 2.0 targets for every FMU that ships
//! FMI 2.0, the FMI 3.0 ones for every FMU that ships FMI 3.0. One crate per FMU because
//! each links one FMU's exported `fmi2*`/`fmi3*` symbols; the targets themselves are the
//! shared drivers of `fuzz/common/`. `--check` writes nothing and fails when a crate is
//! missing or differs (a system test runs it), so an FMU without fuzz targets cannot go
//! unnoticed.
//!
//! The model type is the one the crate's root exports under its model identifier, the
//! convention of every FMU crate here (and of `cargo xtask new-fmu`).
use crate::workspace::Workspace;
use anyhow::{bail, Context, Result};
use fmu_metadata::{Fmi, FmuCrate};
use std::path::PathBuf;

/// `fuzz/<name>`: the package name without its `fmu-` prefix (`fmu-gnc` -> `gnc`).
pub fn short_name(fmu: &FmuCrate) -> String {
    fmu.package
        .strip_prefix("fmu-")
        .unwrap_or(&fmu.package)
        .to_string()
}

/// The targets of one FMU: (binary name, driver module, driver function), per version.
fn targets(fmu: &FmuCrate) -> Vec<(String, &'static str, &'static str)> {
    let mut targets = Vec::new();
    for (version, prefix, driver) in [(Fmi::V2, "", "driver"), (Fmi::V3, "fmi3_", "driver3")] {
        if fmu.ships(version) {
            for function in ["restored_state", "call_sequence"] {
                targets.push((format!("{prefix}{function}"), driver, function));
            }
        }
    }
    targets
}

fn target_source(fmu: &FmuCrate, driver: &str, function: &str) -> String {
    let (what, version) = match function {
        "restored_state" => (
            "(a) A crafted FMU-state payload with a valid header and checksum, then gets and a step.",
            driver,
        ),
        _ => (
            "(b) A random sequence of calls over the whole C ABI of one instance.",
            driver,
        ),
    };
    let (functions_type, functions_macro, label) = if version == "driver3" {
        ("Fmi3Functions", "fmi3_functions", "FMI 3.0: ")
    } else {
        ("Fmi2Functions", "fmi2_functions", "")
    };
    let lib = &fmu.lib_name;
    let model = &fmu.model_identifier;
    format!(
        "#![no_main]\n\
         //! {label}{what}\n\
         //! Written by `cargo xtask fuzz-crates` from [package.metadata.fmu].\n\
         #[path = \"../../common/{driver}.rs\"]\n\
         mod {driver};\n\
         \n\
         static FUNCTIONS: fmi_testkit::{functions_type} = fmi_testkit::{functions_macro}!({lib});\n\
         \n\
         libfuzzer_sys::fuzz_target!(|data: &[u8]| {{\n    \
         {driver}::{function}::<{lib}::{model}>(&FUNCTIONS, data);\n\
         }});\n"
    )
}

fn cargo_toml(fmu: &FmuCrate) -> String {
    let mut text = format!(
        "# Written by `cargo xtask fuzz-crates` from {dir}/Cargo.toml's [package.metadata.fmu].\n\
         [package]\n\
         name = \"fuzz-{short}\"\n\
         version = \"0.0.0\"\n\
         publish = false\n\
         edition = \"2021\"\n\
         description = \"cargo-fuzz targets for {id} (nightly only; never part of the build or the tests)\"\n\
         \n\
         [package.metadata]\n\
         cargo-fuzz = true\n\
         \n\
         [dependencies]\n\
         libfuzzer-sys = \"0.4\"\n\
         crc32fast = \"1\"\n\
         {package} = {{ path = \"../../{dir}\" }}\n\
         fmi-model = {{ path = \"../../fmi-model\" }}\n\
         fmi-export = {{ path = \"../../fmi-export\" }}\n\
         fmi2-export = {{ path = \"../../fmi2-export\" }}\n\
         fmi3-export = {{ path = \"../../fmi3-export\" }}\n\
         fmi-testkit = {{ path = \"../../fmi-testkit\" }}\n\
         \n\
         # Its own workspace: the fuzz crates are excluded from the project's.\n\
         [workspace]\n\
         members = [\".\"]\n",
        short = short_name(fmu),
        id = fmu.model_identifier,
        package = fmu.package,
        dir = fmu.dir.display(),
    );
    for (name, _, _) in targets(fmu) {
        text.push_str(&format!(
            "\n[[bin]]\nname = \"{name}\"\npath = \"fuzz_targets/{name}.rs\"\ntest = false\ndoc = false\nbench = false\n"
        ));
    }
    text
}

/// Every file of every fuzz crate, relative to the workspace root, with its text.
pub fn files(fmus: &[FmuCrate]) -> Vec<(PathBuf, String)> {
    let mut files = Vec::new();
    for fmu in fmus {
        let dir = PathBuf::from("fuzz").join(short_name(fmu));
        files.push((dir.join("Cargo.toml"), cargo_toml(fmu)));
        for (name, driver, function) in targets(fmu) {
            files.push((
                dir.join("fuzz_targets").join(format!("{name}.rs")),
                target_source(fmu, driver, function),
            ));
        }
    }
    files
}

pub fn run(ws: &Workspace, check: bool) -> Result<()> {
    let fmus = fmu_metadata::workspace_fmus(&ws.root).map_err(anyhow::Error::msg)?;
    let mut stale = Vec::new();
    for (path, text) in files(&fmus) {
        let full = ws.root.join(&path);
        let current = std::fs::read_to_string(&full).ok();
        if current.as_deref() == Some(text.as_str()) {
            continue;
        }
        if check {
            stale.push(path.display().to_string());
        } else {
            std::fs::create_dir_all(full.parent().expect("a file in a folder"))?;
            std::fs::write(&full, text).with_context(|| format!("write {}", full.display()))?;
            println!("wrote {}", path.display());
        }
    }
    // A fuzz crate of an FMU that is gone would fuzz nothing anyone ships.
    let expected: Vec<String> = fmus.iter().map(short_name).collect();
    for entry in std::fs::read_dir(ws.root.join("fuzz")).context("read fuzz/")? {
        let entry = entry?;
        let name = entry.file_name().to_string_lossy().into_owned();
        if entry.path().is_dir() && name != "common" && !expected.contains(&name) {
            stale.push(format!("fuzz/{name} (no FMU crate of that name)"));
        }
    }
    if !stale.is_empty() {
        bail!(
            "the fuzz crates differ from the FMU crates' [package.metadata.fmu]; \
             run `cargo xtask fuzz-crates`:\n  {}",
            stale.join("\n  ")
        );
    }
    Ok(())
}
