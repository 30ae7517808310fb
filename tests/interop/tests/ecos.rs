//! The closed loop in Ecos (ecospy), built by Ecos from the SSP package, against the harness
//! flying the same package with Ecos's conventions (`Ordering::Jacobi` + `Conventions::ECOS`):
//! the trajectories must be bit-identical.
//!
//! The package carries a law other than the default (coupled), so the comparison also shows
//! that Ecos applied `control_law`. Ecos (0.7), like libcosim, does not expose FMI 2.0
//! Enumeration variables, which is why LanderGnc declares `control_law` as an Integer with
//! bounds (the values listed in its description).
//!
//! Ecos needs the Debian package libtbb12 (installed by `cargo xtask test`).
// std's transcendental functions make test inputs here, outside any FMU (the
// workspace clippy.toml forbids them for the FMUs' sake).
#![allow(clippy::disallowed_methods)]
use cosim::master::Conventions;
use cosim::system::Ordering;
use fmi_import::Fmu;
use fmi_import::VariableKind;
use interop_tests::compare::assert_identical_after_steps;
use interop_tests::{fmu_dir, python, read_trajectory, run_harness, scenario, scratch, ssp_path};
use std::io::{Read, Write};
use std::path::Path;

const COUPLED: i64 = 1;

/// A copy of `source` whose SSD sets `control_law` to `law`.
fn package_with_law(source: &Path, destination: &Path, law: i64) {
    let mut archive = zip::ZipArchive::new(std::fs::File::open(source).unwrap()).unwrap();
    let mut out = zip::ZipWriter::new(std::fs::File::create(destination).unwrap());
    let options = zip::write::SimpleFileOptions::default();
    for i in 0..archive.len() {
        let mut entry = archive.by_index(i).unwrap();
        let name = entry.name().to_owned();
        let mut bytes = Vec::new();
        entry.read_to_end(&mut bytes).unwrap();
        if name == "SystemStructure.ssd" {
            let text = String::from_utf8(bytes).unwrap();
            let shipped = r#"<ssv:Parameter name="control_law"><ssv:Integer value="2"/>"#;
            assert!(
                text.contains(shipped),
                "the shipped SSD sets control_law = 2"
            );
            bytes = text
                .replace(
                    shipped,
                    &format!(r#"<ssv:Parameter name="control_law"><ssv:Integer value="{law}"/>"#),
                )
                .into_bytes();
        }
        out.start_file(name, options).unwrap();
        out.write_all(&bytes).unwrap();
    }
    out.finish().unwrap();
}

#[test]
fn ecos_flies_the_ssp_package_with_its_parameter_set_bit_identically() {
    // GIVEN the SSP package, asking for the coupled law
    let dir = scratch("interop-ecos-");
    let package = dir.path().join("LanderDescent-coupled.ssp");
    package_with_law(&ssp_path(), &package, COUPLED);
    let mut system = scenario(package.to_str().expect("a UTF-8 temporary path"));
    system.ordering = Ordering::Jacobi;

    // WHEN Ecos builds the simulation from it and applies its parameter set
    let csv = dir.path().join("ecos.csv");
    let stdout = python::run(
        "ecos_master.py",
        [
            package.as_os_str(),
            csv.as_os_str(),
            system.stop_time.to_string().as_ref(),
            system.step_size.to_string().as_ref(),
        ],
    );
    let ecos = read_trajectory(&csv);

    // THEN it flew the package's law, which it can set because the declaration is an Integer
    let gnc = Fmu::load(fmu_dir().join("LanderGnc.fmu")).unwrap();
    let declared = gnc.variable("control_law").unwrap().kind;
    assert_eq!(
        declared,
        VariableKind::Integer,
        "control_law must stay settable in Ecos"
    );
    assert!(stdout.contains("control_law = 1"), "{stdout}");
    // AND every plant output after every step is the number the harness computes
    let reference = run_harness(system, Conventions::ECOS);
    assert_identical_after_steps(
        "Ecos (SSP) vs harness (Jacobi, Ecos conventions)",
        &reference,
        &ecos,
    );
    // AND the plant's parameters were applied: the package's 15 deg tilted start
    let q0 = ecos.column("plant.q_body_to_nue[1]").unwrap()[0];
    assert!((q0 - 7.5f64.to_radians().cos()).abs() < 1e-4, "q0 {q0}");
}
