//! An interrupted campaign continued with `--resume`: killed part-way (SIGKILL, mid-run), the
//! last row cut as a kill mid-write would leave it, resumed; no flight is flown twice, none
//! is lost, and the manifest is the uninterrupted campaign's byte for byte. `--rerun` then
//! re-flies chosen flights to the same rows.
use crate::common;

use std::path::Path;
use std::process::{Command, Output};
use std::time::{Duration, Instant};

const CAMPAIGN: [&str; 8] = [
    "monte-carlo",
    "-n",
    "30",
    "--phi-cmd-deg",
    "0,150",
    "--law",
    "coupled,decoupled",
    "--no-plots",
];
const FLIGHTS: usize = 120;

fn harness(out_dir: &Path, extra: &[&str]) -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_harness"));
    command
        .arg("--fmu-dir")
        .arg(common::fmu_dir())
        .args(CAMPAIGN)
        .arg("--out-dir")
        .arg(out_dir)
        .args(["--workers", "2", "--quiet"])
        .args(extra);
    command
}

fn finished(output: Output) -> String {
    let text = String::from_utf8_lossy(&output.stdout).into_owned();
    // 3: flown, some flights outside the paper scenario's limits (they are results too).
    assert!(
        matches!(output.status.code(), Some(0 | 3)),
        "{text}{}",
        String::from_utf8_lossy(&output.stderr)
    );
    text
}

/// The number before `marker` in `text` (e.g. "17 flights flown").
fn count_before(text: &str, marker: &str) -> usize {
    let at = text
        .find(marker)
        .unwrap_or_else(|| panic!("no '{marker}' in {text}"));
    text[..at]
        .split_whitespace()
        .last()
        .unwrap()
        .parse()
        .unwrap()
}

fn data_lines(manifest: &Path) -> usize {
    std::fs::read_to_string(manifest)
        .map(|t| t.lines().count().saturating_sub(1))
        .unwrap_or(0)
}

#[test]
fn a_killed_campaign_resumes_without_flying_a_flight_twice_or_losing_one() {
    let dir = tempfile::tempdir().unwrap();
    let reference = dir.path().join("reference");
    finished(harness(&reference, &[]).output().unwrap());

    // GIVEN a campaign killed once it has written some rows, its last row cut short
    let interrupted = dir.path().join("interrupted");
    let manifest = interrupted.join("manifest.csv");
    let mut child = harness(&interrupted, &[]).spawn().unwrap();
    let started = Instant::now();
    while data_lines(&manifest) < 20 {
        assert!(started.elapsed() < Duration::from_secs(120), "no rows");
        assert!(
            child.try_wait().unwrap().is_none(),
            "finished before the kill"
        );
        std::thread::sleep(Duration::from_millis(5));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    let mut text = std::fs::read(&manifest).unwrap();
    let rows_left = data_lines(&manifest);
    assert!(rows_left < FLIGHTS, "killed after the end");
    text.truncate(text.len() - 7);
    std::fs::write(&manifest, &text).unwrap();

    // WHEN it is resumed
    let out = finished(harness(&interrupted, &["--resume"]).output().unwrap());

    // THEN the whole rows were kept, the cut one and the rest flown, each once
    let kept = count_before(&out, "flights kept");
    let flown = count_before(&out, "flights flown");
    assert_eq!(kept, rows_left - 1, "{out}");
    assert_eq!(kept + flown, FLIGHTS, "{out}");
    // AND the manifest is the uninterrupted one's, byte for byte
    let bytes = |d: &Path| std::fs::read(d.join("manifest.csv")).unwrap();
    assert_eq!(bytes(&interrupted), bytes(&reference));
    assert_eq!(
        std::fs::read(interrupted.join("summary.csv")).unwrap(),
        std::fs::read(reference.join("summary.csv")).unwrap()
    );

    // AND chosen flights re-flown by index replace their rows with the same ones
    let out = finished(
        harness(&interrupted, &["--resume", "--rerun", "3,117"])
            .output()
            .unwrap(),
    );
    assert_eq!(count_before(&out, "flights flown"), 2, "{out}");
    assert_eq!(bytes(&interrupted), bytes(&reference));
}

#[test]
fn resume_refuses_another_campaign_and_rerun_a_flight_outside_it() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("c");
    finished(harness(&out, &[]).output().unwrap());
    let other = harness(&out, &["--resume", "--seed", "9"])
        .output()
        .unwrap();
    assert_eq!(other.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&other.stderr).contains("another campaign"));
    let outside = harness(&out, &["--resume", "--rerun", "120"])
        .output()
        .unwrap();
    assert_eq!(outside.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&outside.stderr).contains("flights 120"));
}
