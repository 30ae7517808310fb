//! The small commands: `harness vars FMU` (an FMU's variables as a user wires them) and
//! `harness completions SHELL`.
use crate::common;

use common::harness;

#[test]
fn vars_lists_the_declared_variables_and_filters_by_causality() {
    let output = harness(&["vars", "LanderPlant.fmu", "--causality", "input"]);
    assert_eq!(output.status.code(), Some(0));
    let stdout = String::from_utf8_lossy(&output.stdout);
    let lines: Vec<&str> = stdout.lines().collect();
    assert_eq!(
        lines[0],
        "name\tcausality\tvariability\ttype\tstart\tunit\tdescription"
    );
    assert!(
        lines
            .iter()
            .any(|l| l.starts_with("thrust_cmd\tinput\tcontinuous\tReal\t0\tN\t")),
        "{stdout}"
    );
    assert!(
        lines[1..]
            .iter()
            .all(|l| l.split('\t').nth(1) == Some("input")),
        "{stdout}"
    );
    // All causalities: the parameters with their start values and units too.
    let all = String::from_utf8_lossy(&harness(&["vars", "LanderPlant.fmu"]).stdout).into_owned();
    assert!(
        all.contains("m0\tparameter\tfixed\tReal\t900\tkg\t"),
        "{all}"
    );
    assert!(all.lines().count() > lines.len());

    let bad = harness(&["vars", "LanderPlant.fmu", "--causality", "outputs"]);
    assert_eq!(bad.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("--causality outputs: not a causality"));
    let missing = harness(&["vars", "nosuch.fmu"]);
    assert_eq!(missing.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&missing.stderr).contains("loading nosuch.fmu"));
}

#[test]
fn the_completion_scripts_know_every_command() {
    for shell in ["bash", "zsh", "fish"] {
        let output = harness(&["completions", shell]);
        assert_eq!(output.status.code(), Some(0), "{shell}");
        let script = String::from_utf8_lossy(&output.stdout);
        for command in [
            "run",
            "paper",
            "monte-carlo",
            "merge-mc",
            "replay",
            "report",
            "test",
            "vars",
        ] {
            assert!(script.contains(command), "{shell} script lacks {command}");
        }
    }
    assert_eq!(
        harness(&["completions", "tcsh"]).status.code(),
        Some(2),
        "a usage error"
    );
}
