//! `harness run` streams its rows to the results file: the file is the one written from a
//! trajectory held in memory, byte for byte, and memory does not grow with the run's
//! length (shown under `ulimit -v`). A run too large to record is refused before it
//! starts with its estimate; `--force` goes on.
use crate::common;

use common::{fmu_dir, harness};
use std::path::Path;
use std::process::Command;

/// The paper scenario's TOML with `stop_time` replaced.
fn paper_until(stop_time: &str) -> String {
    let paper = lander::scenarios::BUILT_IN
        .iter()
        .find(|(name, _)| *name == "paper")
        .unwrap()
        .1;
    assert!(paper.contains("stop_time = 172.0"));
    paper.replace("stop_time = 172.0", &format!("stop_time = {stop_time}"))
}

/// The stderr of a harness command that must exit 1 (an error, not a usage error).
fn refused(args: &[&str]) -> String {
    let output = harness(args);
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    assert_eq!(output.status.code(), Some(1), "{args:?}: {stderr}");
    stderr
}

#[test]
fn the_streamed_results_are_the_in_memory_trajectorys_byte_for_byte() {
    let dir = tempfile::tempdir().unwrap();
    // The trajectory as `harness run` recorded it before it streamed: all in memory.
    let (mut system, _) = lander::scenarios::spec::load("paper").unwrap();
    let requirements = lander::scenarios::spec::requirements("paper").unwrap();
    if let Some(list) = system.record.as_mut() {
        cosim::requirements::record_signals(list, &requirements);
    }
    let mut simulation = cosim::master::Simulation::new(system, &fmu_dir()).unwrap();
    let mut trajectory = cosim::master::Trajectory {
        names: simulation.column_names().to_vec(),
        ..Default::default()
    };
    simulation.run(&mut trajectory).unwrap();
    assert_eq!(trajectory.len(), 17201);
    for format in [cosim::results::Format::Csv, cosim::results::Format::Arrow] {
        let ext = format.extension();
        let expected = dir.path().join(format!("memory.{ext}"));
        cosim::results::write_typed(
            &expected,
            &trajectory,
            simulation.column_units(),
            &simulation.column_types(),
            format,
        )
        .unwrap();
        let streamed = dir.path().join(format!("run.{ext}"));
        let output = harness(&["run", "paper", "-o", streamed.to_str().unwrap()]);
        assert_eq!(output.status.code(), Some(0), "{output:?}");
        assert!(
            std::fs::read(&expected).unwrap() == std::fs::read(&streamed).unwrap(),
            "{ext}: the streamed file differs from results::write of the trajectory"
        );
        assert!(!Path::new(&format!("{}.partial", streamed.display())).exists());
    }
}

/// Runs `harness run SCENARIO -o OUT` under `ulimit -v KIB`; its exit code (None: killed).
fn run_limited(kib: u64, scenario: &Path, out: &Path) -> Option<i32> {
    let command = format!(
        "ulimit -v {kib}; exec \"$0\" --fmu-dir \"$1\" run \"$2\" --set plant.isp=1000 -o \"$3\""
    );
    Command::new("bash")
        .arg("-c")
        .arg(command)
        .arg(env!("CARGO_BIN_EXE_harness"))
        .arg(fmu_dir())
        .arg(scenario)
        .arg(out)
        .env("RUST_BACKTRACE", "0")
        .output()
        .unwrap()
        .status
        .code()
}

/// The same address-space limit holds a run and one ten times as long (the paper scenario
/// to 172 s and to 1720 s, its propellant made to last with `plant.isp = 1000`): 80 MiB,
/// less than the long run's trajectory alone would take in memory (172,001 rows of 67
/// values, 92 MB), so that run could not pass by holding its rows.
#[test]
fn memory_does_not_grow_with_the_run_under_ulimit() {
    const LIMIT_KIB: u64 = 80 * 1024;
    assert!(172_001.0 * 67.0 * 8.0 > (LIMIT_KIB * 1024) as f64);
    let dir = tempfile::tempdir().unwrap();
    for (stop_time, rows) in [("172.0", 17_201), ("1720.0", 172_001)] {
        let scenario = dir.path().join(format!("paper-{stop_time}.toml"));
        std::fs::write(&scenario, paper_until(stop_time)).unwrap();
        let out = dir.path().join(format!("run-{stop_time}.csv"));
        let code = run_limited(LIMIT_KIB, &scenario, &out);
        // A verdict or requirement may fail (3); the run must not abort.
        assert!(
            matches!(code, Some(0 | 3)),
            "stop_time {stop_time}: exit {code:?}"
        );
        let text = std::fs::read_to_string(&out).unwrap();
        assert_eq!(text.lines().count(), rows + 1, "stop_time {stop_time}");
        assert!(text
            .lines()
            .last()
            .unwrap()
            .starts_with(stop_time.trim_end_matches(".0")));
    }
}

/// A 1e-9 s step over 172 s is refused before the run with its estimate (exit 1); a run
/// over the limit goes on with --force (its stop time is far, it ends at touchdown).
#[test]
fn a_run_too_large_to_record_is_refused_with_its_estimate_unless_forced() {
    let dir = tempfile::tempdir().unwrap();
    let tiny = dir.path().join("tiny-step.toml");
    std::fs::write(
        &tiny,
        paper_until("172.0").replace("step_size = 0.01", "step_size = 1e-9"),
    )
    .unwrap();
    let out = dir.path().join("run.csv");
    let out = out.to_str().unwrap();
    // The paper scenario records every output of its FMUs, and the time.
    let columns =
        1 + cosim::master::Simulation::new(lander::scenarios::load("paper").unwrap(), &fmu_dir())
            .unwrap()
            .column_names()
            .len();
    let values = 1.72e11 * columns as f64;
    let stderr = refused(&["run", tiny.to_str().unwrap(), "-o", out]);
    assert!(
        stderr.contains(&format!(
            "172 s in steps of 0.000000001 s is 1.720e11 communication points; recording \
             {columns} columns of each is {values:.3e} values, about "
        )),
        "{stderr}"
    );
    assert!(
        stderr.contains("bytes of CSV, beyond the 1e9 values one run may record without --force"),
        "{stderr}"
    );
    assert!(stderr.contains("give --force to run it anyway"), "{stderr}");
    // A CSV value is its decimal digits and a separator, an Arrow value 8 bytes.
    let bytes = |stderr: &str, format: &str| -> f64 {
        stderr
            .split(&format!(" bytes of {format}"))
            .next()
            .and_then(|head| head.rsplit(' ').next())
            .and_then(|x| x.parse().ok())
            .unwrap_or_else(|| panic!("no {format} size in: {stderr}"))
    };
    let per_value = bytes(&stderr, "CSV") / values;
    assert!(
        (10.0..25.0).contains(&per_value),
        "{per_value} bytes per CSV value"
    );
    let arrow = dir.path().join("run.arrow");
    let stderr = refused(&["run", tiny.to_str().unwrap(), "-o", arrow.to_str().unwrap()]);
    let per_value = bytes(&stderr, "Arrow") / values;
    assert!(
        (per_value - 8.0).abs() < 0.01,
        "{per_value} bytes per Arrow value"
    );
    if cosim::memory::available_bytes().is_some() {
        // --force cannot make the requirements' 172 s of rows fit.
        let stderr = refused(&["run", tiny.to_str().unwrap(), "-o", out, "--force"]);
        assert!(
            stderr.contains("6.880e12 bytes of memory")
                && stderr.contains("with --force or without"),
            "{stderr}"
        );
    }
    assert!(!Path::new(out).exists());

    let far = dir.path().join("far.toml");
    std::fs::write(&far, paper_until("1e6")).unwrap();
    let stderr = refused(&["run", far.to_str().unwrap(), "-o", out]);
    assert!(stderr.contains("1.000e8 communication points"), "{stderr}");
    assert!(!Path::new(out).exists());
    let output = harness(&["run", far.to_str().unwrap(), "-o", out, "--force"]);
    let stdout = String::from_utf8_lossy(&output.stdout);
    // Out of propellant, it comes down hard: flown, its verdict failed.
    assert_eq!(output.status.code(), Some(3), "{output:?}");
    assert!(
        stdout.contains(&format!("paper: 75016 rows x {columns} columns")),
        "{stdout}"
    );
}
