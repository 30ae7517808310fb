//! `cargo xtask fmus`: build the release cdylibs and package one `.fmu` per FMU crate.
use crate::doc_page;
use crate::fmu_zip::{self, Entry};
use crate::ssp;
use crate::workspace::{self, Workspace};
use anyhow::{bail, Context, Result};
use model_description::ModelDescription;
use std::path::{Path, PathBuf};

/// A workspace crate that builds an FMU's shared library.
struct FmuCrate {
    package: &'static str,
    /// Folder of the crate, relative to the workspace root.
    dir: &'static str,
    /// `[lib] name`, so the cdylib is `lib<lib_name>.so`.
    lib_name: &'static str,
}

const FMU_CRATES: [FmuCrate; 4] = [
    FmuCrate {
        package: "fmu-gnc",
        dir: "fmu-gnc",
        lib_name: "fmu_gnc",
    },
    FmuCrate {
        package: "fmu-nav",
        dir: "fmu-nav",
        lib_name: "fmu_nav",
    },
    FmuCrate {
        package: "fmu-plant",
        dir: "fmu-plant",
        lib_name: "fmu_plant",
    },
    FmuCrate {
        package: "fmu-testmodel",
        dir: "testmodel",
        lib_name: "fmu_testmodel",
    },
];

/// The example each FMU crate provides to print its generated modelDescription.xml.
const DESCRIPTION_EXAMPLE: &str = "model_description";

/// Build and package every FMU whose crate can describe itself, then the SSP of the paper
/// scenario that holds two of them; returns the written files.
pub fn package_all(ws: &Workspace) -> Result<Vec<PathBuf>> {
    let mut build = ws.cargo();
    build.args(["build", "--release", "--lib"]);
    for fmu in &FMU_CRATES {
        build.args(["-p", fmu.package]);
    }
    workspace::run(&mut build)?;

    let out_dir = ws.fmu_dir();
    std::fs::create_dir_all(&out_dir)
        .with_context(|| format!("cannot create {}", out_dir.display()))?;

    let mut written = Vec::new();
    for fmu in &FMU_CRATES {
        let example = ws
            .root
            .join(fmu.dir)
            .join("examples")
            .join(format!("{DESCRIPTION_EXAMPLE}.rs"));
        if !example.is_file() {
            println!(
                "xtask fmus: skipping {}: it has no `{DESCRIPTION_EXAMPLE}` example yet ({} missing)",
                fmu.package,
                example.display()
            );
            continue;
        }
        let path = package_one(ws, fmu, &out_dir)?;
        println!("xtask fmus: wrote {}", path.display());
        written.push(path);
    }
    if written.is_empty() {
        bail!("no FMU crate has a `{DESCRIPTION_EXAMPLE}` example: nothing was packaged");
    }
    let package = ssp::package(ws, &out_dir)?;
    println!("xtask fmus: wrote {}", package.display());
    written.push(package);
    Ok(written)
}

fn package_one(ws: &Workspace, fmu: &FmuCrate, out_dir: &Path) -> Result<PathBuf> {
    let xml = workspace::output(ws.cargo().args([
        "run",
        "--release",
        "-q",
        "-p",
        fmu.package,
        "--example",
        DESCRIPTION_EXAMPLE,
    ]))?;
    let description = ModelDescription::from_xml(&xml).with_context(|| {
        format!(
            "{} printed a modelDescription.xml that does not parse",
            fmu.package
        )
    })?;
    if let Err(problems) = description.validate() {
        bail!(
            "the model description of {} is invalid:\n  {}",
            fmu.package,
            problems.join("\n  ")
        );
    }
    let identifier = model_identifier(&description)
        .with_context(|| format!("in the model description of {}", fmu.package))?;

    let library = ws
        .target_dir
        .join("release")
        .join(format!("lib{}.so", fmu.lib_name));
    let binary = stripped_library(&library, out_dir, identifier)?;

    let entries = vec![
        Entry::file("modelDescription.xml", xml.into_bytes()),
        Entry::executable(format!("binaries/linux64/{identifier}.so"), binary),
        Entry::file(
            "documentation/index.html",
            doc_page::render(&description).into_bytes(),
        ),
    ];
    let fmu_path = out_dir.join(format!("{identifier}.fmu"));
    fmu_zip::write(&fmu_path, entries)?;
    Ok(fmu_path)
}

/// The co-simulation `modelIdentifier`, checked to be usable as a file name.
fn model_identifier(description: &ModelDescription) -> Result<&str> {
    let cs = description
        .co_simulation
        .as_ref()
        .context("no <CoSimulation> element")?;
    let id = cs.model_identifier.as_str();
    let valid = !id.is_empty()
        && id.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
        && !id.starts_with(|c: char| c.is_ascii_digit());
    if !valid {
        bail!("modelIdentifier {id:?} is not a valid C identifier");
    }
    Ok(id)
}

/// The shared library's bytes, without its static symbol table when `strip` is available.
/// Stripping leaves `.dynsym` (the exported fmi2* functions) untouched.
fn stripped_library(library: &Path, scratch_dir: &Path, identifier: &str) -> Result<Vec<u8>> {
    if !library.is_file() {
        bail!("{} was not built", library.display());
    }
    let source = if workspace::on_path("strip") {
        let stripped = scratch_dir.join(format!(".{identifier}.stripped.so"));
        workspace::run(
            std::process::Command::new("strip")
                .arg("--strip-unneeded")
                .arg("-o")
                .arg(&stripped)
                .arg(library),
        )?;
        stripped
    } else {
        println!("xtask fmus: `strip` not found, packaging the unstripped library");
        library.to_path_buf()
    };
    let bytes =
        std::fs::read(&source).with_context(|| format!("cannot read {}", source.display()))?;
    if source != library {
        std::fs::remove_file(&source)?;
    }
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;
    use model_description::CoSimulation;

    fn with_identifier(id: &str) -> ModelDescription {
        ModelDescription {
            co_simulation: Some(CoSimulation {
                model_identifier: id.to_owned(),
                ..Default::default()
            }),
            ..Default::default()
        }
    }

    #[test]
    fn model_identifier_is_read_from_co_simulation() {
        assert_eq!(
            model_identifier(&with_identifier("LanderGnc")).unwrap(),
            "LanderGnc"
        );
    }

    #[test]
    fn model_identifier_that_is_no_c_identifier_is_refused() {
        for bad in ["", "1abc", "a-b", "../x", "a b"] {
            assert!(model_identifier(&with_identifier(bad)).is_err(), "{bad:?}");
        }
    }

    #[test]
    fn model_exchange_only_description_is_refused() {
        assert!(model_identifier(&ModelDescription::default()).is_err());
    }
}
