//! Shared by the harness's system tests: where the packaged FMUs are.
#![allow(dead_code)]
use std::path::PathBuf;

/// `target/fmu` of the workspace, checked to hold both lander FMUs; fails (never skips) with
/// the command to run when they are missing.
pub fn fmu_dir() -> PathBuf {
    let workspace = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("harness sits in the workspace")
        .to_path_buf();
    let dir = std::env::var_os("LANDER_FMU_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| workspace.join("target/fmu"));
    for fmu in ["LanderGnc.fmu", "LanderPlant.fmu"] {
        assert!(
            dir.join(fmu).is_file(),
            "{} is missing: run `cargo xtask fmus` first (cargo xtask test does)",
            dir.join(fmu).display()
        );
    }
    dir
}
