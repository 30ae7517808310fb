//! `cargo xtask results`: rewrite every generated block of README.md and docs/results.md
//! from the harness command its marker names. The blocks' parser and renderers live in one
//! place, the harness test that checks them (`harness/tests/results_numbers.rs`); this runs
//! it with `UPDATE_RESULTS=1`, which writes what the commands print instead of failing.
use crate::fmus;
use crate::workspace::{self, Workspace};
use anyhow::Result;

/// `campaigns`: also the campaign blocks (the test's ignored part, minutes of flights);
/// `only`: just the blocks whose marker contains this text.
pub fn run(ws: &Workspace, campaigns: bool, only: Option<&str>) -> Result<()> {
    fmus::package_all(ws)?;
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
    if campaigns {
        test.arg("--include-ignored");
    }
    if let Some(only) = only {
        test.env("RESULTS_ONLY", only);
    }
    workspace::run(&mut test)
}
