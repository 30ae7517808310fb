//! The packaged FMUs and the Oscillator FMU, and zip helpers independent of the importer's
//! own unpacking: shared by the importer's, the master's and the harness's tests (the latter
//! two include this file by path), each finding the workspace from its own crate folder.
#![allow(dead_code)] // each test binary uses a different subset

use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};
use tempfile::TempDir;

pub fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("every crate lives in the workspace root")
        .to_path_buf()
}

/// The cargo target directory this test binary was built into (`<target>/<profile>/deps/<test>`).
fn target_dir() -> Option<PathBuf> {
    let exe = std::env::current_exe().ok()?;
    Some(exe.parent()?.parent()?.parent()?.to_path_buf())
}

fn profile_dir() -> Option<PathBuf> {
    let exe = std::env::current_exe().ok()?;
    Some(exe.parent()?.parent()?.to_path_buf())
}

/// An FMU file on disk, with whatever temporary directory it was assembled in.
pub struct FmuFile {
    pub path: PathBuf,
    _dir: Option<TempDir>,
}

/// `Oscillator.fmu` as `cargo xtask fmus` packages it or, failing that, assembled here from
/// the `fmu-testmodel` cdylib and `testmodel/modelDescription.xml`. Panics with what to run
/// when neither exists: a test that cannot find its FMU must fail, never pass.
pub fn oscillator_fmu() -> FmuFile {
    let mut looked_in = Vec::new();
    let packaged_dirs = [target_dir(), Some(workspace_root().join("target"))];
    for dir in packaged_dirs.into_iter().flatten() {
        let candidate = dir.join("fmu").join("Oscillator.fmu");
        if candidate.is_file() {
            return FmuFile {
                path: candidate,
                _dir: None,
            };
        }
        looked_in.push(candidate);
    }

    let description = workspace_root()
        .join("testmodel")
        .join("modelDescription.xml");
    let library = profile_dir().map(|dir| dir.join("libfmu_testmodel.so"));
    if let Some(library) = library.filter(|library| library.is_file()) {
        if description.is_file() {
            let dir = TempDir::new().expect("temporary directory");
            let unpacked = dir.path().join("unpacked");
            assemble_unpacked(&unpacked, &description, &library, "Oscillator");
            let path = dir.path().join("Oscillator.fmu");
            zip_dir(&unpacked, &path);
            return FmuFile {
                path,
                _dir: Some(dir),
            };
        }
    }
    looked_in.push(description);
    panic!(
        "Oscillator FMU not found (looked for {looked_in:#?} and libfmu_testmodel.so in the \
         target directory). Run `cargo xtask fmus`, or `cargo build -p fmu-testmodel` with the \
         same CARGO_TARGET_DIR as the tests."
    );
}

/// Lays out an unpacked FMU: `modelDescription.xml` and `binaries/<platform>/<id>.so`.
pub fn assemble_unpacked(dir: &Path, description: &Path, library: &Path, identifier: &str) {
    let binaries = dir.join("binaries").join("linux64");
    fs::create_dir_all(&binaries).expect("create binaries/linux64");
    fs::copy(description, dir.join("modelDescription.xml")).expect("copy modelDescription.xml");
    fs::copy(library, binaries.join(format!("{identifier}.so"))).expect("copy the library");
}

/// Zips a directory tree (entries relative to `dir`) into `out`.
pub fn zip_dir(dir: &Path, out: &Path) {
    let file = fs::File::create(out).expect("create zip");
    let mut zip = zip::ZipWriter::new(file);
    let options = zip::write::SimpleFileOptions::default();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(current) = stack.pop() {
        for entry in fs::read_dir(&current).expect("read dir") {
            let path = entry.expect("dir entry").path();
            if path.is_dir() {
                stack.push(path);
            } else {
                let name = path
                    .strip_prefix(dir)
                    .unwrap()
                    .to_string_lossy()
                    .into_owned();
                zip.start_file(name, options).expect("zip entry");
                zip.write_all(&fs::read(&path).expect("read file"))
                    .expect("write entry");
            }
        }
    }
    zip.finish().expect("finish zip");
}

/// Unpacks a `.fmu` with the zip crate directly, independent of the loader's own unpacking.
pub fn unzip_to(fmu: &Path, dir: &Path) {
    let file = fs::File::open(fmu).expect("open fmu");
    zip::ZipArchive::new(file)
        .expect("fmu is a zip")
        .extract(dir)
        .expect("extract fmu");
}

/// `target/fmu` of the workspace (or `LANDER_FMU_DIR`), checked to hold both lander FMUs;
/// fails (never skips) with the command to run when they are missing.
pub fn fmu_dir() -> PathBuf {
    let dir = std::env::var_os("LANDER_FMU_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| workspace_root().join("target/fmu"));
    for fmu in ["LanderGnc.fmu", "LanderPlant.fmu"] {
        assert!(
            dir.join(fmu).is_file(),
            "{} is missing: run `cargo xtask fmus` first (cargo xtask test does)",
            dir.join(fmu).display()
        );
    }
    dir
}
