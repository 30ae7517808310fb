//! `cargo xtask demo`: install what the plots need, package the FMUs, fly the paper scenario.
use crate::workspace::{self, Workspace};
use crate::{fmus, system_packages};
use anyhow::Result;

/// The harness is built unoptimised, beside the FMUs' description binaries: the paper's
/// flights take seconds either way, and an optimised build of the harness alone would take
/// longer than everything else the demo does (`cargo build --release -p harness` is the
/// build for campaigns).
pub fn run(ws: &Workspace) -> Result<()> {
    system_packages::ensure(&system_packages::for_demo())?;
    fmus::package_all_with(ws, &["harness"])?;
    workspace::run(ws.cargo().args(["run", "-p", "harness", "--", "paper"]))
}
