//! `harness paper` judges each law against the scenario's shipped limits: the law the
//! scenario flies must meet them (exit 3 otherwise); a comparison law's violation is the
//! comparison's finding, printed as such, and leaves the exit status alone.
use crate::common;

use common::harness;

fn paper_text() -> &'static str {
    lander::scenarios::BUILT_IN
        .iter()
        .find(|(name, _)| *name == "paper")
        .expect("the paper scenario is built in")
        .1
}

/// The lines of the summary that belong to one law (its verdict line and its requirements).
fn section<'a>(stdout: &'a str, law: &str) -> Vec<&'a str> {
    let mut lines = stdout
        .lines()
        .skip_while(|l| !l.starts_with(&format!("{law}: ")));
    let first = lines.next().into_iter();
    first
        .chain(lines.take_while(|l| l.starts_with("  ")))
        .collect()
}

#[test]
fn the_coupled_laws_deviation_is_the_comparisons_finding_not_a_failure() {
    let dir = tempfile::tempdir().unwrap();
    let output = harness(&[
        "paper",
        "--no-plots",
        "--out-dir",
        dir.path().to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert_eq!(output.status.code(), Some(0), "{stdout}");
    let coupled = section(&stdout, "coupled").join("\n");
    assert!(
        coupled.contains("requirement descent deviation: VIOLATED")
            && coupled.contains("[a comparison law: not the scenario's failure]"),
        "{coupled}"
    );
    let decoupled = section(&stdout, "decoupled").join("\n");
    assert_eq!(
        decoupled.matches(": holds (robustness").count(),
        3,
        "{decoupled}"
    );
}

#[test]
fn a_scenario_whose_own_law_breaks_a_limit_exits_3() {
    let dir = tempfile::tempdir().unwrap();
    let own_coupled = paper_text().replace("control_law = 2 ", "control_law = 1 ");
    assert_ne!(
        own_coupled,
        paper_text(),
        "the paper scenario sets control_law = 2"
    );
    let path = dir.path().join("paper-coupled.toml");
    std::fs::write(&path, own_coupled).unwrap();
    let out = dir.path().join("out");
    let output = harness(&[
        "paper",
        path.to_str().unwrap(),
        "--no-plots",
        "--out-dir",
        out.to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert_eq!(output.status.code(), Some(3), "{stdout}");
    let coupled = section(&stdout, "coupled").join("\n");
    assert!(
        coupled.contains("descent deviation: VIOLATED") && !coupled.contains("comparison law"),
        "{coupled}"
    );
}
