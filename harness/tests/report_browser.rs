//! The reports in a real browser: headless Chromium renders a paper report and a small
//! Monte Carlo report at 1400x900 and 1000x800, takes screenshots (kept in
//! `target/report-screenshots/` to look at) and, on `report.html?check`, the page's own script
//! says whether the document is wider than the window. Skips, saying why, only when Chromium
//! is missing and cannot be installed.
use crate::common;

use common::harness;
use std::path::{Path, PathBuf};
use std::process::Command;

fn chromium() -> Option<PathBuf> {
    let find = || {
        ["chromium", "chromium-browser"]
            .into_iter()
            .find_map(|name| {
                Command::new("which")
                    .arg(name)
                    .output()
                    .ok()
                    .filter(|o| o.status.success())
                    .map(|o| PathBuf::from(String::from_utf8_lossy(&o.stdout).trim()))
            })
    };
    if let Some(path) = find() {
        return Some(path);
    }
    // Debian's package; apt-get works as root (the test machines) and fails otherwise.
    let installed = Command::new("apt-get")
        .args(["install", "-y", "chromium"])
        .env("DEBIAN_FRONTEND", "noninteractive")
        .output()
        .is_ok_and(|o| o.status.success());
    if installed {
        find()
    } else {
        None
    }
}

fn browser(chromium: &Path, size: (u32, u32), extra: &[&str], url: &str) -> std::process::Output {
    let profile = tempfile::tempdir().unwrap();
    Command::new(chromium)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--no-first-run",
        ])
        .arg(format!("--user-data-dir={}", profile.path().display()))
        .arg(format!("--window-size={},{}", size.0, size.1))
        .args(extra)
        .arg(url)
        .output()
        .unwrap()
}

#[test]
fn the_reports_fit_the_window_at_1400_and_1000_px() {
    let Some(chromium) = chromium() else {
        println!(
            "SKIPPED: no chromium on PATH and `apt-get install -y chromium` failed (not root, \
             or no package source): the reports were not rendered"
        );
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let paper = dir.path().join("paper");
    let mc = dir.path().join("mc");
    for args in [
        vec!["paper", "paper", "--out-dir", paper.to_str().unwrap()],
        vec![
            "monte-carlo",
            "-n",
            "3",
            "-q",
            "--out-dir",
            mc.to_str().unwrap(),
        ],
    ] {
        let output = harness(&args);
        assert!(matches!(output.status.code(), Some(0 | 3)), "{output:?}");
    }
    let shots = Path::new(env!("CARGO_TARGET_TMPDIR")).join("report-screenshots");
    std::fs::create_dir_all(&shots).unwrap();
    for (name, page) in [("paper", &paper), ("monte-carlo", &mc)] {
        let url = format!("file://{}", page.join("report.html").display());
        for size in [(1400, 900), (1000, 800)] {
            let png = shots.join(format!("{name}-{}x{}.png", size.0, size.1));
            let _ = std::fs::remove_file(&png);
            let output = browser(
                &chromium,
                size,
                &[&format!("--screenshot={}", png.display())],
                &url,
            );
            assert!(png.is_file(), "no screenshot {}: {output:?}", png.display());
            let output = browser(
                &chromium,
                size,
                &[
                    "--run-all-compositor-stages-before-draw",
                    "--virtual-time-budget=2000",
                    "--dump-dom",
                ],
                &format!("{url}?check"),
            );
            let dom = String::from_utf8_lossy(&output.stdout);
            let check = dom
                .split("<p id=\"overflow-check\">")
                .nth(1)
                .and_then(|rest| rest.split('<').next())
                .unwrap_or_else(|| panic!("{name} at {size:?}: no overflow check in the DOM"));
            println!(
                "{name} at {}x{}: {check} ({})",
                size.0,
                size.1,
                png.display()
            );
            assert!(
                check.ends_with("fits=true"),
                "{name} at {size:?} is wider than the window: {check}"
            );
        }
    }
}
