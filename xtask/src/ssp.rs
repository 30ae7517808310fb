//! `LanderDescent.ssp`: the paper scenario as an SSP package, the one file a user hands to an
//! SSP-capable master (fmpy's `simulate_ssp`, libcosim) to fly the closed loop. Two are
//! written: SSP 1.0 with the FMI 2.0 pair beside the FMI 2.0 FMUs, SSP 2.0 with the FMI 3.0
//! pair (arrays as arrays) beside the FMI 3.0 FMUs in `fmi3/`.
//!
//! Each archive holds `SystemStructure.ssd` (a shipped `harness/scenarios/*.ssd`, itself
//! generated from `paper.toml` and drift-tested by the harness) and the two FMUs it names
//! under `resources/`. It is written with the FMU archives' writer (sorted entries, fixed
//! timestamps), so the same FMUs give the same bytes.
use crate::fmu_zip::{self, Entry};
use crate::workspace::Workspace;
use anyhow::{bail, Context, Result};
use std::path::{Path, PathBuf};

/// File name of a package in its FMU output folder.
pub const PACKAGE: &str = "LanderDescent.ssp";

/// Each package: the folder of its FMUs under the FMU output folder, and its system structure
/// relative to the workspace root.
const PACKAGES: [(&str, &str); 2] = [
    ("", "harness/scenarios/paper.ssd"),
    ("fmi3", "harness/scenarios/paper-fmi3.ssd"),
];

/// The FMUs the SSD names as `resources/<modelIdentifier>.fmu`.
const COMPONENT_FMUS: [&str; 2] = ["LanderGnc.fmu", "LanderPlant.fmu"];

/// Writes each `LanderDescent.ssp` beside the packaged FMUs it holds, under `fmu_dir`;
/// returns their paths.
pub fn package(ws: &Workspace, fmu_dir: &Path) -> Result<Vec<PathBuf>> {
    PACKAGES
        .iter()
        .map(|(folder, ssd)| package_one(&ws.root.join(ssd), &fmu_dir.join(folder)))
        .collect()
}

fn package_one(ssd_path: &Path, fmu_dir: &Path) -> Result<PathBuf> {
    let ssd = std::fs::read_to_string(ssd_path)
        .with_context(|| format!("cannot read {}", ssd_path.display()))?;
    let mut fmus = Vec::with_capacity(COMPONENT_FMUS.len());
    for fmu in COMPONENT_FMUS {
        let path = fmu_dir.join(fmu);
        let bytes =
            std::fs::read(&path).with_context(|| format!("cannot read {}", path.display()))?;
        fmus.push((fmu, bytes));
    }
    let bytes = archive(&ssd, fmus).with_context(|| format!("packaging {}", ssd_path.display()))?;
    let package = fmu_dir.join(PACKAGE);
    let partial = fmu_dir.join(format!(".{PACKAGE}.partial"));
    std::fs::write(&partial, bytes)
        .with_context(|| format!("cannot write {}", partial.display()))?;
    std::fs::rename(&partial, &package)
        .with_context(|| format!("cannot write {}", package.display()))?;
    Ok(package)
}

/// The package bytes: the SSD and each FMU (file name, bytes) under `resources/`.
fn archive(ssd: &str, fmus: Vec<(&str, Vec<u8>)>) -> Result<Vec<u8>> {
    let mut entries = vec![Entry::file("SystemStructure.ssd", ssd.as_bytes().to_vec())];
    for (name, bytes) in fmus {
        let source = format!("resources/{name}");
        // A renamed FMU would otherwise give a package whose SSD points at nothing.
        if !ssd.contains(&format!("source=\"{source}\"")) {
            bail!("the SSD has no component with source=\"{source}\"");
        }
        entries.push(Entry::file(source, bytes));
    }
    fmu_zip::archive(entries)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Read;

    const SSD_TEXT: &str = r#"<ssd:Component name="gnc" source="resources/LanderGnc.fmu"/>
<ssd:Component name="plant" source="resources/LanderPlant.fmu"/>"#;

    fn fmus() -> Vec<(&'static str, Vec<u8>)> {
        vec![
            ("LanderGnc.fmu", b"gnc bytes".to_vec()),
            ("LanderPlant.fmu", b"plant bytes".to_vec()),
        ]
    }

    #[test]
    fn package_holds_the_ssd_and_the_fmus_under_resources_and_is_reproducible() {
        let bytes = archive(SSD_TEXT, fmus()).unwrap();
        let mut reversed = fmus();
        reversed.reverse();
        assert_eq!(bytes, archive(SSD_TEXT, reversed).unwrap());

        let mut zip = zip::ZipArchive::new(std::io::Cursor::new(bytes)).unwrap();
        let mut names: Vec<_> = zip.file_names().map(str::to_owned).collect();
        names.sort();
        assert_eq!(
            names,
            [
                "SystemStructure.ssd",
                "resources/LanderGnc.fmu",
                "resources/LanderPlant.fmu"
            ]
        );
        let mut ssd = String::new();
        zip.by_name("SystemStructure.ssd")
            .unwrap()
            .read_to_string(&mut ssd)
            .unwrap();
        assert_eq!(ssd, SSD_TEXT);
        let mut plant = Vec::new();
        zip.by_name("resources/LanderPlant.fmu")
            .unwrap()
            .read_to_end(&mut plant)
            .unwrap();
        assert_eq!(plant, b"plant bytes");
    }

    fn entry(package: &Path, name: &str) -> Vec<u8> {
        let mut zip = zip::ZipArchive::new(std::fs::File::open(package).unwrap()).unwrap();
        let mut bytes = Vec::new();
        zip.by_name(name).unwrap().read_to_end(&mut bytes).unwrap();
        bytes
    }

    #[test]
    fn the_ssp1_package_holds_the_fmi2_pair_and_the_ssp2_package_the_fmi3_pair() {
        // GIVEN an FMU folder whose FMI 2.0 and FMI 3.0 FMUs say which they are
        let ws = Workspace::locate().unwrap();
        let dir = std::env::temp_dir().join(format!("xtask-ssp-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("fmi3")).unwrap();
        for fmu in COMPONENT_FMUS {
            std::fs::write(dir.join(fmu), format!("fmi2 {fmu}")).unwrap();
            std::fs::write(dir.join("fmi3").join(fmu), format!("fmi3 {fmu}")).unwrap();
        }
        // WHEN both packages are written
        let written = package(&ws, &dir);
        let (ssp1, ssp2) = (dir.join(PACKAGE), dir.join("fmi3").join(PACKAGE));
        let read = |package: &Path| {
            let ssd = String::from_utf8(entry(package, "SystemStructure.ssd")).unwrap();
            (ssd, entry(package, "resources/LanderGnc.fmu"))
        };
        let found = written.map(|w| (w, read(&ssp1), read(&ssp2)));
        std::fs::remove_dir_all(&dir).unwrap();
        // THEN each sits beside its FMUs, holds them and the SSD of its SSP version
        let (written, from1, from2) = found.unwrap();
        assert_eq!(written, [ssp1, ssp2]);
        for ((ssd, gnc), version, fmi) in [(from1, "1.0", "fmi2"), (from2, "2.0", "fmi3")] {
            assert!(ssd.contains(&format!(r#" version="{version}" name="paper">"#)));
            assert_eq!(gnc, format!("{fmi} LanderGnc.fmu").as_bytes());
        }
    }

    #[test]
    fn an_fmu_the_ssd_does_not_name_is_refused() {
        let ssd = r#"<ssd:Component name="gnc" source="resources/LanderGnc.fmu"/>"#;
        let error = archive(ssd, fmus()).unwrap_err().to_string();
        assert!(error.contains("resources/LanderPlant.fmu"), "{error}");
    }
}
