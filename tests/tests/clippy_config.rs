//! Every FMU crate carries the same `clippy.toml`, the one that forbids std's transcendental
//! functions in model code (docs/floating-point.md). clippy reads the file nearest to the
//! crate, so a crate without one, or with an older copy, would let a platform's C library
//! back into its FMU unnoticed.
use system_tests::{fmu_crates, workspace_root};

#[test]
fn each_fmu_crate_has_the_same_clippy_toml() {
    let fmus = fmu_crates();
    assert!(!fmus.is_empty(), "no FMU crates");
    let read = |dir: &std::path::Path| {
        let path = workspace_root().join(dir).join("clippy.toml");
        std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
    };
    let first = read(&fmus[0].dir);
    for method in [
        "f64::sin_cos",
        "f64::atan2",
        "f64::powi",
        "nalgebra::Unit::from_axis_angle",
    ] {
        assert!(
            first.contains(&format!("\"{method}\"")),
            "{}/clippy.toml does not forbid {method}",
            fmus[0].dir.display()
        );
    }
    for fmu in &fmus[1..] {
        assert!(
            read(&fmu.dir) == first,
            "{}/clippy.toml differs from {}/clippy.toml",
            fmu.dir.display(),
            fmus[0].dir.display()
        );
    }
}
