//! `cargo xtask dist`: a release directory for people who never build from source.
//!
//! `target/dist/lander-fmi-<version>/` holds the all-platform FMUs of every FMI version
//! (`fmi2/`, `fmi3/`), the SSP packages (SSP 1.0 at the top, SSP 2.0 of the FMI 3.0 pair in
//! `fmi3/`), the harness for every platform (`bin/<platform>/`) with the shipped scenarios
//! (`scenarios/`), the Python driver of `harness monte-carlo --dask` (`python/`), the user
//! documentation and `SHA256SUMS` in the format `sha256sum -c` reads. The version is the workspace's (`[workspace.package]`, which
//! xtask and every FMU crate inherit); each FMU must say the same in its model description's
//! `version` attribute, and must carry a binary for every platform of its FMI version, or
//! nothing is written.
use crate::dist_harness;
use crate::fmus;
use crate::ssp;
use crate::workspace::{self, Workspace};
use anyhow::{bail, Context, Result};
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The release version: xtask's own, inherited from `[workspace.package]` like the FMUs'.
const VERSION: &str = env!("CARGO_PKG_VERSION");

/// The binaries folders a released FMU of each FMI version must carry.
const FMI2_FOLDERS: [&str; 2] = ["linux64", "win64"];
const FMI3_FOLDERS: [&str; 3] = ["x86_64-linux", "aarch64-linux", "x86_64-windows"];

/// Files and folders of the workspace copied as the release's documentation.
const DOCUMENTATION: [&str; 3] = ["README.md", "CHANGELOG.md", "docs"];
const LICENSES: [&str; 2] = ["LICENSE-MIT", "LICENSE-APACHE"];
/// The plain-Python driver of `harness monte-carlo --dask`, in `harness/python/`.
const DASK_DRIVER: &str = "harness_dask.py";

pub fn run(ws: &Workspace) -> Result<PathBuf> {
    let written = fmus::package_all_platforms(ws, fmus::Describers::Build(&[]))?;
    let release = ws
        .target_dir
        .join("dist")
        .join(format!("lander-fmi-{VERSION}"));
    let mut problems = Vec::new();
    let mut copies: Vec<(PathBuf, PathBuf)> = Vec::new();
    for fmu in written
        .iter()
        .filter(|p| p.extension().is_some_and(|e| e == "fmu"))
    {
        let fmi3 = fmu.parent().is_some_and(|d| d.ends_with("fmi3"));
        let (folder, platforms): (&str, &[&str]) = if fmi3 {
            ("fmi3", &FMI3_FOLDERS)
        } else {
            ("fmi2", &FMI2_FOLDERS)
        };
        match released_fmu_problems(fmu, platforms) {
            Ok(found) => problems.extend(found),
            Err(error) => problems.push(format!("{}: {error:#}", fmu.display())),
        }
        let name = fmu.file_name().context("an FMU path without a file name")?;
        copies.push((fmu.clone(), release.join(folder).join(name)));
    }
    let ssp = ws.fmu_dir().join(ssp::PACKAGE);
    copies.push((ssp.clone(), release.join(ssp::PACKAGE)));
    // The SSP 2.0 package holds the FMI 3.0 pair: beside the FMI 3.0 FMUs, as in target/fmu.
    let ssp2 = ws.fmu_dir().join("fmi3").join(ssp::PACKAGE);
    copies.push((ssp2, release.join("fmi3").join(ssp::PACKAGE)));
    let harnesses = dist_harness::build(ws)?;
    for built in &harnesses {
        copies.push((built.from.clone(), release.join(&built.to)));
    }
    copies.push((ws.root.join("harness/scenarios"), release.join("scenarios")));
    // Found beside the harness by `--dask` (harness/src/dask.rs): `<release>/python/`.
    copies.push((
        ws.root.join("harness/python").join(DASK_DRIVER),
        release.join("python").join(DASK_DRIVER),
    ));
    for item in DOCUMENTATION.iter().chain(LICENSES.iter()) {
        let from = ws.root.join(item);
        if !from.exists() {
            problems.push(format!("{} is missing", from.display()));
        }
        copies.push((from, release.join(item)));
    }
    if !problems.is_empty() {
        bail!(
            "not releasing lander-fmi {VERSION}:\n  {}",
            problems.join("\n  ")
        );
    }
    if release.exists() {
        std::fs::remove_dir_all(&release)
            .with_context(|| format!("cannot clear {}", release.display()))?;
    }
    for (from, to) in &copies {
        copy(from, to)?;
    }
    for built in &harnesses {
        dist_harness::strip(built, &release)?;
    }
    write_checksums(&release)?;
    println!("xtask dist: wrote {}", release.display());
    Ok(release)
}

/// What keeps `fmu` out of a release: a version other than the release's, a missing
/// platform.
fn released_fmu_problems(fmu: &Path, platforms: &[&str]) -> Result<Vec<String>> {
    let file =
        std::fs::File::open(fmu).with_context(|| format!("cannot open {}", fmu.display()))?;
    let mut archive = zip::ZipArchive::new(file).context("not a zip archive")?;
    let mut xml = String::new();
    archive
        .by_name("modelDescription.xml")
        .context("no modelDescription.xml")?
        .read_to_string(&mut xml)
        .context("modelDescription.xml is not UTF-8")?;
    let mut problems = Vec::new();
    match root_attribute(&xml, "version") {
        Some(v) if v == VERSION => {}
        Some(v) => problems.push(format!(
            "{}: its model description says version=\"{v}\", the release is {VERSION}",
            fmu.display()
        )),
        None => problems.push(format!(
            "{}: its model description has no version attribute",
            fmu.display()
        )),
    }
    let names: Vec<String> = archive.file_names().map(str::to_owned).collect();
    for platform in platforms {
        let prefix = format!("binaries/{platform}/");
        if !names
            .iter()
            .any(|n| n.starts_with(&prefix) && n.len() > prefix.len())
        {
            problems.push(format!("{}: no binary in {prefix}", fmu.display()));
        }
    }
    Ok(problems)
}

/// The value of `name` on the `<fmiModelDescription>` element.
fn root_attribute<'a>(xml: &'a str, name: &str) -> Option<&'a str> {
    let start = xml.find("<fmiModelDescription")?;
    let element = &xml[start..start + xml[start..].find('>')?];
    let key = format!(" {name}=\"");
    let value = &element[element.find(&key)? + key.len()..];
    Some(&value[..value.find('"')?])
}

fn copy(from: &Path, to: &Path) -> Result<()> {
    if from.is_dir() {
        for entry in
            std::fs::read_dir(from).with_context(|| format!("cannot read {}", from.display()))?
        {
            let entry = entry?;
            copy(&entry.path(), &to.join(entry.file_name()))?;
        }
        return Ok(());
    }
    if let Some(parent) = to.parent() {
        std::fs::create_dir_all(parent)
            .with_context(|| format!("cannot create {}", parent.display()))?;
    }
    std::fs::copy(from, to)
        .with_context(|| format!("cannot copy {} to {}", from.display(), to.display()))?;
    Ok(())
}

/// `SHA256SUMS` of every file in the release, by coreutils' `sha256sum` (part of every
/// Debian system) so that the file is exactly what `sha256sum -c SHA256SUMS` checks.
fn write_checksums(release: &Path) -> Result<()> {
    let mut files = Vec::new();
    collect_files(release, release, &mut files)?;
    files.sort();
    let mut command = Command::new("sha256sum");
    command.current_dir(release).arg("--").args(&files);
    let sums = workspace::output(&mut command)?;
    std::fs::write(release.join("SHA256SUMS"), sums)
        .with_context(|| format!("cannot write SHA256SUMS in {}", release.display()))
}

fn collect_files(root: &Path, dir: &Path, files: &mut Vec<String>) -> Result<()> {
    for entry in std::fs::read_dir(dir).with_context(|| format!("cannot read {}", dir.display()))? {
        let path = entry?.path();
        if path.is_dir() {
            collect_files(root, &path, files)?;
        } else {
            let relative = path
                .strip_prefix(root)
                .expect("below the release directory");
            files.push(relative.to_string_lossy().into_owned());
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::{released_fmu_problems, root_attribute, VERSION};
    use crate::fmu_zip::{self, Entry};

    /// An FMU archive in the temporary directory with the given version and binaries.
    fn fmu(name: &str, version: &str, binaries: &[&str]) -> std::path::PathBuf {
        let xml = format!(
            "<?xml version=\"1.0\"?>\n<fmiModelDescription fmiVersion=\"3.0\" \
             version=\"{version}\"/>"
        );
        let mut entries = vec![Entry::file("modelDescription.xml", xml.into_bytes())];
        for folder in binaries {
            entries.push(Entry::executable(
                format!("binaries/{folder}/M.so"),
                vec![0],
            ));
        }
        let path =
            std::env::temp_dir().join(format!("xtask-dist-{}-{name}.fmu", std::process::id()));
        fmu_zip::write(&path, entries).unwrap();
        path
    }

    #[test]
    fn an_fmu_of_another_version_or_without_a_platform_is_not_released() {
        let all = ["x86_64-linux", "aarch64-linux", "x86_64-windows"];
        let good = fmu("good", VERSION, &all);
        assert_eq!(
            released_fmu_problems(&good, &all).unwrap(),
            Vec::<String>::new()
        );
        let old = fmu("old", "0.0.1", &all);
        let problems = released_fmu_problems(&old, &all).unwrap();
        assert!(
            problems.len() == 1 && problems[0].contains("version=\"0.0.1\""),
            "{problems:?}"
        );
        let host_only = fmu("host", VERSION, &all[..1]);
        let problems = released_fmu_problems(&host_only, &all).unwrap();
        assert_eq!(problems.len(), 2, "{problems:?}");
        assert!(
            problems[1].contains("binaries/x86_64-windows/"),
            "{problems:?}"
        );
        for path in [good, old, host_only] {
            let _ = std::fs::remove_file(path);
        }
    }

    #[test]
    fn the_version_is_read_from_the_root_element_only() {
        let xml = r#"<?xml version="1.0"?>
<fmiModelDescription fmiVersion="3.0" modelName="M" version="1.2.3">
  <DefaultExperiment version="9"/>"#;
        assert_eq!(root_attribute(xml, "version"), Some("1.2.3"));
        assert_eq!(root_attribute(xml, "fmiVersion"), Some("3.0"));
        let without = r#"<fmiModelDescription fmiVersion="2.0"><X version="9"/>"#;
        assert_eq!(root_attribute(without, "version"), None);
    }
}
