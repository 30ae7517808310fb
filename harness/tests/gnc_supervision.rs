//! LanderGnc's supervision (input-consistency monitor and feasibility checks) raises nothing
//! on the project's own plant: not on the full-fidelity flight (sensors, filter, slosh,
//! thrusters, terrain), nor on any of 100 dispersed paper flights, judged by a requirement on
//! its `monitor_status`; and the same campaign with a wrong `gravity` fails that requirement
//! on every flight, so the requirement does watch the monitor.
use crate::common;

use common::harness;

const REQUIREMENT: &str = "GNC inputs consistent";

/// Built-in scenario `name` with `edit` applied and the requirement that LanderGnc's
/// supervision found nothing from 0 to `stop_s` (the scenario's stop time), written to `dir`.
fn scenario_with_monitor(
    dir: &std::path::Path,
    name: &str,
    stop_s: u32,
    edit: impl Fn(&str) -> String,
) -> String {
    let text = lander::scenarios::BUILT_IN
        .iter()
        .find(|(built_in, _)| *built_in == name)
        .unwrap_or_else(|| panic!("no built-in scenario {name}"))
        .1;
    let path = dir.join(format!("{name}-monitored.toml"));
    std::fs::write(
        &path,
        format!(
            "{}\n[[requirement]]\nname = \"{REQUIREMENT}\"\nformula = \"always [0, {stop_s}] gnc.monitor_status <= 0\"\n",
            edit(text)
        ),
    )
    .unwrap();
    path.to_str().unwrap().to_owned()
}

/// 25 runs x phi_cmd 0 and 150 deg x coupled and decoupled: the flights whose rows say the
/// requirement was violated, and the number of flights.
fn campaign(scenario: &str, out_dir: &std::path::Path, runs: &str) -> (usize, usize) {
    let output = harness(&[
        "monte-carlo",
        "--scenario",
        scenario,
        "-n",
        runs,
        "--phi-cmd-deg",
        "0,150",
        "--law",
        "coupled,decoupled",
        "--out-dir",
        out_dir.to_str().unwrap(),
        "--quiet",
        "--no-plots",
    ]);
    // 0: all flights as expected; 3: some failed a requirement. Never an error.
    assert!(
        matches!(output.status.code(), Some(0 | 3)),
        "{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
    let rows = campaign::manifest::read(&out_dir.join("manifest.csv")).unwrap();
    // A flight that errored or was cut short before its window ended was never judged: it
    // must not count as one that raised nothing.
    for row in &rows {
        assert_ne!(row.verdict.word, "error", "{:?}", row.verdict);
        assert!(
            !row.verdict
                .detail
                .contains(&format!("{REQUIREMENT}: INCONCLUSIVE")),
            "{:?}",
            row.verdict
        );
    }
    let violated = rows
        .iter()
        .filter(|row| {
            row.verdict
                .detail
                .contains(&format!("{REQUIREMENT}: VIOLATED"))
        })
        .count();
    (violated, rows.len())
}

#[test]
fn a_hundred_dispersed_paper_flights_raise_nothing_and_a_wrong_gravity_is_caught_in_each() {
    let dir = tempfile::tempdir().unwrap();
    let nominal = scenario_with_monitor(dir.path(), "paper", 172, str::to_owned);
    let (violated, flights) = campaign(&nominal, &dir.path().join("nominal"), "25");
    assert_eq!(flights, 100);
    assert_eq!(
        violated, 0,
        "the monitor raised on {violated} of 100 flights"
    );

    // the control: the same flights with the GNC's gravity the Earth's
    let earth = scenario_with_monitor(dir.path(), "paper", 172, |text| {
        text.replacen(
            "phi_cmd_time = 0.0",
            "phi_cmd_time = 0.0\ngravity = 9.81",
            1,
        )
    });
    let (violated, flights) = campaign(&earth, &dir.path().join("earth"), "1");
    assert_eq!(flights, 4);
    assert_eq!(violated, 4);
}

#[test]
fn the_full_fidelity_flight_raises_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let scenario = scenario_with_monitor(dir.path(), "full-fidelity", 300, str::to_owned);
    let out = dir.path().join("full-fidelity.csv");
    let output = harness(&["run", &scenario, "--out", out.to_str().unwrap()]);
    let stdout = String::from_utf8_lossy(&output.stdout);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stdout.contains(&format!("requirement {REQUIREMENT}: holds")),
        "{stdout}{stderr}"
    );
    assert!(!stderr.contains("input monitor"), "{stderr}");
}
