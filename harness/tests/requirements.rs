//! `[[requirement]]` entries of a scenario: judged after the run with their robustness,
//! part of the exit code, written as JUnit XML; a bad one refused before the run.
use crate::common;

use std::path::Path;

use common::harness;

/// The landing scenario (it lands at 323.61 s) with these requirements appended.
fn landing_with(dir: &Path, requirements: &[(&str, &str)]) -> String {
    let text: String = requirements
        .iter()
        .map(|(name, formula)| {
            format!("\n[[requirement]]\nname = \"{name}\"\nformula = \"{formula}\"\n")
        })
        .collect();
    landing_with_text(dir, &text)
}

/// The landing scenario with `requirements` (TOML) appended.
fn landing_with_text(dir: &Path, requirements: &str) -> String {
    let landing = lander::scenarios::BUILT_IN
        .iter()
        .find(|(name, _)| *name == "landing")
        .unwrap()
        .1;
    let path = dir.join("landing-requirements.toml");
    std::fs::write(&path, format!("{landing}{requirements}")).unwrap();
    path.to_str().unwrap().to_owned()
}

/// What a CI system reads of a JUnit report.
#[derive(serde::Deserialize)]
struct TestSuites {
    #[serde(rename = "@tests")]
    tests: usize,
    #[serde(rename = "@failures")]
    failures: usize,
    #[serde(rename = "@errors")]
    errors: usize,
    testsuite: Vec<TestSuite>,
}

#[derive(serde::Deserialize)]
struct TestSuite {
    #[serde(rename = "@name")]
    name: String,
    testcase: Vec<TestCase>,
}

#[derive(serde::Deserialize)]
struct TestCase {
    #[serde(rename = "@name")]
    name: String,
    #[serde(rename = "@time")]
    time: f64,
    failure: Option<Failure>,
    error: Option<Failure>,
}

#[derive(serde::Deserialize)]
struct Failure {
    #[serde(rename = "@message")]
    message: String,
}

#[test]
fn a_violated_requirement_fails_the_run_with_its_robustness_and_in_the_junit_report() {
    let dir = tempfile::tempdir().unwrap();
    let scenario = landing_with(
        dir.path(),
        &[
            ("above 700 m", "always [0, 100] plant.r_nue[2] > 700"),
            ("above ground", "always [0, 300] plant.r_nue[2] > -0.01"),
        ],
    );
    let junit = dir.path().join("reports/junit.xml");
    let out = dir.path().join("run.csv");
    let output = harness(&[
        "run",
        &scenario,
        "-o",
        out.to_str().unwrap(),
        "--junit",
        junit.to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert_eq!(output.status.code(), Some(3), "{stdout}");
    // The altitude at t = 100 s is 276.7 m: 423.3 m short of 700 m.
    assert!(
        stdout.contains("requirement above 700 m: VIOLATED (robustness -4.23"),
        "{stdout}"
    );
    assert!(stdout.contains("at t = 100 s"), "{stdout}");
    assert!(
        stdout.contains("requirement above ground: holds (robustness +"),
        "{stdout}"
    );
    assert!(stdout.contains("landed inside the envelope"), "{stdout}");

    let report: TestSuites =
        serde_xml_rs::from_str(&std::fs::read_to_string(&junit).unwrap()).unwrap();
    assert_eq!((report.tests, report.failures, report.errors), (3, 1, 0));
    let suite = &report.testsuite[0];
    let names: Vec<&str> = suite.testcase.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(names, ["verdict", "above 700 m", "above ground"]);
    assert!(suite.testcase[0].failure.is_none());
    // The run's time is the verdict's.
    assert!(suite.testcase[0].time > 0.0);
    let failure = suite.testcase[1]
        .failure
        .as_ref()
        .expect("the violated one fails");
    assert!(
        failure.message.contains("robustness -4.23"),
        "{}",
        failure.message
    );
    assert!(suite.testcase[2].failure.is_none());
}

#[test]
fn requirements_that_hold_leave_the_exit_code_of_the_verdict() {
    let dir = tempfile::tempdir().unwrap();
    let scenario = landing_with(
        dir.path(),
        &[
            ("above ground", "always [0, 300] plant.r_nue[2] > -0.01"),
            ("descends", "eventually [0, 320] plant.r_nue[2] < 10"),
        ],
    );
    let out = dir.path().join("run.csv");
    let output = harness(&["run", &scenario, "-o", out.to_str().unwrap()]);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert_eq!(output.status.code(), Some(0), "{stdout}");
    assert_eq!(
        stdout.matches(": holds (robustness +").count(),
        2,
        "{stdout}"
    );
}

#[test]
fn a_bad_requirement_is_refused_before_the_run_naming_it_and_the_position() {
    let dir = tempfile::tempdir().unwrap();
    let scenario = landing_with(
        dir.path(),
        &[
            ("typo", "always [0, 100 plant.r_nue[2] > 700"),
            ("unknown signal", "always [0, 10] plant.altitude_m > 0"),
        ],
    );
    let out = dir.path().join("run.csv");
    let output = harness(&["run", &scenario, "-o", out.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("requirement 1 (\"typo\"): formula \"always [0, 100 plant.r_nue[2] > 700\" at character 16: expected \"]\""),
        "{stderr}"
    );
    assert!(!out.exists(), "refused before the run");

    let scenario = landing_with(
        dir.path(),
        &[("unknown signal", "always [0, 10] plant.altitude_m > 0")],
    );
    let output = harness(&["run", &scenario, "-o", out.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains(
            "requirement \"unknown signal\": formula \"always [0, 10] plant.altitude_m > 0\" at \
             character 16: plant.altitude_m is not a recorded signal"
        ),
        "{stderr}"
    );
    assert!(!out.exists(), "refused before the run");
}

#[test]
fn harness_test_runs_every_scenario_of_a_folder_into_one_junit_report() {
    let dir = tempfile::tempdir().unwrap();
    let scenarios = dir.path().join("scenarios");
    std::fs::create_dir(&scenarios).unwrap();
    let built_in = |name: &str| {
        lander::scenarios::BUILT_IN
            .iter()
            .find(|(n, _)| *n == name)
            .unwrap()
            .1
    };
    std::fs::write(scenarios.join("a-upright.toml"), built_in("upright")).unwrap();
    let landing = landing_with(
        dir.path(),
        &[("above ground", "always [0, 300] plant.r_nue[2] > -0.01")],
    );
    std::fs::copy(&landing, scenarios.join("b-landing.toml")).unwrap();
    std::fs::write(scenarios.join("notes.txt"), "not a scenario").unwrap();
    let junit = dir.path().join("junit.xml");
    let out_dir = dir.path().join("out");
    let run = |junit: &Path| {
        harness(&[
            "test",
            scenarios.to_str().unwrap(),
            "--junit",
            junit.to_str().unwrap(),
            "--out-dir",
            out_dir.to_str().unwrap(),
        ])
    };
    let output = run(&junit);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert_eq!(output.status.code(), Some(0), "{stdout}");
    assert!(
        stdout.contains("2 scenarios: 2 passed, 0 failed, 0 could not be run"),
        "{stdout}"
    );
    let report: TestSuites =
        serde_xml_rs::from_str(&std::fs::read_to_string(&junit).unwrap()).unwrap();
    assert_eq!((report.tests, report.failures, report.errors), (3, 0, 0));
    let names: Vec<&str> = report.testsuite.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(names, ["a-upright", "b-landing"]);
    assert!(out_dir.join("a-upright.csv").exists() && out_dir.join("b-landing.csv").exists());

    // A violated requirement fails its scenario (3); one that cannot be run makes it 1.
    let violated = landing_with(
        dir.path(),
        &[("above 700 m", "always [0, 100] plant.r_nue[2] > 700")],
    );
    std::fs::copy(&violated, scenarios.join("b-landing.toml")).unwrap();
    let output = run(&junit);
    assert_eq!(output.status.code(), Some(3));
    std::fs::write(scenarios.join("c-broken.toml"), "name = \"broken\"\n").unwrap();
    let output = run(&junit);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert_eq!(output.status.code(), Some(1), "{stdout}");
    assert!(
        stdout.contains("3 scenarios: 1 passed, 1 failed, 1 could not be run"),
        "{stdout}"
    );
    let report: TestSuites =
        serde_xml_rs::from_str(&std::fs::read_to_string(&junit).unwrap()).unwrap();
    // The violated requirement is a failure, the scenario that could not be run an error.
    assert_eq!((report.tests, report.failures, report.errors), (4, 1, 1));
    let broken = &report.testsuite[2];
    assert_eq!(broken.name, "c-broken");
    assert!(broken.testcase[0].failure.is_none());
    assert!(broken.testcase[0]
        .error
        .as_ref()
        .is_some_and(|f| f.message.contains("could not be run")));

    // AND `harness report` on the results gives one page with a table per run, the violated
    // requirement and the scenario that could not be run marked.
    let output = harness(&["report", out_dir.to_str().unwrap()]);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let html = std::fs::read_to_string(out_dir.join("report.html")).unwrap();
    assert!(html.contains("Verdicts: 3 runs, 1 passed"), "{html}");
    for name in ["a-upright", "b-landing", "c-broken"] {
        assert!(html.contains(&format!("<h3>{name}</h3>")), "{name}");
    }
    let violated_row = html.lines().find(|l| l.contains("above 700 m")).unwrap();
    assert!(
        violated_row.starts_with("<tr class=\"fail\">") && violated_row.contains("VIOLATED"),
        "{violated_row}"
    );
}

/// A window past the touchdown at 323.61 s: inconclusive, failing, for `always` and
/// `eventually` alike, unless the requirement accepts an early end; a window the flight
/// covers is judged as before.
#[test]
fn a_window_past_the_end_of_the_run_is_inconclusive_unless_an_early_end_is_accepted() {
    let dir = tempfile::tempdir().unwrap();
    let junit = dir.path().join("junit.xml");
    let out = dir.path().join("run.csv");
    let run = |scenario: &str| {
        let output = harness(&[
            "run",
            scenario,
            "-o",
            out.to_str().unwrap(),
            "--junit",
            junit.to_str().unwrap(),
        ]);
        let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
        let report: TestSuites =
            serde_xml_rs::from_str(&std::fs::read_to_string(&junit).unwrap()).unwrap();
        (output.status.code(), stdout, report)
    };
    let requirements = |early_end: &str| {
        format!(
            "\n[[requirement]]\nname = \"above ground\"\nformula = \"always [0, 400] \
             plant.r_nue[2] > -0.01\"\n{early_end}\n[[requirement]]\nname = \"climbs \
             back\"\nformula = \"eventually [0, 400] plant.r_nue[2] > 2000\"\n{early_end}"
        )
    };
    let (code, stdout, report) = run(&landing_with_text(dir.path(), &requirements("")));
    assert_eq!(code, Some(3), "{stdout}");
    for name in ["above ground", "climbs back"] {
        assert!(
            stdout.contains(&format!(
                "requirement {name}: INCONCLUSIVE (window [0, 400] s, run ended at 323.609 s:"
            )),
            "{stdout}"
        );
    }
    assert_eq!((report.tests, report.failures), (3, 2));
    assert!(report.testsuite[0].testcase[1]
        .failure
        .as_ref()
        .is_some_and(|f| f.message.contains("INCONCLUSIVE (window [0, 400] s")));

    // Accepted: judged over the flight, which stays above ground and never climbs back.
    let accepted = landing_with_text(dir.path(), &requirements("early_end = \"accept\"\n"));
    let (code, stdout, report) = run(&accepted);
    assert_eq!(code, Some(3), "{stdout}");
    assert!(
        stdout.contains("requirement above ground: holds (robustness +"),
        "{stdout}"
    );
    assert!(
        stdout.contains("requirement climbs back: VIOLATED (robustness -"),
        "{stdout}"
    );
    assert_eq!((report.tests, report.failures), (3, 1));
}
