//! Verdicts of whole runs through the packaged FMUs and the `harness` binary: the exit code
//! says whether each run ended as its scenario expects, and a hard landing names its limits.
mod common;

use std::process::Command;

fn harness(args: &[&str]) -> (i32, String) {
    let out_dir = tempfile::tempdir().unwrap();
    let output = Command::new(env!("CARGO_BIN_EXE_harness"))
        .arg("--fmu-dir")
        .arg(common::fmu_dir())
        .args(args)
        .current_dir(out_dir.path())
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&output.stdout).into_owned()
        + &String::from_utf8_lossy(&output.stderr);
    (output.status.code().unwrap(), text)
}

#[test]
fn a_heavy_lander_lands_hard_and_the_run_fails_naming_the_broken_limits() {
    // GIVEN the paper scenario with 100 kg more than the engines can brake in the descent
    // WHEN it is run
    let (code, text) = harness(&["run", "paper", "--set", "plant.m0=1000", "-o", "r.csv"]);
    // THEN the verdict is a hard landing, naming the vertical speed and the tilt
    assert_eq!(code, harness::verdict::EXIT_FAILED_VERDICT, "{text}");
    assert!(text.contains("HARD LANDING"), "{text}");
    assert!(
        text.contains("vertical speed") && text.contains("> 2.00 m/s"),
        "{text}"
    );
    assert!(
        text.contains("tilt") && text.contains("> 12.00 deg"),
        "{text}"
    );
}

#[test]
fn the_landing_scenario_touches_down_inside_the_envelope() {
    let (code, text) = harness(&["run", "landing", "-o", "r.csv"]);
    assert_eq!(code, harness::verdict::EXIT_OK, "{text}");
    assert!(text.contains("landed inside the envelope"), "{text}");
    assert!(
        text.contains("vertical 1.0"),
        "commanded 1 m/s sink rate: {text}"
    );
}

#[test]
fn the_paper_scenario_completes_and_a_landing_it_does_not_expect_fails() {
    let (code, text) = harness(&["run", "paper", "-o", "r.csv"]);
    assert_eq!(code, harness::verdict::EXIT_OK, "{text}");
    assert!(text.contains("verdict: completed"), "{text}");
    // the terminal descent switched on in a scenario expecting a hover: a soft landing at
    // ~150 s from a descent to 20 m, and still a failed run
    let (code, text) = harness(&[
        "run",
        "paper",
        "--set",
        "gnc.descent_target_nue[2]=20.0",
        "--set",
        "gnc.terminal_descent_speed=1.0",
        "--set",
        "gnc.target_hover_duration=0.0",
        "-o",
        "r.csv",
    ]);
    assert_eq!(code, harness::verdict::EXIT_FAILED_VERDICT, "{text}");
    assert!(text.contains("landed inside the envelope"), "{text}");
    assert!(text.contains("expects: completed"), "{text}");
}

#[test]
fn a_run_that_cannot_start_is_an_error_not_a_failed_verdict() {
    let (code, text) = harness(&["run", "paper", "--set", "plant.m0=-5", "-o", "r.csv"]);
    assert_eq!(code, harness::verdict::EXIT_ERROR, "{text}");
}
