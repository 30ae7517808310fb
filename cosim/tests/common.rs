//! Test fixtures: the packaged lander FMUs of target/fmu, their closed loop as a system, and
//! zip helpers independent of the importer's own unpacking.

use cosim::system::{toml_format, SystemDescription};
use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};

pub fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("cosim/ lives in the workspace root")
        .to_path_buf()
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

/// The lander's closed loop (tests/fixtures/lander_loop.toml), its FMUs named relative to
/// [`fmu_dir`].
pub fn lander_loop() -> SystemDescription {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/lander_loop.toml");
    let text = fs::read_to_string(&path).unwrap();
    toml_format::parse(&text, &path).unwrap_or_else(|e| panic!("{e}"))
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
