//! `cargo xtask test`: every check, in order, stopping at the first failure.
use crate::workspace::{self, Workspace};
use crate::{fmus, python_env, system_packages};
use anyhow::Result;
use std::time::{Duration, Instant};

struct Stage {
    name: &'static str,
    run: fn(&Workspace) -> Result<()>,
}

const STAGES: [Stage; 9] = [
    // First: a missing C library otherwise fails deep inside a build script.
    Stage {
        name: "system packages",
        run: |_| {
            let (packages, architectures) = system_packages::for_test_all_platforms();
            system_packages::ensure_with_architectures(&packages, architectures)
        },
    },
    Stage {
        name: "rustfmt",
        run: |ws| workspace::run(ws.cargo().args(["fmt", "--all", "--", "--check"])),
    },
    Stage {
        name: "clippy",
        run: |ws| {
            workspace::run(ws.cargo().args([
                "clippy",
                "--workspace",
                "--all-targets",
                "--",
                "-D",
                "warnings",
            ]))
        },
    },
    // Every test binary, and with them the FMU crates' description binaries, which the
    // packaging below then uses as built here: one resolution of features for both.
    Stage {
        name: "build tests",
        run: |ws| workspace::run(ws.cargo().args(["test", "--workspace", "--no-run"])),
    },
    // Every platform, so that every later test loads the FMUs a release ships.
    Stage {
        name: "package FMUs",
        run: |ws| fmus::package_all_platforms(ws, fmus::Describers::FromTestBuild).map(|_| ()),
    },
    // Before the cargo tests: the fmpy system tests run in this venv.
    Stage {
        name: "python venv",
        run: python_env::ensure,
    },
    // Unit tests of every crate and the system tests (C ABI check, the `fmi` crate's
    // importer, the fmpy scripts), all against the FMUs packaged above.
    Stage {
        name: "cargo test",
        run: |ws| workspace::run(ws.cargo().args(["test", "--workspace"])),
    },
    // The foreign binaries as their platforms see them, natively, under qemu-aarch64 and
    // under wine: outside `cargo test --workspace` because a plain `cargo xtask fmus`
    // writes host-only FMUs.
    Stage {
        name: "platforms",
        run: |ws| {
            // `--workspace`, as the build above, so that nothing is compiled again for other
            // features; only system-tests has tests of these names.
            workspace::run(ws.cargo().args([
                "test",
                "--workspace",
                "--test",
                "main",
                "--",
                "--ignored",
                "all_platforms::",
                "same_bits::",
                "windows_users::",
            ]))?;
            // Kept to repeat a failed run by hand; a passed stage needs none of them.
            remove_trajectories(&ws.target_dir.join("cross-runs").join("runs"))
        },
    },
    // The release as a user unpacks it: its harness for every platform, run from a copy
    // of the release directory alone (natively, under qemu-aarch64, under Wine).
    Stage {
        name: "release",
        run: |ws| {
            crate::dist::run(ws)?;
            workspace::run(ws.cargo().args([
                "test",
                "--workspace",
                "--test",
                "main",
                "--",
                "--ignored",
                "release_directory::",
            ]))
        },
    },
];

pub fn run_all(ws: &Workspace) -> Result<()> {
    let started = Instant::now();
    let mut finished: Vec<(&str, Duration)> = Vec::new();
    for stage in &STAGES {
        println!("\n=== xtask test: {} ===", stage.name);
        let stage_started = Instant::now();
        let result = (stage.run)(ws);
        let elapsed = stage_started.elapsed();
        if let Err(error) = result {
            println!("\n=== xtask test: summary ===");
            print_timings(&finished);
            println!(
                "FAILED  {:<14} {:>8.1} s: {error:#}",
                stage.name,
                elapsed.as_secs_f64()
            );
            anyhow::bail!("stage `{}` failed", stage.name);
        }
        println!(
            "=== xtask test: {} passed in {:.1} s ===",
            stage.name,
            elapsed.as_secs_f64()
        );
        finished.push((stage.name, elapsed));
    }
    println!("\n=== xtask test: summary ===");
    print_timings(&finished);
    println!(
        "all {} stages passed in {:.1} s",
        STAGES.len(),
        started.elapsed().as_secs_f64()
    );
    Ok(())
}

/// The `.out` trajectories of the platform runs (about 0.7 GB); their plans and logs stay.
fn remove_trajectories(dir: &std::path::Path) -> Result<()> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Ok(());
    };
    for entry in entries {
        let path = entry?.path();
        if path.extension().is_some_and(|e| e == "out") {
            std::fs::remove_file(&path)?;
        }
    }
    Ok(())
}

fn print_timings(finished: &[(&str, Duration)]) {
    for (name, elapsed) in finished {
        println!("ok      {name:<14} {:>8.1} s", elapsed.as_secs_f64());
    }
}
