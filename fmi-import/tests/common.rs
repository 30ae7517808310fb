//! Test fixtures: the files of `files.rs` (the packaged FMUs, the Oscillator, zip helpers)
//! and a C stub FMU compiled on the spot.

use crate::archives::STUB_DESCRIPTION;
pub use crate::files::*;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;
use tempfile::TempDir;

/// An unpacked stub FMU: `stub_fmu.c` compiled with `defines` (e.g. `-DSTUB_OMIT_DO_STEP`)
/// into `binaries/linux64/Stub.so`, next to `description`.
pub struct StubFmu {
    pub dir: PathBuf,
    _temp: TempDir,
}

impl StubFmu {
    pub fn build(defines: &[&str], description: &str) -> Self {
        let temp = TempDir::new().expect("temporary directory");
        let dir = temp.path().join("stub");
        let binaries = dir.join("binaries").join("linux64");
        fs::create_dir_all(&binaries).expect("create binaries/linux64");
        fs::write(dir.join("modelDescription.xml"), description).expect("write description");
        let source = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests")
            .join("fixtures")
            .join("stub_fmu.c");
        let compiler = std::env::var("CC").unwrap_or_else(|_| "cc".to_owned());
        let output = Command::new(&compiler)
            .args([
                "-shared", "-fPIC", "-std=c99", "-Wall", "-Wextra", "-Werror", "-o",
            ])
            .arg(binaries.join("Stub.so"))
            .arg(&source)
            .args(defines)
            .output()
            .unwrap_or_else(|error| {
                panic!("cannot run the C compiler `{compiler}` (set CC to one): {error}")
            });
        assert!(
            output.status.success(),
            "compiling {} failed:\n{}",
            source.display(),
            String::from_utf8_lossy(&output.stderr)
        );
        Self { dir, _temp: temp }
    }

    pub fn standard() -> Self {
        Self::build(&[], STUB_DESCRIPTION)
    }

    pub fn binary(&self) -> PathBuf {
        self.dir.join("binaries").join("linux64").join("Stub.so")
    }

    /// Calls one of the stub's counters (`stub_live_instances`, `stub_live_states`) through
    /// a second handle on the same loaded library.
    pub fn counter(&self, symbol: &str) -> i32 {
        // SAFETY: the stub defines these as `int name(void)`.
        unsafe {
            let library = libloading::Library::new(self.binary()).expect("reopen the stub");
            let counter = library
                .get::<unsafe extern "C" fn() -> i32>(symbol.as_bytes())
                .expect("stub counter symbol");
            counter()
        }
    }
}
