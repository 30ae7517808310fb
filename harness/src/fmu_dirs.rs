//! Where the FMUs a scenario names are looked for when the user names no directory
//! (`--fmu-dir`, `LANDER_FMU_DIR`): a source checkout's `target/fmu` (the working
//! directory's), else the release the harness was unpacked with. A release holds the harness
//! at `bin/<platform>/harness` and the FMUs in `fmi2/` and `fmi3/`; the shipped scenarios
//! name the FMUs bare (`LanderGnc.fmu`) or as `fmi3/...`, so a release's version folder
//! is searched first and its root after.
use std::path::{Path, PathBuf};

/// A source checkout's FMU directory, relative to the working directory.
pub const CHECKOUT: &str = "target/fmu";

/// The release folder searched first: FMI 2.0 where it has a binaries folder for this
/// platform; FMI 2.0 defines none for Linux on ARM, so there the FMI 3.0 FMUs fly.
const FIRST_VERSION_FOLDER: &str = if cfg!(target_arch = "aarch64") {
    "fmi3"
} else {
    "fmi2"
};

/// The directories to search, first one first.
pub fn default_fmu_dirs() -> Vec<PathBuf> {
    let checkout = PathBuf::from(CHECKOUT);
    if checkout.is_dir() {
        return vec![checkout];
    }
    let release = std::env::current_exe()
        .ok()
        .and_then(|exe| release_of(&exe));
    match release {
        Some(root) => vec![root.join(FIRST_VERSION_FOLDER), root],
        // Neither: errors name target/fmu, where a source checkout builds them.
        None => vec![checkout],
    }
}

/// The release directory of a harness at `exe` (`<release>/bin/<platform>/harness`), if it
/// is one: a directory with the FMUs' `fmi2/` and `fmi3/` beside `bin/`.
pub fn release_of(exe: &Path) -> Option<PathBuf> {
    let root = exe.parent()?.parent()?.parent()?;
    let is_release = exe.parent()?.parent()?.file_name()? == "bin"
        && root.join("fmi2").is_dir()
        && root.join("fmi3").is_dir();
    is_release.then(|| root.to_owned())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_harness_in_a_release_finds_the_release_and_elsewhere_none() {
        let dir = tempfile::tempdir().unwrap();
        let root = dir.path().join("lander-fmi-1.0.0");
        for sub in ["bin/x86_64-linux", "fmi2", "fmi3"] {
            std::fs::create_dir_all(root.join(sub)).unwrap();
        }
        let exe = root.join("bin/x86_64-linux/harness");
        assert_eq!(release_of(&exe), Some(root.clone()));
        // The same layout without the FMUs, or with the harness elsewhere, is no release.
        std::fs::remove_dir(root.join("fmi3")).unwrap();
        assert_eq!(release_of(&exe), None);
        assert_eq!(release_of(&root.join("target/release/harness")), None);
    }
}
