//! `cargo xtask new-fmu` writes a crate every metadata-driven list takes in as it is, and
//! `cargo xtask fuzz-crates --check` holds fuzz/ to the FMU crates' metadata.
use std::path::Path;
use std::process::Command;

fn xtask(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_xtask"))
        .args(args)
        .output()
        .expect("xtask runs")
}

fn text(output: &std::process::Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    )
}

#[test]
fn every_fmu_crate_has_its_fuzz_crate() {
    let output = xtask(&["fuzz-crates", "--check"]);
    assert!(output.status.success(), "{}", text(&output));
}

#[test]
fn a_new_fmu_crate_is_an_fmu_crate_by_its_metadata_and_its_exports() {
    let into = std::env::temp_dir().join(format!("xtask-new-fmu-{}", std::process::id()));
    std::fs::create_dir_all(&into).unwrap();
    let output = xtask(&["new-fmu", "LanderRadar", "--into", into.to_str().unwrap()]);
    assert!(output.status.success(), "{}", text(&output));
    let dir = into.join("fmu-lander-radar");
    let read = |path: &str| std::fs::read_to_string(dir.join(path)).unwrap();
    let fmu = fmu_metadata::parse_manifest(Path::new("fmu-lander-radar"), &read("Cargo.toml"))
        .unwrap()
        .expect("a [package.metadata.fmu] table");
    assert_eq!(fmu.model_identifier, "LanderRadar");
    assert_eq!(fmu.lib_name, "fmu_lander_radar");
    let exports = fmu_metadata::exports_in_source(&read("src/lib.rs")).unwrap();
    assert_eq!(
        fmu_metadata::check_exports(&fmu, &exports),
        Vec::<String>::new()
    );
    // The binaries `cargo xtask fmus` prints each shipped version's description with.
    for bin in [
        "fmu_lander_radar_model_description",
        "fmu_lander_radar_model_description_fmi3",
    ] {
        assert!(dir.join(format!("src/bin/{bin}.rs")).is_file(), "{bin}");
    }
    assert!(read("tests/conformance.rs")
        .contains("fmi_testkit::conformance!(fmu_lander_radar, LanderRadar);"));
    let count = walk(&dir);
    std::fs::remove_dir_all(&into).unwrap();
    assert!(count <= 8, "{count} files");
    // A name that is no model identifier is refused, and nothing is written.
    let output = xtask(&["new-fmu", "lander radar", "--into", into.to_str().unwrap()]);
    assert!(!output.status.success());
    assert!(
        text(&output).contains("UpperCamelCase"),
        "{}",
        text(&output)
    );
    assert!(!into.exists());
}

fn walk(dir: &Path) -> usize {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| {
            let path = e.unwrap().path();
            if path.is_dir() {
                walk(&path)
            } else {
                1
            }
        })
        .sum()
}
