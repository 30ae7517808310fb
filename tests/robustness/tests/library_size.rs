//! Each shipped FMU library, stripped, stays within its budget: a budget catches a
//! dependency or a generic instantiation that bloats a library unnoticed.
use robustness_tests::package::{Lander, Unpacked};
use std::process::Command;

/// 1 MiB for every FMU (a new one included), and 1.25 MiB for LanderPlant:
/// the one FMU with Model Exchange beside Co-Simulation, and the landing gear, slosh and
/// mass-property models.
fn limit_bytes(lander: Lander) -> u64 {
    match lander {
        Lander::Plant => 5 << 18,
        _ => 1 << 20,
    }
}

#[test]
fn each_stripped_library_is_within_its_budget() {
    for lander in Lander::all() {
        let fmu = Unpacked::open(lander).expect("packaged FMU");
        let stripped = tempfile::NamedTempFile::new().expect("temporary file");
        let status = Command::new("strip")
            .arg("--strip-all")
            .arg("-o")
            .arg(stripped.path())
            .arg(&fmu.library)
            .status()
            .expect("strip (binutils) must be installed");
        assert!(status.success());
        let shipped = std::fs::metadata(&fmu.library).unwrap().len();
        let size = std::fs::metadata(stripped.path()).unwrap().len();
        println!(
            "{}: shipped {shipped} bytes, stripped {size} bytes",
            lander.model_identifier()
        );
        assert!(
            size < limit_bytes(lander),
            "{}: {size} bytes stripped, over its budget of {}",
            lander.model_identifier(),
            limit_bytes(lander)
        );
    }
}
