//! `target/fmu/LanderDescent.ssp`, written by `cargo xtask fmus`: what it holds, and fmpy's
//! SSP reader accepting it with schema validation on.
use cosim::system::ParamValue;
use interop_tests::{fmu_path, python, scenario, ssp_path, workspace_root};
use std::io::Read;

fn entry(archive: &mut zip::ZipArchive<std::fs::File>, name: &str) -> Vec<u8> {
    let mut bytes = Vec::new();
    archive
        .by_name(name)
        .unwrap_or_else(|e| panic!("LanderDescent.ssp has no {name}: {e}"))
        .read_to_end(&mut bytes)
        .unwrap();
    bytes
}

#[test]
fn package_holds_the_shipped_ssd_and_the_packaged_fmus() {
    let mut archive = zip::ZipArchive::new(std::fs::File::open(ssp_path()).unwrap()).unwrap();
    let mut names: Vec<_> = archive.file_names().map(str::to_owned).collect();
    names.sort();
    assert_eq!(
        names,
        [
            "SystemStructure.ssd",
            "resources/LanderGnc.fmu",
            "resources/LanderPlant.fmu"
        ]
    );
    let shipped = std::fs::read(workspace_root().join("harness/scenarios/paper.ssd")).unwrap();
    assert_eq!(entry(&mut archive, "SystemStructure.ssd"), shipped);
    for fmu in ["LanderGnc", "LanderPlant"] {
        let packaged = std::fs::read(fmu_path(fmu)).unwrap();
        assert!(
            entry(&mut archive, &format!("resources/{fmu}.fmu")) == packaged,
            "resources/{fmu}.fmu differs from target/fmu/{fmu}.fmu"
        );
    }
}

#[test]
fn fmpy_reads_the_package_with_schema_validation_and_finds_the_harness_system() {
    // GIVEN what the harness reads from the shipped SSD (the source of the package)
    let system = scenario("paper");

    // WHEN fmpy's read_ssd validates and reads the package
    let report = python::run("ssp_read.py", [ssp_path()]);

    // THEN the same components, every parameter value exactly, and the 18 scalar connections
    let lines: Vec<&str> = report.lines().collect();
    let components: Vec<_> = lines
        .iter()
        .filter(|l| l.starts_with("component "))
        .collect();
    assert_eq!(components.len(), 2, "{report}");
    let mut parameter_count = 0;
    for instance in &system.instances {
        for (name, value) in &instance.parameters {
            let prefix = format!("parameter {}.{name} ", instance.name);
            let read = lines
                .iter()
                .find_map(|l| l.strip_prefix(prefix.as_str()))
                .unwrap_or_else(|| panic!("fmpy did not read {}.{name}:\n{report}", instance.name));
            match value {
                ParamValue::Real(x) => assert_eq!(read.parse::<f64>().unwrap(), *x, "{name}"),
                ParamValue::Integer(i) => assert_eq!(read.parse::<i64>().unwrap(), *i, "{name}"),
                other => panic!("unexpected parameter type {other:?}"),
            }
            parameter_count += 1;
        }
    }
    assert_eq!(
        lines.iter().filter(|l| l.starts_with("parameter ")).count(),
        parameter_count
    );
    let connections = lines
        .iter()
        .filter(|l| l.starts_with("connection "))
        .count();
    assert_eq!(
        connections, 18,
        "14 navigation + 4 command scalars:\n{report}"
    );
}
