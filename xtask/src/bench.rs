//! `cargo xtask bench`: package the FMUs, make sure the Python venv exists, then run the
//! side-by-side speed measurement (tests/speed) in one release process, which prints the
//! table. Arguments after `--` go to it (`cargo xtask bench -- --quick`, `--runs 100`).
use crate::workspace::{self, Workspace};
use crate::{fmus, python_env};
use anyhow::Result;

pub fn run(ws: &Workspace, args: &[String]) -> Result<()> {
    fmus::package_all(ws)?;
    // Rows 5 and 6 (fmpy, pythonfmu) need the venv; without them there is no side by side.
    if !args.iter().any(|a| a == "--no-python") {
        python_env::ensure(ws)?;
    }
    let mut bench = ws.cargo();
    bench
        .args([
            "run",
            "--release",
            "-q",
            "-p",
            "speed-bench",
            "--",
            "--fmu-dir",
        ])
        .arg(ws.fmu_dir())
        .args(args);
    workspace::run(&mut bench)
}
