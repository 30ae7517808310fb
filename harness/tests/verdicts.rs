//! Verdicts of whole runs through the packaged FMUs and the `harness` binary: the exit code
//! says whether each run ended as its scenario expects, and a hard landing names its limits.
use crate::common;

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
    assert_eq!(code, lander::verdict::EXIT_FAILED_VERDICT, "{text}");
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
    assert_eq!(code, lander::verdict::EXIT_OK, "{text}");
    assert!(text.contains("landed inside the envelope"), "{text}");
    assert!(
        text.contains("vertical 1.0"),
        "commanded 1 m/s sink rate: {text}"
    );
}

#[test]
fn the_paper_scenario_completes_and_a_landing_it_does_not_expect_fails() {
    let (code, text) = harness(&["run", "paper", "-o", "r.csv"]);
    assert_eq!(code, lander::verdict::EXIT_OK, "{text}");
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
    assert_eq!(code, lander::verdict::EXIT_FAILED_VERDICT, "{text}");
    assert!(text.contains("landed inside the envelope"), "{text}");
    assert!(text.contains("expects: completed"), "{text}");
}

#[test]
fn a_run_that_cannot_start_is_an_error_not_a_failed_verdict() {
    let (code, text) = harness(&["run", "paper", "--set", "plant.m0=-5", "-o", "r.csv"]);
    assert_eq!(code, lander::verdict::EXIT_ERROR, "{text}");
}

/// The number after `key` in a verdict line (`vertical 1.87 m/s` -> 1.87).
fn number_after(text: &str, key: &str) -> f64 {
    let rest = &text[text
        .find(key)
        .unwrap_or_else(|| panic!("no {key:?} in {text}"))
        + key.len()..];
    rest.split_whitespace().next().unwrap().parse().unwrap()
}

#[test]
fn a_flaring_terminal_descent_cuts_the_engine_and_falls_the_last_metre() {
    // GIVEN the landing with a terminal descent from 2 m/s slowing to 0.5 m/s (10 s flare)
    // and the engine cut at 1 m (the plant's touchdown: the centre of mass at 0)
    let sets = [
        "gnc.terminal_descent_speed=2.0",
        "gnc.terminal_final_speed=0.5",
        "gnc.terminal_flare_time=10.0",
        "gnc.engine_cutoff_height=1.0",
    ];
    let mut args = vec!["run", "landing", "-o", "r.csv"];
    for set in &sets {
        args.extend(["--set", set]);
    }
    let (code, text) = harness(&args);
    // THEN it lands inside the envelope, sooner than at a constant 1 m/s (323.6 s)
    assert_eq!(code, lander::verdict::EXIT_OK, "{text}");
    let t = number_after(&text, "touchdown at t =");
    assert!(t > 250.0 && t < 290.0, "{text}");
    // AND at the free-fall speed from the cut-off, sqrt(0.5^2 + 2 g 1 m) = 1.87 m/s (the cut
    // comes at a 10 Hz guidance cycle, up to 5 cm lower: down to 1.84 m/s); without the cut
    // it would touch down at the final 0.5 m/s
    let vertical = number_after(&text, "vertical");
    assert!(vertical > 1.80 && vertical < 1.90, "{text}");
    let (code, text) = harness(&args[..args.len() - 2]);
    assert_eq!(code, lander::verdict::EXIT_OK, "{text}");
    let vertical = number_after(&text, "vertical");
    assert!((vertical - 0.5).abs() < 0.05, "{text}");
}
