//! The Python side: the workspace venv (pinned packages of tests/python/requirements.txt,
//! created by `cargo xtask python-env`) and the scripts of tests/interop/python.
use std::ffi::OsStr;
use std::path::PathBuf;
use std::process::Command;

pub fn venv_python() -> PathBuf {
    let python = crate::workspace_root().join(".venv/bin/python");
    assert!(
        python.is_file(),
        "{} is missing: run `cargo xtask python-env` (or `cargo xtask test`, which does)",
        python.display()
    );
    python
}

pub fn script(name: &str) -> PathBuf {
    crate::workspace_root()
        .join("tests/interop/python")
        .join(name)
}

/// `python script args...` with `envs` added; returns stdout, printed too. Panics with both
/// streams when the script fails.
pub fn run_with_env<I, S>(name: &str, args: I, envs: &[(String, String)]) -> String
where
    I: IntoIterator<Item = S>,
    S: AsRef<OsStr>,
{
    let path = script(name);
    let output = Command::new(venv_python())
        .arg(&path)
        .args(args)
        .envs(envs.iter().map(|(k, v)| (k, v)))
        .output()
        .unwrap_or_else(|e| panic!("cannot run {}: {e}", path.display()));
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    let stderr = String::from_utf8_lossy(&output.stderr);
    println!("{stdout}");
    assert!(
        output.status.success(),
        "{name} failed ({}):\n{stdout}\n{stderr}",
        output.status
    );
    stdout
}

/// `python script args...`; see [`run_with_env`].
pub fn run<I, S>(name: &str, args: I) -> String
where
    I: IntoIterator<Item = S>,
    S: AsRef<OsStr>,
{
    run_with_env(name, args, &[])
}

/// `python -m <exporter> build -f <script> -d <dir>` (pythonfmu, pythonfmu3): the FMU it
/// writes, named after the script.
pub fn build_fmu(exporter: &str, script_name: &str, dir: &std::path::Path) -> PathBuf {
    let source = script(script_name);
    let output = Command::new(venv_python())
        .args(["-m", exporter, "build", "-f"])
        .arg(&source)
        .arg("-d")
        .arg(dir)
        .output()
        .unwrap_or_else(|e| panic!("cannot run {exporter}: {e}"));
    assert!(
        output.status.success(),
        "{exporter} build failed:\n{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
    let stem = source.file_stem().expect("a script file name");
    let fmu = dir.join(stem).with_extension("fmu");
    assert!(fmu.is_file(), "{exporter} wrote no {}", fmu.display());
    fmu
}

/// Rewrites the FMU's modelDescription.xml in place, as a model's author would correct what
/// an exporter cannot express.
pub fn rewrite_model_description(fmu: &std::path::Path, rewrite: impl FnOnce(String) -> String) {
    use std::io::{Read, Write};
    let mut entries = Vec::new();
    let mut archive = zip::ZipArchive::new(std::fs::File::open(fmu).unwrap()).unwrap();
    let mut rewrite = Some(rewrite);
    for i in 0..archive.len() {
        let mut entry = archive.by_index(i).unwrap();
        let name = entry.name().to_owned();
        let mut bytes = Vec::new();
        entry.read_to_end(&mut bytes).unwrap();
        if name == "modelDescription.xml" {
            let rewrite = rewrite.take().expect("one modelDescription.xml");
            bytes = rewrite(String::from_utf8(bytes).unwrap()).into_bytes();
        }
        entries.push((name, bytes));
    }
    drop(archive);
    let mut out = zip::ZipWriter::new(std::fs::File::create(fmu).unwrap());
    for (name, bytes) in entries {
        out.start_file(name, zip::write::SimpleFileOptions::default())
            .unwrap();
        out.write_all(&bytes).unwrap();
    }
    out.finish().unwrap();
}

/// What a native process needs to host an embedded Python (the venv's libpython preloaded,
/// PYTHONHOME), from tests/interop/python/embedding_env.py.
pub fn embedding_env() -> Vec<(String, String)> {
    run("embedding_env.py", std::iter::empty::<&str>())
        .lines()
        .filter_map(|line| line.split_once('='))
        .map(|(k, v)| (k.to_owned(), v.to_owned()))
        .collect()
}
