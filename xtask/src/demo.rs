//! `cargo xtask demo`: install what the plots need, package the FMUs, fly the paper scenario.
use crate::workspace::{self, Workspace};
use crate::{fmus, system_packages};
use anyhow::Result;

pub fn run(ws: &Workspace) -> Result<()> {
    system_packages::ensure(&system_packages::for_demo())?;
    fmus::package_all(ws)?;
    workspace::run(
        ws.cargo()
            .args(["run", "--release", "-p", "harness", "--", "paper"]),
    )
}
