//! `cargo xtask demo`: package the FMUs, then run the demonstration job.
use crate::fmus;
use crate::workspace::{self, Workspace};
use anyhow::Result;

/// The job run after packaging. The harness's closed-loop master is wired here once it has
/// a binary; until then the command is only printed.
pub fn run(ws: &Workspace) -> Result<()> {
    fmus::package_all(ws)?;
    let harness = ws.root.join("harness");
    let has_binary =
        harness.join("src").join("main.rs").is_file() || harness.join("src").join("bin").is_dir();
    let mut job = ws.cargo();
    job.args(["run", "--release", "-p", "harness", "--", "paper"]);
    if has_binary {
        workspace::run(&mut job)
    } else {
        println!(
            "xtask demo: the harness has no binary yet; once it has, this runs: {}",
            workspace::describe(&job)
        );
        Ok(())
    }
}
