//! `cargo xtask bench`: package the FMUs, make sure the Python venv and valgrind exist, then
//! run the side-by-side speed measurement (tests/speed) in one release process, which prints
//! the wall-clock table, the instruction counts per closed-loop step in each call order
//! against the plain Rust floor, and what the harness's master adds to the FMUs (both with
//! callgrind). Arguments after `--` go to the first (`cargo xtask bench -- --quick`,
//! `--runs 100`); `--quick` skips the counts.
use crate::workspace::{self, Workspace};
use crate::{fmus, python_env, system_packages};
use anyhow::Result;

pub fn run(ws: &Workspace, args: &[String]) -> Result<()> {
    system_packages::ensure(&system_packages::for_test())?;
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
            "--bin",
            "speed-bench",
            "--",
            "--fmu-dir",
        ])
        .arg(ws.fmu_dir())
        .args(args);
    workspace::run(&mut bench)?;
    if args.iter().any(|a| a == "--quick") {
        return Ok(());
    }
    // The packaged libraries are stripped; their unstripped twins of the same build (in
    // target/release) let callgrind name the functions and count the GNC's evaluations.
    let mut counts = ws.cargo();
    counts
        .args([
            "run",
            "--release",
            "-q",
            "-p",
            "speed-bench",
            "--bin",
            "call_orders",
            "--",
            "--fmu-dir",
        ])
        .arg(ws.fmu_dir())
        .arg("--binaries")
        .arg(ws.target_dir.join("release"))
        .arg("count");
    workspace::run(&mut counts)?;
    // What the harness's master adds to the FMUs, recording every output.
    let mut master = ws.cargo();
    master
        .args([
            "run",
            "--release",
            "-q",
            "-p",
            "speed-bench",
            "--bin",
            "harness-cost",
            "--",
            "compare",
            "--fmu-dir",
        ])
        .arg(ws.fmu_dir());
    workspace::run(&mut master)
}
