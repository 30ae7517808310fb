//! A campaign judges every flight by its scenario's `[[requirement]]` entries too: a flight
//! that wanders beyond a stated limit has not ended as expected, whatever its verdict.
use crate::common;

use common::harness;

/// The paper scenario with one requirement appended.
fn paper_with(dir: &std::path::Path, formula: &str) -> String {
    let paper = lander::scenarios::BUILT_IN
        .iter()
        .find(|(name, _)| *name == "paper")
        .unwrap()
        .1;
    let path = dir.join("paper-limit.toml");
    std::fs::write(
        &path,
        format!(
            "{paper}\n[[requirement]]\nname = \"descent within 20 m\"\nformula = \"{formula}\"\n"
        ),
    )
    .unwrap();
    path.to_str().unwrap().to_owned()
}

/// The paper scenario ships its limits: a campaign over it fails exactly the flights whose
/// descent leaves the 10 m corridor (and says which requirement), passes the others on it.
#[test]
fn flights_beyond_the_shipped_deviation_limit_fail_and_the_others_pass() {
    let dir = tempfile::tempdir().unwrap();
    let out_dir = dir.path().join("mc");
    let output = harness(&[
        "monte-carlo",
        "--scenario",
        "paper",
        "-n",
        "20",
        "--phi-cmd-deg",
        "150",
        "--law",
        "coupled,decoupled",
        "--out-dir",
        out_dir.to_str().unwrap(),
        "--quiet",
        "--no-plots",
    ]);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert_eq!(output.status.code(), Some(3), "{stdout}");
    let rows = campaign::manifest::read(&out_dir.join("manifest.csv")).unwrap();
    assert_eq!(rows.len(), 40);
    // The requirement and the descent metric measure the same excursion (the metric over
    // the descent phase's samples, the requirement over its time window): they agree away
    // from the limit.
    let (mut failed, mut passed) = (0, 0);
    for row in &rows {
        let deviation = row.metrics.max_horizontal_deviation_descent_m;
        let violated = row.verdict.detail.contains("descent deviation: VIOLATED");
        if deviation > 10.5 {
            assert!(
                violated && !row.verdict.as_expected,
                "{deviation} m: {:?}",
                row.verdict
            );
            failed += 1;
        } else if deviation < 9.5 {
            assert!(!violated, "{deviation} m: {:?}", row.verdict);
            passed += 1;
        }
    }
    assert!(failed > 0 && passed > 0, "{failed} failed, {passed} passed");
    assert!(
        stdout.contains("did not end as the scenario expects (completes without touchdown or error, meeting its 3 requirements)"),
        "{stdout}"
    );
}

#[test]
fn a_campaign_requirement_on_a_signal_nobody_outputs_is_refused_before_any_flight() {
    let dir = tempfile::tempdir().unwrap();
    let scenario = paper_with(dir.path(), "always [0, 10] plant.altitude_m > 0");
    let out_dir = dir.path().join("mc");
    let output = harness(&[
        "monte-carlo",
        "--scenario",
        &scenario,
        "-n",
        "1",
        "--out-dir",
        out_dir.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("plant.altitude_m"), "{stderr}");
    assert!(!out_dir.join("manifest.csv").exists());
}
