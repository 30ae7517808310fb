//! `cargo xtask results`: rewrite every generated block of README.md and docs/results.md
//! from the harness command its marker names. The blocks' parser and renderers live in one
//! place, the harness test that checks them (`harness/tests/results_numbers.rs`); this runs
//! it with `UPDATE_RESULTS=1`, which writes what the commands print instead of failing.
use crate::fmus;
use crate::workspace::{self, Workspace};
use anyhow::Result;

/// `campaigns`: also the campaign blocks (the test's ignored part, minutes of flights), flown
/// by a release build of the harness; `only`: just the blocks whose marker contains this
/// text; `workers`: the campaigns' worker threads (default: the harness's, one per core).
pub fn run(
    ws: &Workspace,
    campaigns: bool,
    only: Option<&str>,
    workers: Option<usize>,
) -> Result<()> {
    fmus::package_all(ws)?;
    let mut release = None;
    if campaigns {
        workspace::run(ws.cargo().args(["build", "--release", "-p", "harness"]))?;
        release = Some(ws.target_dir.join("release").join("harness"));
    }
    let mut test = ws.cargo();
    test.args([
        "test",
        "-p",
        "harness",
        "--test",
        "main",
        "results_numbers::",
        "--",
        // Each test rewrites the documents it checks: one at a time.
        "--test-threads=1",
    ])
    .env("UPDATE_RESULTS", "1");
    if let Some(release) = release {
        // Each campaign's flight count and time on stderr.
        test.args(["--include-ignored", "--nocapture"])
            .env("RESULTS_HARNESS", release);
    }
    if let Some(workers) = workers {
        test.env("RESULTS_WORKERS", workers.to_string());
    }
    if let Some(only) = only {
        test.env("RESULTS_ONLY", only);
    }
    workspace::run(&mut test)
}
