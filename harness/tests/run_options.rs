//! `harness run --stop-time/--step-size` and `harness paper --set`: the options change what
//! is flown, and bad values are refused before anything runs, all at once, exit code 1.
mod common;

use common::harness;

#[test]
fn stop_time_and_step_size_override_the_scenario() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("short.csv");
    let output = harness(&[
        "run",
        "paper",
        "--stop-time",
        "5",
        "--step-size",
        "0.02",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let csv = std::fs::read_to_string(&out).unwrap();
    let times: Vec<&str> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').next().unwrap())
        .collect();
    // 5 s in steps of 0.02 s: 251 rows, from 0 to 5 s
    assert_eq!(times.len(), 251);
    assert_eq!((times[1], *times.last().unwrap()), ("0.02", "5.0"));
}

#[test]
fn bad_stop_time_and_step_size_are_refused_together_before_the_run() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("never.csv");
    let output = harness(&[
        "run",
        "paper",
        "--stop-time",
        "-5",
        "--step-size",
        "0",
        "-o",
        out.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("step_size must be a positive number, got 0"),
        "{stderr}"
    );
    assert!(
        stderr.contains("stop_time (-5) must be after start_time (0)"),
        "{stderr}"
    );
    assert!(!out.exists());
}

#[test]
fn paper_applies_set_to_every_law_and_refuses_the_law_it_varies() {
    // GIVEN the paper command with the start altitude changed, for 1 s
    let dir = tempfile::tempdir().unwrap();
    let scenario = dir.path().join("short.toml");
    let text =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/scenarios/paper.toml"))
            .unwrap()
            .replace("stop_time = 172.0", "stop_time = 1.0");
    // the paper scenario's requirements read up to 172 s; a 1 s flight only needs the runs
    let text = text.split("[[requirement]]").next().unwrap().to_owned();
    std::fs::write(&scenario, text).unwrap();
    let out_dir = dir.path().join("paper");
    let output = harness(&[
        "paper",
        scenario.to_str().unwrap(),
        "--set",
        "plant.r0_nue[2]=600",
        "--no-plots",
        "--out-dir",
        out_dir.to_str().unwrap(),
    ]);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    // THEN every law's flight starts at 600 m
    let mut flights = 0;
    for entry in std::fs::read_dir(&out_dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "csv") && path.to_string_lossy().contains("-") {
            let csv = std::fs::read_to_string(&path).unwrap();
            let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
            let column = header.iter().position(|h| *h == "plant.r_nue[2]");
            let Some(column) = column else { continue };
            let first: Vec<&str> = csv.lines().nth(1).unwrap().split(',').collect();
            assert_eq!(first[column], "600.0", "{}", path.display());
            flights += 1;
        }
    }
    assert_eq!(flights, 3, "one trajectory per law");
    // AND setting the law it varies is refused, with the other problems, exit 1
    let output = harness(&[
        "paper",
        scenario.to_str().unwrap(),
        "--set",
        "gnc.control_law=1",
        "--set",
        "nosuch.x=1",
        "--no-plots",
        "--out-dir",
        out_dir.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("this command sets gnc.control_law itself"),
        "{stderr}"
    );
    assert!(
        stderr.contains("--set nosuch.x=1: no instance 'nosuch'"),
        "{stderr}"
    );
}
