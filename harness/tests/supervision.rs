//! The harness outlives the FMUs it runs: an FMU built here to crash, exit, abort, hang or
//! allocate without bound, in each kind of FMI call, ends its run with an error verdict
//! naming the instance, the function and the time, exit code 1, the rows recorded until then
//! kept (partial), the JUnit report written, and no temporary directory left behind.
use crate::common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use tempfile::TempDir;

const DESCRIPTION: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="2.0" modelName="Faulty" guid="{faulty}">
  <CoSimulation modelIdentifier="Faulty"/>
  <ModelVariables>
    <ScalarVariable name="y" valueReference="0" causality="output" variability="continuous">
      <Real/>
    </ScalarVariable>
    <ScalarVariable name="u" valueReference="1" causality="input" variability="continuous">
      <Real start="0"/>
    </ScalarVariable>
    <ScalarVariable name="k" valueReference="2" causality="parameter" variability="tunable">
      <Real start="1"/>
    </ScalarVariable>
  </ModelVariables>
  <ModelStructure>
    <Outputs><Unknown index="1" dependencies=""/></Outputs>
  </ModelStructure>
</fmiModelDescription>
"#;

/// `fixtures/faulty_fmu.c` compiled into an unpacked FMU directory.
struct Faulty {
    temp: TempDir,
}

impl Faulty {
    fn build() -> Self {
        let temp = TempDir::new().unwrap();
        let dir = temp.path().join("Faulty");
        let binaries = dir.join("binaries").join("linux64");
        std::fs::create_dir_all(&binaries).unwrap();
        std::fs::write(dir.join("modelDescription.xml"), DESCRIPTION).unwrap();
        let source = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/faulty_fmu.c");
        // The FMI 2.0 types every C fixture shares live beside the importer's stub FMU.
        let types = common::workspace_root().join("fmi-import/tests/fixtures");
        let compiler = std::env::var("CC").unwrap_or_else(|_| "cc".to_owned());
        let output = Command::new(&compiler)
            .args([
                "-shared", "-fPIC", "-std=c99", "-Wall", "-Wextra", "-Werror", "-o",
            ])
            .arg(binaries.join("Faulty.so"))
            .arg("-I")
            .arg(&types)
            .arg(&source)
            .output()
            .unwrap_or_else(|e| panic!("cannot run the C compiler `{compiler}`: {e}"));
        assert!(
            output.status.success(),
            "compiling {} failed:\n{}",
            source.display(),
            String::from_utf8_lossy(&output.stderr)
        );
        Self { temp }
    }

    fn dir(&self) -> PathBuf {
        self.temp.path().join("Faulty")
    }

    /// A scenario of the faulty FMU alone, 1 s in steps of 0.1 s, with a requirement.
    fn scenario(&self, folder: &Path, name: &str) -> PathBuf {
        let path = folder.join(format!("{name}.toml"));
        std::fs::write(
            &path,
            format!(
                "name = \"{name}\"\nstop_time = 1.0\nstep_size = 0.1\n\n[[instance]]\nname = \
                 \"faulty\"\nfmu = \"{}\"\nparameters = {{ k = 2.0 }}\n\n[[requirement]]\nname = \"y bounded\"\nformula = \
                 \"always [0, 1] faulty.y <= 2\"\n",
                self.dir().display()
            ),
        )
        .unwrap();
        path
    }
}

impl Faulty {
    /// The paper's scenario with the faulty FMU as a third instance, connected to nothing.
    fn paper_with_it(&self, folder: &Path) -> PathBuf {
        let paper = lander::scenarios::BUILT_IN
            .iter()
            .find(|(name, _)| *name == "paper")
            .unwrap()
            .1;
        let path = folder.join("paper-faulty.toml");
        let instance = format!(
            "\n[[instance]]\nname = \"faulty\"\nfmu = \"{}\"\n",
            self.dir().display()
        );
        let at = paper.find("[[instance]]").unwrap();
        std::fs::write(
            &path,
            format!("{}{instance}\n{}", &paper[..at], &paper[at..]),
        )
        .unwrap();
        path
    }
}

/// `harness ARGS` with the fault in the environment and TMPDIR pointing at `tmp`.
fn harness_with(fault: &[(&str, &str)], tmp: &Path, args: &[&str]) -> Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_harness"));
    command
        .args(args)
        .env("RUST_BACKTRACE", "0")
        .env("TMPDIR", tmp)
        .env_remove("FAULTY_FMU_FAULT");
    for (key, value) in fault {
        command.env(key, value);
    }
    command.output().unwrap()
}

fn text(output: &Output) -> String {
    format!(
        "status {:?}\nstdout:\n{}\nstderr:\n{}",
        output.status,
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    )
}

fn assert_nothing_left_in(tmp: &Path) {
    let left: Vec<_> = std::fs::read_dir(tmp)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    assert!(left.is_empty(), "left in the temporary directory: {left:?}");
}

/// One faulty run through `harness run --junit`: its exit code is 1, its verdict an error
/// naming the call, and it leaves nothing in the temporary directory. Returns the output and
/// the paths of the results and the JUnit report.
fn run_faulty(fault: &str, call: &str, time: &str, extra: &[&str]) -> (String, PathBuf, PathBuf) {
    let faulty = Faulty::build();
    let work = TempDir::new().unwrap();
    let tmp = TempDir::new().unwrap();
    let scenario = faulty.scenario(work.path(), "faulty");
    let out = work.path().join("out.csv");
    let junit = work.path().join("junit.xml");
    let mut args = vec![
        "run",
        scenario.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--junit",
        junit.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let output = harness_with(
        &[
            ("FAULTY_FMU_FAULT", fault),
            ("FAULTY_FMU_CALL", call),
            ("FAULTY_FMU_TIME", time),
        ],
        tmp.path(),
        &args,
    );
    let said = text(&output);
    assert_eq!(output.status.code(), Some(1), "{said}");
    assert!(!said.contains("panicked"), "{said}");
    // An error verdict after the run started, or the error that stopped it before.
    assert!(
        said.contains("verdict: error") || said.contains("Error: "),
        "{said}"
    );
    assert!(
        said.contains(&format!("instance 'faulty' did not return from {call}")),
        "{said}"
    );
    assert!(!out.exists(), "a failed run has no complete results file");
    let junit_text = std::fs::read_to_string(&junit).unwrap_or_else(|e| panic!("{e}: {said}"));
    assert!(junit_text.contains("errors=\"1\""), "{junit_text}");
    assert!(junit_text.contains("<error"), "{junit_text}");
    assert!(junit_text.contains(call), "{junit_text}");
    assert_nothing_left_in(tmp.path());
    // The results were in the work directory: keep them for the caller.
    let kept = work.keep();
    (said, kept.join("out.csv"), kept.join("junit.xml"))
}

#[test]
fn a_crash_in_each_kind_of_call_is_an_error_verdict_naming_it() {
    for call in [
        "fmi2Instantiate",
        "fmi2SetupExperiment",
        "fmi2EnterInitializationMode",
        "fmi2ExitInitializationMode",
        "fmi2SetReal",
        "fmi2GetReal",
        "fmi2DoStep",
        "fmi2Terminate",
    ] {
        let (said, _, _) = run_faulty("segv", call, "0", &[]);
        assert!(said.contains("SIGSEGV"), "{call}: {said}");
    }
}

#[test]
fn a_crash_mid_run_keeps_the_rows_recorded_before_it_and_names_the_time() {
    let (said, out, _) = run_faulty("segv", "fmi2DoStep", "0.45", &[]);
    let partial = std::fs::read_to_string(out.with_extension("csv.partial")).unwrap();
    let times: Vec<f64> = partial
        .lines()
        .skip(1)
        .map(|l| l.split(',').next().unwrap().parse().unwrap())
        .collect();
    assert_eq!(times.len(), 6, "rows at 0, 0.1, ..., 0.5: {partial}");
    assert!((times[5] - 0.5).abs() < 1e-9, "{partial}");
    // The step that crashed starts at the last row's time.
    assert!(said.contains(&format!("at t = {} s", times[5])), "{said}");
}

#[test]
fn exit_and_abort_from_fmu_code_are_errors_never_success() {
    for (fault, how) in [
        ("exit0", "exited with status 0"),
        ("exit1", "exited with status 1"),
        ("abort", "SIGABRT"),
    ] {
        let (said, _, _) = run_faulty(fault, "fmi2DoStep", "0.25", &[]);
        assert!(said.contains(how), "{fault}: {said}");
        assert!(said.contains("at t = 0.3"), "{fault}: {said}");
    }
}

#[test]
fn a_call_that_never_returns_is_killed_after_the_call_timeout() {
    for call in ["fmi2DoStep", "fmi2GetReal"] {
        let started = std::time::Instant::now();
        let (said, _, _) = run_faulty("hang", call, "0.2", &["--call-timeout", "1"]);
        assert!(said.contains("call timeout"), "{said}");
        assert!(
            started.elapsed().as_secs_f64() < 30.0,
            "a 1 s call timeout ended the run after {:?}",
            started.elapsed()
        );
    }
}

#[test]
fn the_whole_run_limit_ends_a_run_whose_calls_each_return() {
    // Each step returns at once, but the run may not take 1 ms.
    let faulty = Faulty::build();
    let work = TempDir::new().unwrap();
    let tmp = TempDir::new().unwrap();
    let scenario = faulty.scenario(work.path(), "long");
    let text_of = |args: &[&str]| {
        let output = harness_with(&[], tmp.path(), args);
        (output.status.code(), text(&output))
    };
    let out = work.path().join("long.csv");
    let (code, said) = text_of(&[
        "run",
        scenario.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--stop-time",
        "100000",
        "--run-timeout",
        "0.5",
    ]);
    assert_eq!(code, Some(1), "{said}");
    assert!(said.contains("run timeout"), "{said}");
    assert_nothing_left_in(tmp.path());
}

#[test]
fn an_allocation_without_bound_ends_at_the_memory_limit() {
    let (said, _, _) = run_faulty("alloc", "fmi2DoStep", "0.2", &["--memory-limit", "300"]);
    assert!(said.contains("memory limit is 300 MB"), "{said}");
}

#[test]
fn what_an_fmu_prints_to_stdout_does_not_break_the_run() {
    let faulty = Faulty::build();
    let work = TempDir::new().unwrap();
    let tmp = TempDir::new().unwrap();
    let scenario = faulty.scenario(work.path(), "chatty");
    let out = work.path().join("chatty.csv");
    let output = harness_with(
        &[("FAULTY_FMU_PRINT", "hello from the FMU")],
        tmp.path(),
        &[
            "run",
            scenario.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ],
    );
    let said = text(&output);
    assert_eq!(output.status.code(), Some(0), "{said}");
    assert_eq!(std::fs::read_to_string(&out).unwrap().lines().count(), 12);
    assert!(said.contains("hello from the FMU"), "{said}");
    assert_nothing_left_in(tmp.path());
}

#[test]
fn harness_test_reports_a_crashed_scenario_as_an_error_and_runs_the_others() {
    let faulty = Faulty::build();
    let scenarios = TempDir::new().unwrap();
    let work = TempDir::new().unwrap();
    let tmp = TempDir::new().unwrap();
    faulty.scenario(scenarios.path(), "a-crashes");
    std::fs::write(
        scenarios.path().join("b-fine.toml"),
        format!(
            "name = \"b-fine\"\nstop_time = 1.0\nstep_size = 0.1\n\n[[instance]]\nname = \
             \"other\"\nfmu = \"{}\"\n",
            faulty.dir().display()
        ),
    )
    .unwrap();
    let junit = work.path().join("junit.xml");
    // Only the instance named `faulty` is in a crashing run: the fault strikes by instance
    // name through FAULTY_FMU_CALL at fmi2DoStep, so `other` would crash too; strike in run 1
    // only, counted across processes.
    let counter = work.path().join("counter");
    let output = harness_with(
        &[
            ("FAULTY_FMU_FAULT", "segv"),
            ("FAULTY_FMU_CALL", "fmi2DoStep"),
            ("FAULTY_FMU_TIME", "0.5"),
            ("FAULTY_FMU_RUNS", "1"),
            ("FAULTY_FMU_COUNTER", counter.to_str().unwrap()),
        ],
        tmp.path(),
        &[
            "test",
            scenarios.path().to_str().unwrap(),
            "--junit",
            junit.to_str().unwrap(),
            "--out-dir",
            work.path().join("out").to_str().unwrap(),
        ],
    );
    let said = text(&output);
    assert_eq!(output.status.code(), Some(1), "{said}");
    let report = std::fs::read_to_string(&junit).unwrap();
    assert!(report.contains("errors=\"1\""), "{report}");
    assert!(report.contains("name=\"a-crashes\""), "{report}");
    assert!(report.contains("name=\"b-fine\""), "{report}");
    assert!(report.contains("SIGSEGV"), "{report}");
    assert!(said.contains("1 could not be run"), "{said}");
    assert_nothing_left_in(tmp.path());
}

#[test]
fn in_process_runs_remain_for_debugging_and_give_the_same_rows() {
    let faulty = Faulty::build();
    let work = TempDir::new().unwrap();
    let tmp = TempDir::new().unwrap();
    let scenario = faulty.scenario(work.path(), "same");
    let supervised = work.path().join("supervised.csv");
    let in_process = work.path().join("in-process.csv");
    for (out, flag) in [(&supervised, None), (&in_process, Some("--in-process"))] {
        let mut args = vec![
            "run",
            scenario.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ];
        args.extend(flag);
        let output = harness_with(&[], tmp.path(), &args);
        assert_eq!(output.status.code(), Some(0), "{}", text(&output));
    }
    assert_eq!(
        std::fs::read(&supervised).unwrap(),
        std::fs::read(&in_process).unwrap()
    );
}

#[test]
fn a_campaign_records_a_crashed_flight_as_an_error_and_completes_the_others() {
    let faulty = Faulty::build();
    let work = TempDir::new().unwrap();
    let tmp = TempDir::new().unwrap();
    // The paper's descent with a third instance that crashes in the second flight only.
    let scenario = faulty.paper_with_it(work.path());
    let out = work.path().join("campaign");
    let counter = work.path().join("counter");
    let output = harness_with(
        &[
            ("FAULTY_FMU_FAULT", "segv"),
            ("FAULTY_FMU_CALL", "fmi2DoStep"),
            ("FAULTY_FMU_TIME", "20"),
            ("FAULTY_FMU_RUNS", "2"),
            ("FAULTY_FMU_COUNTER", counter.to_str().unwrap()),
        ],
        tmp.path(),
        &[
            "--fmu-dir",
            common::fmu_dir().to_str().unwrap(),
            "monte-carlo",
            "--scenario",
            scenario.to_str().unwrap(),
            "--runs",
            "3",
            "--law",
            "decoupled",
            "--phi-cmd-deg",
            "0",
            "--workers",
            "1",
            "--no-plots",
            "--out-dir",
            out.to_str().unwrap(),
        ],
    );
    let said = text(&output);
    assert_eq!(output.status.code(), Some(1), "{said}");
    let manifest = std::fs::read_to_string(out.join("manifest.csv")).unwrap();
    let rows: Vec<&str> = manifest.lines().skip(1).collect();
    assert_eq!(rows.len(), 3, "{manifest}");
    let crashed: Vec<&&str> = rows.iter().filter(|r| r.contains("SIGSEGV")).collect();
    assert_eq!(crashed.len(), 1, "{manifest}");
    assert!(
        crashed[0].contains("instance 'faulty' did not return from fmi2DoStep at t = 20"),
        "{manifest}"
    );
    assert_eq!(
        rows.iter().filter(|r| r.contains(",completed,")).count(),
        2,
        "{manifest}"
    );
    assert!(said.contains("1 flights ended in error"), "{said}");
    assert_nothing_left_in(tmp.path());
}

#[test]
fn the_unpacked_size_bound_is_settable_on_the_command_line() {
    let tmp = TempDir::new().unwrap();
    let output = harness_with(
        &[],
        tmp.path(),
        &[
            "--fmu-dir",
            common::fmu_dir().to_str().unwrap(),
            "--max-unpacked",
            "10k",
            "run",
            "paper",
            "-o",
            tmp.path().join("never.csv").to_str().unwrap(),
        ],
    );
    let said = text(&output);
    assert_eq!(output.status.code(), Some(1), "{said}");
    assert!(said.contains("LanderGnc.fmu"), "{said}");
    assert!(said.contains("10000"), "{said}");
    assert_nothing_left_in(tmp.path());
}

#[test]
fn harness_paper_ends_with_an_error_naming_the_call_when_a_law_s_flight_crashes() {
    let faulty = Faulty::build();
    let work = TempDir::new().unwrap();
    let tmp = TempDir::new().unwrap();
    let scenario = faulty.paper_with_it(work.path());
    let counter = work.path().join("counter");
    // The second law's flight crashes; the first has flown.
    let output = harness_with(
        &[
            ("FAULTY_FMU_FAULT", "abort"),
            ("FAULTY_FMU_CALL", "fmi2DoStep"),
            ("FAULTY_FMU_TIME", "10"),
            ("FAULTY_FMU_RUNS", "2"),
            ("FAULTY_FMU_COUNTER", counter.to_str().unwrap()),
        ],
        tmp.path(),
        &[
            "--fmu-dir",
            common::fmu_dir().to_str().unwrap(),
            "paper",
            scenario.to_str().unwrap(),
            "--no-plots",
            "--out-dir",
            work.path().join("paper").to_str().unwrap(),
        ],
    );
    let said = text(&output);
    assert_eq!(output.status.code(), Some(1), "{said}");
    assert!(
        said.contains("instance 'faulty' did not return from fmi2DoStep at t = 10"),
        "{said}"
    );
    assert!(said.contains("SIGABRT"), "{said}");
    assert_nothing_left_in(tmp.path());
}

#[test]
fn a_scenario_sets_its_own_limits_and_a_bad_one_is_refused_by_name() {
    let faulty = Faulty::build();
    let work = TempDir::new().unwrap();
    let tmp = TempDir::new().unwrap();
    let with_limits = |name: &str, limits: &str| {
        let path = faulty.scenario(work.path(), name);
        let text = std::fs::read_to_string(&path).unwrap();
        // Top-level keys come before the first table.
        let at = text.find("[[instance]]").unwrap();
        std::fs::write(
            &path,
            format!("{}[limits]\n{limits}\n\n{}", &text[..at], &text[at..]),
        )
        .unwrap();
        path
    };
    let hang = [
        ("FAULTY_FMU_FAULT", "hang"),
        ("FAULTY_FMU_CALL", "fmi2DoStep"),
        ("FAULTY_FMU_TIME", "0.2"),
    ];
    let scenario = with_limits("limited", "call_timeout_s = 1.0");
    let out = work.path().join("limited.csv");
    let started = std::time::Instant::now();
    let output = harness_with(
        &hang,
        tmp.path(),
        &[
            "run",
            scenario.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ],
    );
    let said = text(&output);
    assert_eq!(output.status.code(), Some(1), "{said}");
    assert!(said.contains("call timeout"), "{said}");
    assert!(started.elapsed().as_secs_f64() < 30.0, "{said}");
    // The command line overrides the scenario.
    let output = harness_with(
        &hang,
        tmp.path(),
        &[
            "--call-timeout",
            "0.5",
            "run",
            scenario.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ],
    );
    assert!(
        text(&output).contains("for 0.5 s (the call timeout)"),
        "{}",
        text(&output)
    );
    let bad = with_limits("bad", "call_timeout_s = -1.0\nmemory_mb = 0.0");
    let output = harness_with(
        &[],
        tmp.path(),
        &["run", bad.to_str().unwrap(), "-o", out.to_str().unwrap()],
    );
    let said = text(&output);
    assert_eq!(output.status.code(), Some(1), "{said}");
    assert!(
        said.contains("call_timeout_s = -1 must be a positive number"),
        "{said}"
    );
    assert!(
        said.contains("memory_mb = 0 must be a positive number"),
        "{said}"
    );
    assert_nothing_left_in(tmp.path());
}
