//! Each shipped FMU library, stripped, stays under 1 MiB.
use robustness_tests::package::{Lander, Unpacked};
use std::process::Command;

const LIMIT_BYTES: u64 = 1 << 20;

#[test]
fn each_stripped_library_is_under_one_mebibyte() {
    for lander in Lander::ALL {
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
            size < LIMIT_BYTES,
            "{}: {size} bytes stripped",
            lander.model_identifier()
        );
    }
}
