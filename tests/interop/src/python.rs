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
