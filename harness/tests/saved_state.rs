//! `harness run --save-state FILE --save-at T` and `--from-state FILE`: the paper flight
//! saved at 80 s and continued in another harness process writes the uninterrupted
//! flight's rows from 80 s on, bit for bit, in FMI 2.0 and 3.0, and judges its verdict and
//! its requirements over the whole flight as the uninterrupted run does (the rows before
//! 80 s that the requirements read come from the file); files that cannot continue the run and
//! FMUs that cannot serialize their state are refused before the run, naming why, with no
//! backtrace.
use crate::common::{self, harness, workspace_root, zip_dir};
use std::path::{Path, PathBuf};

/// The paper scenario with the FMI 3.0 FMUs of the FMU directory, written into `dir`.
fn fmi3_paper(dir: &Path) -> PathBuf {
    let shipped =
        std::fs::read_to_string(workspace_root().join("harness/scenarios/paper.toml")).unwrap();
    let text = shipped
        .replace("\"LanderGnc.fmu\"", "\"fmi3/LanderGnc.fmu\"")
        .replace("\"LanderPlant.fmu\"", "\"fmi3/LanderPlant.fmu\"");
    assert_ne!(text, shipped);
    let path = dir.join("paper-fmi3.toml");
    std::fs::write(&path, text).unwrap();
    path
}

fn ok(output: &std::process::Output) -> String {
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    assert!(
        output.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&output.stderr)
    );
    stdout
}

/// The CSV's lines from the row of time `from` on (the header first).
fn rows_from(csv: &Path, from: &str) -> Vec<String> {
    let text = std::fs::read_to_string(csv).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().to_owned();
    let rows: Vec<String> = lines
        .skip_while(|line| line.split(',').next() != Some(from))
        .map(str::to_owned)
        .collect();
    assert!(
        !rows.is_empty(),
        "no row at t = {from} in {}",
        csv.display()
    );
    std::iter::once(header).chain(rows).collect()
}

/// Saves `scenario` at `at` s on an uninterrupted flight, continues it from the file in
/// another process, and compares.
fn continued_matches_uninterrupted(scenario: &str, dir: &Path, at: u32) {
    let whole = dir.join("whole.csv");
    let state = dir.join("paper.state");
    let continued = dir.join("continued.csv");
    let saved = ok(&harness(&[
        "run",
        scenario,
        "-o",
        whole.to_str().unwrap(),
        "--save-state",
        state.to_str().unwrap(),
        "--save-at",
        &at.to_string(),
    ]));
    assert!(
        saved.contains(&format!("saved the run at t = {at} s")),
        "{saved}"
    );
    let said = ok(&harness(&[
        "run",
        scenario,
        "-o",
        continued.to_str().unwrap(),
        "--from-state",
        state.to_str().unwrap(),
    ]));
    // CSV values are written shortest-round-trip: equal text is equal bits.
    let expected = rows_from(&whole, &format!("{at}.0"));
    let got: Vec<String> = std::fs::read_to_string(&continued)
        .unwrap()
        .lines()
        .map(str::to_owned)
        .collect();
    assert_eq!(got.len(), expected.len(), "{scenario}: rows from {at} s");
    assert_eq!(got, expected, "{scenario}: continued rows");
    assert!(
        said.contains("the requirements are judged over the whole flight"),
        "the continued run says what it judges: {said}"
    );
    // The verdict (the last row) and every requirement (robustness at the start, to the
    // millisecond and six digits) are the uninterrupted flight's.
    let judged = |text: &str| -> Vec<String> {
        text.lines()
            .filter(|l| l.starts_with("verdict:") || l.starts_with("requirement "))
            .map(str::to_owned)
            .collect()
    };
    assert!(judged(&said)[0].starts_with("verdict:"), "{said}");
    if scenario.contains("paper") {
        assert_eq!(
            judged(&said).len(),
            4,
            "the verdict and three requirements: {said}"
        );
    }
    assert_eq!(judged(&said), judged(&saved));
}

#[test]
fn the_paper_flight_continued_from_a_saved_state_is_bit_identical_in_fmi2() {
    let dir = tempfile::tempdir().unwrap();
    continued_matches_uninterrupted("paper", dir.path(), 80);
}

#[test]
fn the_paper_flight_continued_from_a_saved_state_is_bit_identical_in_fmi3() {
    let dir = tempfile::tempdir().unwrap();
    let scenario = fmi3_paper(dir.path());
    continued_matches_uninterrupted(scenario.to_str().unwrap(), dir.path(), 80);
}

#[test]
fn a_landing_continued_from_a_saved_state_touches_down_on_the_same_row() {
    // The run ends at touchdown (the plant terminates it between two points): the last
    // row, its time and the landing verdict are the uninterrupted flight's.
    let dir = tempfile::tempdir().unwrap();
    continued_matches_uninterrupted("landing", dir.path(), 50);
}

/// A refusal before the run: exit code 1, the words expected on stderr, no backtrace, no
/// results written.
#[test]
fn a_fault_due_at_the_saved_point_is_applied_once_by_the_continued_flight() {
    // GIVEN fault-engine, its engine fault due at 60 s, saved at 60 s (before the point's
    // exchange, so before the fault): the continued flight applies it, once, at 60 s, and
    // writes the uninterrupted flight's rows and verdicts
    // (to 80 s: the whole flight ends in a hard landing, exit code 1; to 80 s its
    // requirements over [12, 142] s are inconclusive, exit code 3, in both runs alike)
    let dir = tempfile::tempdir().unwrap();
    let (whole, state, continued) = (
        dir.path().join("whole.csv"),
        dir.path().join("fault.state"),
        dir.path().join("continued.csv"),
    );
    let run = |extra: &[&str], out: &Path| {
        let mut args = vec!["run", "fault-engine", "--stop-time", "80", "-o"];
        args.push(out.to_str().unwrap());
        args.extend_from_slice(extra);
        let output = harness(&args);
        let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
        (output.status.code(), stdout)
    };
    let (code, saved) = run(
        &["--save-state", state.to_str().unwrap(), "--save-at", "60"],
        &whole,
    );
    assert!(saved.contains("saved the run at t = 60 s"), "{saved}");
    let (continued_code, said) = run(&["--from-state", state.to_str().unwrap()], &continued);
    assert_eq!(
        (code, continued_code),
        (Some(3), Some(3)),
        "{saved}\n{said}"
    );
    // CSV values are written shortest-round-trip: equal text is equal bits.
    let got: Vec<String> = std::fs::read_to_string(&continued)
        .unwrap()
        .lines()
        .map(str::to_owned)
        .collect();
    assert_eq!(got, rows_from(&whole, "60.0"), "continued rows");
    let event = "event 'engine-degraded' (plant.engine_health = 0.93) due at 60 s: applied at 60 s";
    assert!(saved.contains(event) && said.contains(event), "{said}");
    // WHEN the fault is moved before the saved point THEN that scenario cannot continue the
    // file: its FMU states were saved without the fault
    let shipped =
        std::fs::read_to_string(workspace_root().join("harness/scenarios/fault-engine.toml"))
            .unwrap();
    let moved = shipped.replace("time = 60.0", "time = 40.0");
    assert_ne!(moved, shipped);
    let scenario = dir.path().join("fault-engine-40.toml");
    std::fs::write(&scenario, moved).unwrap();
    let out = dir.path().join("never.csv");
    refused(
        &[
            "run",
            scenario.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--from-state",
            state.to_str().unwrap(),
        ],
        &out,
        &[
            "fault.state",
            "the events before t = 60 s were none in the run saved",
            "'engine-degraded' (plant.engine_health = 0.93) due at 40 s",
        ],
    );
}

fn refused(args: &[&str], out: &Path, expected: &[&str]) {
    let output = harness(args);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    for words in expected {
        assert!(stderr.contains(words), "{words:?} in {stderr}");
    }
    assert!(
        !stderr.contains("panicked") && !stderr.contains("backtrace"),
        "{stderr}"
    );
    assert!(!out.exists(), "results written by a refused run");
    assert!(
        !String::from_utf8_lossy(&output.stdout).contains("rows"),
        "a refused run flew"
    );
}

#[test]
fn missing_damaged_and_foreign_state_files_are_refused_before_the_run() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("never.csv");
    let out_arg = out.to_str().unwrap();
    let missing = dir.path().join("missing.state");
    refused(
        &[
            "run",
            "paper",
            "-o",
            out_arg,
            "--from-state",
            missing.to_str().unwrap(),
        ],
        &out,
        &["--from-state", "missing.state", "cannot read the saved run"],
    );

    let results = dir.path().join("results.csv");
    std::fs::write(&results, "time,plant.mass\n0.0,900.0\n").unwrap();
    refused(
        &[
            "run",
            "paper",
            "-o",
            out_arg,
            "--from-state",
            results.to_str().unwrap(),
        ],
        &out,
        &["results.csv is not a saved run"],
    );

    // A state of the FMI 2.0 flight, continued with the FMI 3.0 FMUs or another scenario.
    let state = dir.path().join("fmi2.state");
    // (Its requirements are inconclusive over 1 s: the exit code says so, not the save.)
    let short = harness(&[
        "run",
        "paper",
        "--stop-time",
        "1",
        "-o",
        dir.path().join("short.csv").to_str().unwrap(),
        "--save-state",
        state.to_str().unwrap(),
    ]);
    assert!(
        String::from_utf8_lossy(&short.stdout).contains("saved the run at t = 1 s"),
        "{}",
        String::from_utf8_lossy(&short.stderr)
    );
    let mut damaged = std::fs::read(&state).unwrap();
    let last = damaged.len() - 1;
    damaged[last] ^= 0x40;
    let damaged_path = dir.path().join("damaged.state");
    std::fs::write(&damaged_path, damaged).unwrap();
    refused(
        &[
            "run",
            "paper",
            "-o",
            out_arg,
            "--from-state",
            damaged_path.to_str().unwrap(),
        ],
        &out,
        &["damaged.state", "checksum"],
    );
    let fmi3 = fmi3_paper(dir.path());
    refused(
        &[
            "run",
            fmi3.to_str().unwrap(),
            "--stop-time",
            "1",
            "-o",
            out_arg,
            "--from-state",
            state.to_str().unwrap(),
        ],
        &out,
        &[
            "--from-state",
            "fmi2.state",
            "instance 'gnc'",
            "FMI 2.0",
            "FMI 3.0",
        ],
    );
    refused(
        &[
            "run",
            "upright",
            "-o",
            out_arg,
            "--from-state",
            state.to_str().unwrap(),
        ],
        &out,
        &["fmi2.state", "saved from system 'paper'"],
    );
}

#[test]
fn an_fmu_that_cannot_serialize_its_state_is_refused_with_the_reason() {
    // GIVEN the paper scenario beside a LanderPlant whose description says it cannot
    // serialize its state (its binary could: the harness must believe the description)
    let dir = tempfile::tempdir().unwrap();
    let unpacked = dir.path().join("plant");
    common::unzip_to(&common::fmu_dir().join("LanderPlant.fmu"), &unpacked);
    let description = unpacked.join("modelDescription.xml");
    let text = std::fs::read_to_string(&description).unwrap();
    assert!(text.contains("canSerializeFMUstate=\"true\""));
    std::fs::write(
        &description,
        text.replace(
            "canSerializeFMUstate=\"true\"",
            "canSerializeFMUstate=\"false\"",
        ),
    )
    .unwrap();
    zip_dir(&unpacked, &dir.path().join("LanderPlant.fmu"));
    let scenario = dir.path().join("paper.toml");
    std::fs::copy(
        workspace_root().join("harness/scenarios/paper.toml"),
        &scenario,
    )
    .unwrap();
    // WHEN its run is asked to save THEN it is refused before flying, naming plant and flag
    let out = dir.path().join("never.csv");
    let state = dir.path().join("never.state");
    refused(
        &[
            "run",
            scenario.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--save-state",
            state.to_str().unwrap(),
        ],
        &out,
        &[
            "--save-state",
            "instance 'plant'",
            "canSerializeFMUstate",
            "cannot be serialized",
        ],
    );
    assert!(!state.exists());
}

#[test]
fn a_run_that_ends_before_its_save_point_says_nothing_was_saved() {
    // The landing ends at touchdown, long before its stop time of 400 s.
    let dir = tempfile::tempdir().unwrap();
    let state = dir.path().join("late.state");
    let output = harness(&[
        "run",
        "landing",
        "-o",
        dir.path().join("landing.csv").to_str().unwrap(),
        "--save-state",
        state.to_str().unwrap(),
        "--save-at",
        "399",
    ]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("nothing saved"), "{stderr}");
    assert!(stderr.contains("terminated it"), "{stderr}");
    assert!(!state.exists());
}
