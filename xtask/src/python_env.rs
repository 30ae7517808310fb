//! `cargo xtask python-env`: the virtual environment the Python checks run in, with the
//! pinned versions of tests/python/requirements.txt.
use crate::workspace::{self, Workspace};
use anyhow::{Context, Result};
use std::path::PathBuf;
use std::process::Command;

/// A copy of the requirements the venv was last populated from; equal contents mean the
/// venv already satisfies the file and nothing is installed.
const STAMP: &str = "lander-requirements.txt";

pub fn requirements(ws: &Workspace) -> PathBuf {
    ws.root
        .join("tests")
        .join("python")
        .join("requirements.txt")
}

pub fn venv_dir(ws: &Workspace) -> PathBuf {
    ws.root.join(".venv")
}

pub fn ensure(ws: &Workspace) -> Result<()> {
    let requirements_path = requirements(ws);
    let wanted = std::fs::read_to_string(&requirements_path)
        .with_context(|| format!("cannot read {}", requirements_path.display()))?;
    let venv = venv_dir(ws);
    let python = venv.join("bin").join("python");
    let stamp = venv.join(STAMP);

    let installed = std::fs::read_to_string(&stamp).ok();
    if python.is_file() && installed.as_deref() == Some(wanted.as_str()) {
        println!("xtask python-env: {} is up to date", venv.display());
        return Ok(());
    }

    if !python.is_file() {
        let base_python = std::env::var_os("PYTHON").unwrap_or_else(|| "python3".into());
        workspace::run(Command::new(base_python).args(["-m", "venv"]).arg(&venv))?;
    }
    workspace::run(
        Command::new(&python)
            .args([
                "-m",
                "pip",
                "install",
                "--disable-pip-version-check",
                "-q",
                "-r",
            ])
            .arg(&requirements_path),
    )?;
    workspace::run(Command::new(&python).args([
        "-m",
        "pip",
        "check",
        "--disable-pip-version-check",
    ]))?;
    std::fs::write(&stamp, wanted).with_context(|| format!("cannot write {}", stamp.display()))?;
    println!(
        "xtask python-env: installed {} into {}",
        requirements_path.display(),
        venv.display()
    );
    Ok(())
}
