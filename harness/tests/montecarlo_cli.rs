//! The monte-carlo command line: negative values without `=`, every bad range named at once
//! in a readable message, options that would be ignored refused.
use crate::common;

use std::process::Command;

use common::harness;

/// The stderr of a harness command that must exit 1 (a user's error).
fn refused(args: &[&str]) -> String {
    let output = harness(args);
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    assert_eq!(output.status.code(), Some(1), "{args:?}: {stderr}");
    stderr
}

#[test]
fn a_negative_phi_cmd_grid_needs_no_equals_sign() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().to_str().unwrap();
    let output = harness(&[
        "monte-carlo",
        "--phi-cmd-deg",
        "-30,0",
        "--phi-cmd-deg",
        "-10",
        "--law",
        "decoupled",
        "-n",
        "1",
        "--out-dir",
        out,
        "--quiet",
        "--no-plots",
    ]);
    assert!(output.status.success(), "{output:?}");
    let campaign = std::fs::read_to_string(dir.path().join("campaign.toml")).unwrap();
    assert!(
        campaign.contains("-30.0") && campaign.contains("-10.0"),
        "{campaign}"
    );
}

#[test]
fn bad_ranges_are_all_named_with_their_limits_in_short() {
    let dir = tempfile::tempdir().unwrap();
    let output = harness(&[
        "monte-carlo",
        "--disp-horizontal-m",
        "-3",
        "--disp-mass-frac",
        "-1",
        "--out-dir",
        dir.path().to_str().unwrap(),
    ]);
    assert_eq!(output.status.code(), Some(1));
    let text = String::from_utf8_lossy(&output.stderr);
    assert!(
        text.contains("--disp-horizontal-m -3: must be a finite number >= 0"),
        "{text}"
    );
    assert!(
        text.contains("--disp-mass-frac -1: must be in [0, 0.5]"),
        "{text}"
    );
    assert!(text.len() < 300, "{text}");
}

#[test]
fn replay_from_a_manifest_refuses_the_options_it_would_ignore() {
    for extra in [
        ["--law", "reduced"],
        ["--phi-cmd-deg", "30"],
        ["--disp-tilt-deg", "3"],
    ] {
        let mut args = vec!["replay", "--manifest", "x", "--index", "0"];
        args.extend(extra);
        let output = harness(&args);
        assert_eq!(output.status.code(), Some(2), "{extra:?}");
        let text = String::from_utf8_lossy(&output.stderr);
        assert!(
            text.contains("cannot be used with") && text.contains(extra[0]),
            "{text}"
        );
    }
}

/// A user's mistake is one readable message and exit code 1 even where the developer's
/// environment asks for backtraces.
#[test]
fn a_user_error_prints_no_backtrace_even_with_rust_backtrace_set() {
    for setting in ["1", "full"] {
        let output = Command::new(env!("CARGO_BIN_EXE_harness"))
            .args(["run", "/nonexistent/scenario.toml"])
            .env("RUST_BACKTRACE", setting)
            .env("RUST_LIB_BACKTRACE", setting)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(1), "{stderr}");
        assert!(stderr.starts_with("Error: "), "{stderr}");
        assert!(stderr.contains("/nonexistent/scenario.toml"), "{stderr}");
        assert!(
            !stderr.to_lowercase().contains("backtrace"),
            "RUST_BACKTRACE={setting}: {stderr}"
        );
    }
}

/// An output name that says another format than the one written is refused before the
/// flight, and nothing is written.
#[test]
fn an_output_name_that_is_no_result_format_is_refused_before_the_run() {
    let dir = tempfile::tempdir().unwrap();
    for (name, format, expected) in [
        ("run.parquet", None, ".parquet is not a result format"),
        ("run.csv", Some("arrow"), "--format arrow asks for Arrow"),
    ] {
        let out = dir.path().join(name);
        let mut args = vec!["run", "paper", "-o", out.to_str().unwrap()];
        if let Some(format) = format {
            args.extend(["--format", format]);
        }
        let stderr = refused(&args);
        assert!(stderr.contains(expected), "{stderr}");
        assert!(!out.exists(), "{name} was written");
    }
    let stderr = refused(&["report", dir.path().to_str().unwrap()]);
    assert!(stderr.contains("holds no results"), "{stderr}");
}

/// A phi_cmd outside LanderGnc's declared range is refused before any flight, in degrees,
/// by monte-carlo and by replay alike.
#[test]
fn a_phi_cmd_outside_its_declared_range_is_refused_in_degrees_before_any_flight() {
    let dir = tempfile::tempdir().unwrap();
    let out_dir = dir.path().join("mc");
    let stderr = refused(&[
        "monte-carlo",
        "--phi-cmd-deg",
        "1000,30",
        "-n",
        "1",
        "--out-dir",
        out_dir.to_str().unwrap(),
        "--quiet",
        "--no-plots",
    ]);
    assert!(
        stderr
            .contains("--phi-cmd-deg 1000: LanderGnc's phi_cmd is declared within -720 to 720 deg"),
        "{stderr}"
    );
    assert!(!out_dir.exists(), "the campaign wrote files");
    let csv = dir.path().join("replay.csv");
    let stderr = refused(&[
        "replay",
        "--seed",
        "1",
        "--run",
        "3",
        "--phi-cmd-deg",
        "1e6",
        "-o",
        csv.to_str().unwrap(),
    ]);
    assert!(stderr.contains("--phi-cmd-deg 1000000"), "{stderr}");
    assert!(!csv.exists());
}

/// A run that would record an absurd number of values is refused before it starts, with
/// its numbers (more in tests/bounded_memory.rs).
#[test]
fn a_step_too_small_to_record_is_refused_before_the_run() {
    let dir = tempfile::tempdir().unwrap();
    let scenario = dir.path().join("tiny-step.toml");
    let paper = lander::scenarios::BUILT_IN
        .iter()
        .find(|(name, _)| *name == "paper")
        .unwrap()
        .1;
    std::fs::write(
        &scenario,
        paper.replace("step_size = 0.01", "step_size = 1e-9"),
    )
    .unwrap();
    let out = dir.path().join("run.csv");
    let stderr = refused(&[
        "run",
        scenario.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(stderr.contains("1.720e11 communication points"), "{stderr}");
    assert!(stderr.contains("use a larger step_size"), "{stderr}");
    assert!(!out.exists());
}

/// A campaign whose rows could not be summarised in memory is refused before any flight,
/// with its numbers (flights, time, memory, manifest size, the largest -n that fits),
/// --force or not.
#[test]
fn a_campaign_too_large_to_summarise_is_refused_before_any_flight_with_the_estimate() {
    let dir = tempfile::tempdir().unwrap();
    let out_dir = dir.path().join("mc");
    let stderr = refused(&[
        "monte-carlo",
        "-n",
        "100000000",
        "--law",
        "coupled,decoupled,reduced",
        "--workers",
        "2",
        "--out-dir",
        out_dir.to_str().unwrap(),
        "--quiet",
        "--no-plots",
        "--force",
    ]);
    assert!(
        stderr.contains(
            "2100000000 flights (100000000 runs x 7 phi_cmd x 3 laws) would take about 627 \
             days on 2 workers (up to 17201 communication points a flight"
        ),
        "{stderr}"
    );
    assert!(stderr.contains("with --force or without"), "{stderr}");
    assert!(stderr.contains("bytes of memory"), "{stderr}");
    assert!(
        stderr.contains("manifest.csv would take about 1.680e12 bytes"),
        "{stderr}"
    );
    assert!(stderr.contains("flights fit (-n "), "{stderr}");
    assert!(!out_dir.exists(), "the refused campaign wrote files");
    // The largest count of all: no overflow, the same refusal.
    let stderr = refused(&[
        "monte-carlo",
        "-n",
        &u64::MAX.to_string(),
        "--out-dir",
        out_dir.to_str().unwrap(),
    ]);
    assert!(stderr.contains("too many for one campaign"), "{stderr}");
    assert!(!out_dir.exists());
}

/// More than 10,000,000 flights are refused before any flight with the estimate, unless
/// --force: then the campaign goes on (here to its FMU directory, which does not exist).
#[test]
fn a_campaign_over_the_flight_limit_is_refused_unless_forced() {
    let dir = tempfile::tempdir().unwrap();
    let out_dir = dir.path().join("mc");
    let out = out_dir.to_str().unwrap();
    let args = [
        "monte-carlo",
        "-n",
        "10000001",
        "--phi-cmd-deg",
        "150",
        "--law",
        "decoupled",
        "--workers",
        "2",
        "--out-dir",
        out,
        "--quiet",
    ];
    // 6 GB of rows to summarise: a machine with less memory refuses it either way.
    if cosim::memory::available_bytes().is_none_or(|a| a < 1e10) {
        return;
    }
    let stderr = refused(&args);
    assert!(
        stderr.contains(
            "10000001 flights (10000001 runs x 1 phi_cmd x 1 laws) would take about 3 days \
             on 2 workers"
        ),
        "{stderr}"
    );
    assert!(
        stderr.contains("manifest.csv would take about 8.000e9 bytes"),
        "{stderr}"
    );
    assert!(
        stderr.contains(
            "more than the 10000000 flights a campaign (or shard) flies without --force: \
             fewer runs (at most -n 10000000 with these points)"
        ),
        "{stderr}"
    );
    assert!(!out_dir.exists());
    // One shard of it is within the limit; so is the campaign with --force.
    let output = Command::new(env!("CARGO_BIN_EXE_harness"))
        .args(["--fmu-dir", "/nonexistent-fmus"])
        .args(args)
        .arg("--force")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(!stderr.contains("flights a campaign"), "{stderr}");
    assert!(stderr.contains("/nonexistent-fmus"), "{stderr}");
}

/// The campaign help names every built-in scenario and the file kinds a campaign takes.
#[test]
fn the_campaign_help_names_every_built_in_scenario() {
    let output = harness(&["monte-carlo", "--help"]);
    let help = String::from_utf8_lossy(&output.stdout);
    for (name, _) in lander::scenarios::BUILT_IN {
        assert!(help.contains(name), "{name} missing from: {help}");
    }
    assert!(help.contains(".ssp package"), "{help}");
}

/// A campaign path that does not exist is named as given.
#[test]
fn a_missing_campaign_path_is_named_as_given() {
    for args in [
        vec!["replay", "--manifest", "/nonexistent", "--index", "1"],
        vec!["merge-mc", "/nonexistent", "--out-dir", "/tmp/unused-merge"],
    ] {
        let stderr = refused(&args);
        assert!(
            stderr.contains("/nonexistent: no such file or directory"),
            "{args:?}: {stderr}"
        );
        assert!(!stderr.contains("/campaign.toml"), "{stderr}");
    }
}

/// One variable given two values by --set is refused, naming both, before the run.
#[test]
fn a_variable_set_twice_is_refused_naming_both_values() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("run.csv");
    let stderr = refused(&[
        "run",
        "paper",
        "-o",
        out.to_str().unwrap(),
        "--set",
        "gnc.phi_cmd=1",
        "--set",
        "gnc.phi_cmd=2",
    ]);
    assert!(
        stderr.contains("--set gnc.phi_cmd=2: gnc.phi_cmd is already set by --set gnc.phi_cmd=1"),
        "{stderr}"
    );
    assert!(!out.exists());
}

/// Every value refused before the run, and which of them came from the command line.
#[test]
fn bad_set_values_are_all_reported_before_the_run_naming_the_option() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("run.csv");
    let stderr = refused(&[
        "run",
        "paper",
        "-o",
        out.to_str().unwrap(),
        "--set",
        "gnc.control_law=7",
        "--set",
        "plant.m0=-5",
    ]);
    assert!(
        stderr.contains("'control_law' = 7 is above its declared max")
            && stderr.contains("(from --set gnc.control_law=7)"),
        "{stderr}"
    );
    assert!(
        stderr.contains("'m0' = -5 is below its declared min 5e-324 (from --set plant.m0=-5)"),
        "{stderr}"
    );
    assert!(!out.exists());
}

#[test]
fn set_moves_every_flights_nominal_is_recorded_and_replays_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let campaign = |out: &std::path::Path, extra: &[&str]| {
        let mut args = vec![
            "monte-carlo",
            "-n",
            "1",
            "--phi-cmd-deg",
            "150",
            "--law",
            "decoupled",
            "--no-plots",
            "-q",
            "--out-dir",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let output = harness(&args);
        assert_eq!(
            output.status.code(),
            Some(0),
            "{}",
            String::from_utf8_lossy(&output.stderr)
        );
        std::fs::read_to_string(out.join("manifest.csv")).unwrap()
    };
    // GIVEN the same one-flight campaign with and without a lighter lander
    let (with, without) = (dir.path().join("with"), dir.path().join("without"));
    let set = campaign(&with, &["--set", "plant.m0=850"]);
    let nominal = campaign(&without, &[]);
    // THEN the flight differs, and campaign.toml records the override
    assert_ne!(set.lines().nth(1), nominal.lines().nth(1));
    let toml = std::fs::read_to_string(with.join("campaign.toml")).unwrap();
    assert!(toml.contains(r#"sets = ["plant.m0=850"]"#), "{toml}");
    // AND a replay from the manifest applies it again: the metrics come back bit for bit
    let out = dir.path().join("replay.csv");
    let output = harness(&[
        "replay",
        "--manifest",
        with.to_str().unwrap(),
        "--index",
        "0",
        "-o",
        out.to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert_eq!(output.status.code(), Some(0), "{stdout}");
    assert!(
        stdout.contains("identical to the manifest's, bit for bit"),
        "{stdout}"
    );
    let first_mass = |csv: &str| -> String {
        let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
        let column = header.iter().position(|h| *h == "plant.mass").unwrap();
        csv.lines()
            .nth(1)
            .unwrap()
            .split(',')
            .nth(column)
            .unwrap()
            .to_owned()
    };
    // (the default dispersions move the mass by a few per cent around the new nominal)
    let mass: f64 = first_mass(&std::fs::read_to_string(&out).unwrap())
        .parse()
        .unwrap();
    assert!((mass - 850.0).abs() < 0.05 * 850.0, "{mass}");
    // AND what the campaign varies itself cannot be set
    let stderr = refused(&[
        "monte-carlo",
        "-n",
        "1",
        "--set",
        "gnc.phi_cmd=1",
        "--set",
        "gnc.control_law=1",
    ]);
    assert!(
        stderr.contains("the campaign flies the grid of --phi-cmd-deg"),
        "{stderr}"
    );
    assert!(
        stderr.contains("the campaign flies the laws of --law"),
        "{stderr}"
    );
}
