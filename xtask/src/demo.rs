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
    // The binary just built, not `cargo run -p harness`: that resolves the features of the
    // harness alone, unlike the build beside the FMUs, and would compile it again.
    let harness = ws.target_dir.join("debug").join("harness");
    workspace::run(
        std::process::Command::new(harness)
            .arg("paper")
            .current_dir(&ws.root),
    )
}
