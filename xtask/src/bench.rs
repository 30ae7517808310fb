//! `cargo xtask bench`: package the FMUs, make sure the Python venv and valgrind exist, then
//! run the side-by-side speed measurement (tests/speed) in one release process, which prints
//! the wall-clock table, the instruction counts per closed-loop step in each call order
//! against the plain-C floor (then a native C master's, with the value references listed in
//! each way users' masters list them, and the worst of each call order), and what the
//! harness's master adds to the FMUs (all with callgrind). Arguments after `--` go to the first (`cargo xtask bench -- --quick`,
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
    let fmu_dir = ws.fmu_dir().display().to_string();
    let mut first = vec!["--fmu-dir".to_string(), fmu_dir.clone()];
    first.extend(args.iter().cloned());
    run_release_bin(ws, "speed-bench", &first)?;
    if args.iter().any(|a| a == "--quick") {
        return Ok(());
    }
    // The packaged libraries are stripped; their unstripped twins of the same build (in
    // target/release) let callgrind name the functions and count the GNC's evaluations.
    let release = ws.target_dir.join("release").display().to_string();
    run_release_bin(
        ws,
        "call_orders",
        &["--fmu-dir", &fmu_dir, "--binaries", &release, "count"].map(String::from),
    )?;
    // What the harness's master adds to the FMUs, recording every output.
    run_release_bin(
        ws,
        "harness-cost",
        &["compare", "--fmu-dir", &fmu_dir].map(String::from),
    )
}

/// `cargo run --release` of one of the speed-bench binaries with `args`.
fn run_release_bin(ws: &Workspace, bin: &str, args: &[String]) -> Result<()> {
    let mut command = ws.cargo();
    command
        .args([
            "run",
            "--release",
            "-q",
            "-p",
            "speed-bench",
            "--bin",
            bin,
            "--",
        ])
        .args(args);
    workspace::run(&mut command)
}
