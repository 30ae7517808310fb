//! The release directory alone. `cargo xtask dist` writes `target/dist/lander-fmi-<version>/`;
//! copied to a temporary directory with no checkout beside it, its harness for each platform
//! (x86_64 Linux natively, aarch64 Linux under qemu-aarch64, x86_64 Windows under Wine) runs
//! from the release's own files: `harness run paper` finds the release's FMUs by itself
//! and writes the paper flight, which must be the same rows on every platform, and
//! `harness test fmi3` checks every FMI 3.0 FMU against the references it carries.
//!
//!     cargo xtask dist
//!     cargo test -p system-tests --test main release_directory:: -- --ignored --nocapture
//!
//! Under qemu the harness runs its FMUs in its own process (`--in-process`): its supervised
//! worker is the harness started again, which needs the kernel to run an aarch64 program
//! directly (binfmt_misc), and a test machine need not have that.
use crate::cross::{self, Platform};
use std::path::{Path, PathBuf};
use std::process::Output;
use system_tests::target_dir;

/// The one release `cargo xtask dist` wrote (`target/dist/lander-fmi-*`).
fn built_release() -> PathBuf {
    let dist = target_dir().join("dist");
    let found: Vec<PathBuf> = std::fs::read_dir(&dist)
        .unwrap_or_else(|e| panic!("{}: {e}: run `cargo xtask dist`", dist.display()))
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.join("SHA256SUMS").is_file())
        .collect();
    match found.as_slice() {
        [one] => one.clone(),
        [] => panic!("no release in {}: run `cargo xtask dist`", dist.display()),
        more => panic!("{} releases in {}: {more:?}", more.len(), dist.display()),
    }
}

fn copy_tree(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap() {
        let entry = entry.unwrap();
        let target = to.join(entry.file_name());
        if entry.file_type().unwrap().is_dir() {
            copy_tree(&entry.path(), &target);
        } else {
            std::fs::copy(entry.path(), &target).unwrap();
        }
    }
}

fn harness_of(release: &Path, platform: Platform) -> PathBuf {
    let (folder, file) = match platform {
        Platform::LinuxX86_64 => ("x86_64-linux", "harness"),
        Platform::LinuxAarch64 => ("aarch64-linux", "harness"),
        Platform::WindowsX86_64 => ("x86_64-windows", "harness.exe"),
    };
    release.join("bin").join(folder).join(file)
}

/// Runs the release's harness for `platform` in `dir` (its own working directory, with no
/// `target/fmu`), with `args`.
fn harness(release: &Path, platform: Platform, dir: &Path, args: &[&str]) -> Output {
    let mut all: Vec<String> = Vec::new();
    if platform == Platform::LinuxAarch64 {
        all.push("--in-process".into());
    }
    all.extend(args.iter().map(|a| a.to_string()));
    let program = harness_of(release, platform);
    let mut command = cross::command(platform, &program, &all);
    command.current_dir(dir).env_remove("LANDER_FMU_DIR");
    command
        .output()
        .unwrap_or_else(|e| panic!("cannot run {program:?} on {}: {e}", platform.name()))
}

fn assert_success(output: &Output, what: &str, platform: Platform) {
    assert!(
        output.status.success(),
        "{what} on {}: {}\nstdout:\n{}\nstderr:\n{}",
        platform.name(),
        output.status,
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
}

#[test]
#[ignore = "needs `cargo xtask dist`, qemu-user and Wine"]
fn an_unpacked_release_flies_the_paper_and_tests_its_fmus_on_every_platform() {
    let scratch = tempfile::tempdir().unwrap();
    let release = scratch.path().join("release");
    copy_tree(&built_release(), &release);
    for platform in Platform::ALL {
        cross::prepare(platform);
    }
    let flights: Vec<(Platform, String)> = std::thread::scope(|s| {
        let handles: Vec<_> = Platform::ALL
            .into_iter()
            .map(|platform| {
                let release = &release;
                let dir = scratch.path().join(format!("{platform:?}"));
                s.spawn(move || {
                    std::fs::create_dir_all(&dir).unwrap();
                    let run = harness(
                        release,
                        platform,
                        &dir,
                        &["run", "paper", "-o", "paper.csv"],
                    );
                    assert_success(&run, "harness run paper", platform);
                    // Relative, so that Wine reads it as it reads the working directory.
                    let tested = harness(release, platform, &dir, &["test", "../release/fmi3"]);
                    assert_success(&tested, "harness test fmi3", platform);
                    let rows = std::fs::read_to_string(dir.join("paper.csv")).unwrap();
                    (platform, rows)
                })
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    let (_, native) = &flights[0];
    assert!(
        native.lines().count() > 17_000,
        "the paper flight has 17,200 steps"
    );
    for (platform, rows) in &flights[1..] {
        let first = native.lines().zip(rows.lines()).position(|(a, b)| a != b);
        assert!(
            first.is_none() && native.lines().count() == rows.lines().count(),
            "the paper flight on {} differs from x86_64 Linux's at row {first:?}",
            platform.name()
        );
    }
}

/// The release ships the Python driver of `--dask` beside its harness, which finds it there:
/// a campaign flown from a copy of the release directory alone on a local Dask cluster (the
/// venv's dask), whose tasks carry the release's harness and FMUs.
#[test]
#[ignore = "needs `cargo xtask dist` and the venv of `cargo xtask python-env`"]
fn an_unpacked_release_flies_a_campaign_on_dask_with_its_own_driver() {
    let scratch = tempfile::tempdir().unwrap();
    let release = scratch.path().join("release");
    copy_tree(&built_release(), &release);
    assert!(
        release.join("python/harness_dask.py").is_file(),
        "the release has no python/harness_dask.py"
    );
    let python = system_tests::workspace_root().join(".venv/bin/python");
    let dir = scratch.path().join("run");
    std::fs::create_dir_all(&dir).unwrap();
    let program = harness_of(&release, Platform::LinuxX86_64);
    let output = std::process::Command::new(&program)
        .current_dir(&dir)
        .env_remove("LANDER_FMU_DIR")
        .env("HARNESS_PYTHON", &python)
        .args(["monte-carlo", "-n", "2", "--phi-cmd-deg", "150"])
        .args([
            "--law",
            "decoupled,coupled",
            "--no-plots",
            "--out-dir",
            "mc",
        ])
        .args(["--dask", "local:1"])
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        matches!(output.status.code(), Some(0 | 3)),
        "{}\n{stdout}{}",
        output.status,
        String::from_utf8_lossy(&output.stderr)
    );
    assert!(stdout.contains("4/4 flights"), "{stdout}");
    let manifest = std::fs::read_to_string(dir.join("mc/manifest.csv")).unwrap();
    assert_eq!(manifest.lines().count(), 5, "a header and four flights");
}
