//! The harness in the release: built for the host and for every cross target the FMUs are
//! built for, each at `bin/<platform>/harness[.exe]` (the FMI 3.0 platform folder names), and
//! the shipped scenario files in `scenarios/`. A harness run from there finds the release's
//! FMUs by itself (`harness/src/fmu_dirs.rs`).
use crate::cross::{self, Artifact};
use crate::platform::{FmiVersion, Platform};
use crate::workspace::{self, Workspace};
use anyhow::{Context, Result};
use std::path::{Path, PathBuf};

const PACKAGE: &str = "harness";
const PROGRAM: &str = "harness";

/// One built harness: where it is, where it goes in the release, and the `strip` for it.
pub struct Built {
    pub from: PathBuf,
    pub to: PathBuf,
    strip: &'static str,
}

/// Builds the harness for the host and every cross target; returns what to copy where.
pub fn build(ws: &Workspace) -> Result<Vec<Built>> {
    let mut built = Vec::new();
    let host = Platform::host()?;
    workspace::run(
        ws.cargo()
            .args(["build", "--release", "-p", PACKAGE, "--bin", PROGRAM]),
    )
    .context("building the harness for the host")?;
    built.push(Built {
        from: ws.target_dir.join("release").join(file_name(&host)),
        to: release_path(&host)?,
        strip: "strip",
    });
    for target in &cross::TARGETS {
        let platform = Platform::from_triple(target.triple)?;
        let dir = cross::build_artifact(
            ws,
            target,
            Artifact::Program {
                package: PACKAGE,
                bin: PROGRAM,
            },
        )?;
        built.push(Built {
            from: dir.join(file_name(&platform)),
            to: release_path(&platform)?,
            strip: target.strip,
        });
    }
    Ok(built)
}

/// Strips the copy of `built` in `release` of its symbols (a third of its size).
pub fn strip(built: &Built, release: &Path) -> Result<()> {
    let path = release.join(&built.to);
    workspace::run(std::process::Command::new(built.strip).arg(&path))
        .with_context(|| format!("stripping {}", path.display()))
}

fn file_name(platform: &Platform) -> String {
    if platform.triple.contains("windows") {
        format!("{PROGRAM}.exe")
    } else {
        PROGRAM.to_owned()
    }
}

/// `bin/<FMI 3.0 platform folder>/harness[.exe]`, relative to the release directory.
fn release_path(platform: &Platform) -> Result<PathBuf> {
    Ok(Path::new("bin")
        .join(platform.folder(FmiVersion::V3)?)
        .join(file_name(platform)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_platform_has_its_folder_and_windows_an_exe() {
        let paths: Vec<PathBuf> = [
            "x86_64-unknown-linux-gnu",
            "aarch64-unknown-linux-gnu",
            "x86_64-pc-windows-gnu",
        ]
        .iter()
        .map(|t| release_path(&Platform::from_triple(t).unwrap()).unwrap())
        .collect();
        assert_eq!(
            paths,
            [
                Path::new("bin/x86_64-linux/harness"),
                Path::new("bin/aarch64-linux/harness"),
                Path::new("bin/x86_64-windows/harness.exe"),
            ]
        );
    }
}
