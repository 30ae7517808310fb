//! A value that is not a number, returned with fmi2OK by an output the master reads, ends the
//! run with an error naming the instance, the variable and the time, unless the scenario
//! allows it for that variable (then a warning, once per variable and run). The FMU is
//! tests/fixtures/non_finite_fmu.c, compiled here.
use cosim::master::{MasterError, Simulation, Trajectory};
use cosim::system::{Connection, InstanceDesc, Ordering, ParamValue, SystemDescription};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::{Mutex, OnceLock};
use tempfile::TempDir;

/// Variables in the order of the fixture's value references, which the ModelStructure's
/// indices (1-based) count.
const DESCRIPTION: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="2.0" modelName="NonFinite" guid="{non-finite}">
  <CoSimulation modelIdentifier="NonFinite"/>
  <ModelVariables>
    <ScalarVariable name="y" valueReference="0" causality="output"><Real/></ScalarVariable>
    <ScalarVariable name="z" valueReference="1" causality="output"><Real/></ScalarVariable>
    <ScalarVariable name="v[1]" valueReference="2" causality="output"><Real/></ScalarVariable>
    <ScalarVariable name="v[2]" valueReference="3" causality="output"><Real/></ScalarVariable>
    <ScalarVariable name="k" valueReference="4" causality="calculatedParameter"
        variability="fixed" initial="calculated"><Real/></ScalarVariable>
    <ScalarVariable name="u" valueReference="5" causality="input"><Real start="0"/></ScalarVariable>
    <ScalarVariable name="t_bad" valueReference="6" causality="parameter" variability="fixed"
        initial="exact"><Real start="0.45"/></ScalarVariable>
    <ScalarVariable name="echo" valueReference="7" causality="output"><Real/></ScalarVariable>
  </ModelVariables>
  <ModelStructure>
    <Outputs>
      <Unknown index="1" dependencies=""/>
      <Unknown index="2" dependencies=""/>
      <Unknown index="3" dependencies=""/>
      <Unknown index="4" dependencies=""/>
      <Unknown index="8" dependencies="6"/>
    </Outputs>
  </ModelStructure>
</fmiModelDescription>
"#;

/// The fixture compiled with `defines` into an unpacked FMU directory.
struct NonFiniteFmu {
    dir: PathBuf,
    _temp: TempDir,
}

impl NonFiniteFmu {
    fn build(defines: &[&str]) -> Self {
        let temp = TempDir::new().expect("temporary directory");
        let dir = temp.path().join("NonFinite");
        let binaries = dir.join("binaries").join("linux64");
        std::fs::create_dir_all(&binaries).expect("create binaries/linux64");
        std::fs::write(dir.join("modelDescription.xml"), DESCRIPTION).expect("write description");
        let source = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/non_finite_fmu.c");
        let compiler = std::env::var("CC").unwrap_or_else(|_| "cc".to_owned());
        let output = Command::new(&compiler)
            .args([
                "-shared", "-fPIC", "-std=c99", "-Wall", "-Wextra", "-Werror", "-o",
            ])
            .arg(binaries.join("NonFinite.so"))
            .arg(&source)
            .args(defines)
            .arg("-lm")
            .output()
            .unwrap_or_else(|error| panic!("cannot run the C compiler `{compiler}`: {error}"));
        assert!(
            output.status.success(),
            "compiling {} failed:\n{}",
            source.display(),
            String::from_utf8_lossy(&output.stderr)
        );
        Self { dir, _temp: temp }
    }
}

fn instance(name: &str, fmu: &NonFiniteFmu) -> InstanceDesc {
    InstanceDesc {
        name: name.into(),
        fmu: fmu.dir.clone(),
        parameters: Vec::new(),
        connectors: None,
        model_exchange: None,
    }
}

/// One instance of the fixture, 0 to 1 s in steps of 0.1 s: its outputs are bad from 0.5 s.
fn single(name: &str, fmu: &NonFiniteFmu) -> SystemDescription {
    SystemDescription {
        name: "non-finite".into(),
        start_time: 0.0,
        stop_time: 1.0,
        step_size: 0.1,
        ordering: Ordering::GaussSeidel,
        instances: vec![instance(name, fmu)],
        connections: Vec::new(),
        record: None,
        limits: Default::default(),
        allow_non_finite: Vec::new(),
        package: None,
    }
}

fn run(system: SystemDescription) -> (Result<cosim::master::RunEnd, MasterError>, Trajectory) {
    let mut simulation = Simulation::new(system, Path::new(".")).expect("the system resolves");
    let mut trajectory = Trajectory {
        names: simulation.column_names().to_vec(),
        ..Default::default()
    };
    let end = simulation.run(&mut trajectory);
    (end, trajectory)
}

/// The warnings logged so far whose text contains `needle`: every test names its instances
/// differently, so parallel tests do not see each other's.
fn warnings_about(needle: &str) -> Vec<String> {
    static WARNINGS: OnceLock<&'static Capture> = OnceLock::new();
    struct Capture(Mutex<Vec<String>>);
    impl log::Log for Capture {
        fn enabled(&self, metadata: &log::Metadata) -> bool {
            metadata.level() <= log::Level::Warn
        }
        fn log(&self, record: &log::Record) {
            if self.enabled(record.metadata()) {
                self.0.lock().unwrap().push(record.args().to_string());
            }
        }
        fn flush(&self) {}
    }
    let capture = WARNINGS.get_or_init(|| {
        let capture: &'static Capture = Box::leak(Box::new(Capture(Mutex::new(Vec::new()))));
        log::set_logger(capture).expect("no other logger in this test binary");
        log::set_max_level(log::LevelFilter::Warn);
        capture
    });
    let all = capture.0.lock().unwrap();
    all.iter().filter(|w| w.contains(needle)).cloned().collect()
}

#[test]
fn a_nan_output_ends_the_run_at_its_row_naming_instance_variable_and_time() {
    // GIVEN an FMU whose output y turns NaN at t = 0.5 s, still returning fmi2OK
    let fmu = NonFiniteFmu::build(&[]);
    // WHEN it is run with every output recorded
    let (end, trajectory) = run(single("lander", &fmu));
    // THEN the run ends with an error naming instance, variable and time
    let error = end.expect_err("a NaN output must not give a completed run");
    match &error {
        MasterError::NonFinite {
            instance,
            variable,
            time,
            value,
        } => {
            assert_eq!((instance.as_str(), variable.as_str()), ("lander", "y"));
            assert_eq!(*time, 0.5);
            assert!(value.is_nan());
        }
        other => panic!("wrong error: {other}"),
    }
    let text = error.to_string();
    assert!(
        text.contains("'lander'") && text.contains("'y'") && text.contains("t = 0.5"),
        "{text}"
    );
    assert!(
        text.contains("NaN") && text.contains("allow_non_finite"),
        "{text}"
    );
    // AND the rows before it are kept, the offending row last, so the user sees it
    assert_eq!(
        trajectory.times,
        [0.0, 0.1, 0.2, 0.30000000000000004, 0.4, 0.5]
    );
    let y = trajectory.column("lander.y").unwrap();
    assert!(y[..5].iter().all(|x| x.is_finite()), "{y:?}");
    assert!(y[5].is_nan());
}

#[test]
fn an_infinite_output_ends_the_run_as_a_nan_does() {
    let fmu = NonFiniteFmu::build(&["-DBAD=INFINITY"]);
    let (end, trajectory) = run(single("rover", &fmu));
    let error = end.expect_err("an infinite output must not give a completed run");
    let text = error.to_string();
    assert!(
        matches!(&error, MasterError::NonFinite { instance, variable, time, value }
            if instance == "rover" && variable == "y" && *time == 0.5 && *value == f64::INFINITY),
        "{text}"
    );
    assert!(text.contains("inf"), "{text}");
    assert_eq!(trajectory.len(), 6);
}

#[test]
fn a_nan_only_exchanged_through_a_connection_ends_the_run_too() {
    // GIVEN src.y wired to dst.u, with only dst.z recorded: src.y is read for the exchange
    let fmu = NonFiniteFmu::build(&[]);
    let mut system = single("src", &fmu);
    system.instances.push(instance("dst", &fmu));
    system.connections.push(Connection {
        from: "src.y".into(),
        to: "dst.u".into(),
    });
    system.record = Some(vec!["dst.z".into()]);
    // WHEN it runs
    let (end, trajectory) = run(system);
    // THEN the error names the source of the connection
    match end {
        Err(MasterError::NonFinite {
            instance,
            variable,
            time,
            ..
        }) => assert_eq!(
            (instance.as_str(), variable.as_str(), time),
            ("src", "y", 0.5)
        ),
        other => panic!("wrong end: {other:?}"),
    }
    assert_eq!(trajectory.len(), 6);
}

#[test]
fn a_nan_calculated_parameter_recorded_ends_the_run_at_the_start() {
    let fmu = NonFiniteFmu::build(&["-DCALCULATED_BAD"]);
    let mut system = single("probe", &fmu);
    system.record = Some(vec!["probe.k".into()]);
    let (end, trajectory) = run(system);
    match end {
        Err(MasterError::NonFinite {
            instance,
            variable,
            time,
            ..
        }) => assert_eq!(
            (instance.as_str(), variable.as_str(), time),
            ("probe", "k", 0.0)
        ),
        other => panic!("wrong end: {other:?}"),
    }
    assert_eq!(trajectory.len(), 1);
}

#[test]
fn a_nan_read_only_at_the_end_ends_the_run_at_the_stop_time() {
    // GIVEN y bad from 0.95 s on, read only as a final value
    let fmu = NonFiniteFmu::build(&[]);
    let mut system = single("late", &fmu);
    system.instances[0]
        .parameters
        .push(("t_bad".into(), ParamValue::Real(0.95)));
    system.record = Some(vec!["late.z".into()]);
    let mut simulation = Simulation::new(system, Path::new(".")).unwrap();
    simulation.set_final_columns(&["late.y".into()]).unwrap();
    let mut trajectory = Trajectory::default();
    // WHEN it runs to the end
    let end = simulation.run(&mut trajectory);
    // THEN every row is recorded and the final read fails the run at the stop time
    match end {
        Err(MasterError::NonFinite {
            instance,
            variable,
            time,
            ..
        }) => assert_eq!(
            (instance.as_str(), variable.as_str(), time),
            ("late", "y", 1.0)
        ),
        other => panic!("wrong end: {other:?}"),
    }
    assert_eq!(trajectory.len(), 11);
}

#[test]
fn allowed_variables_warn_once_per_run_with_their_first_time() {
    // GIVEN the scenario allows y and the whole vector v to be NaN ("no value")
    let fmu = NonFiniteFmu::build(&[]);
    let mut system = single("quiet", &fmu);
    system.allow_non_finite = vec!["quiet.y".into(), "quiet.v".into()];
    assert!(warnings_about("'quiet.").is_empty());
    let mut simulation = Simulation::new(system, Path::new(".")).unwrap();
    // WHEN it runs twice
    for run in 1..=2 {
        let mut trajectory = Trajectory {
            names: simulation.column_names().to_vec(),
            ..Default::default()
        };
        let end = simulation.run(&mut trajectory);
        // THEN each run completes with the NaN rows recorded
        assert_eq!(end.unwrap(), cosim::master::RunEnd::Completed);
        assert_eq!(trajectory.len(), 11);
        assert!(trajectory.column("quiet.y").unwrap()[5..]
            .iter()
            .all(|y| y.is_nan()));
        // AND warns once per variable and run, with the first time
        let y = warnings_about("'quiet.y'");
        let v2 = warnings_about("'quiet.v[2]'");
        assert_eq!((y.len(), v2.len()), (run, run), "{y:?} {v2:?}");
        assert!(y[0].contains("t = 0.5"), "{y:?}");
        assert!(warnings_about("'quiet.v[1]'").is_empty());
    }
}

#[test]
fn a_misspelt_allowed_variable_is_refused_with_a_suggestion() {
    let fmu = NonFiniteFmu::build(&[]);
    let mut system = single("src", &fmu);
    system.allow_non_finite = vec!["src.yy".into(), "scr.z".into()];
    let error = match Simulation::new(system, Path::new(".")) {
        Err(error @ MasterError::Resolve { .. }) => error.to_string(),
        Err(other) => panic!("wrong error: {other}"),
        Ok(_) => panic!("a misspelt name was accepted"),
    };
    assert!(error.contains("allow_non_finite"), "{error}");
    assert!(error.contains("did you mean 'y'?"), "{error}");
    assert!(error.contains("did you mean 'src'?"), "{error}");
}

/// `harness run` on a TOML scenario of the fixture, with `extra` top-level keys.
fn harness_run(
    fmu: &NonFiniteFmu,
    extra: &str,
    options: &[&str],
) -> (std::process::Output, TempDir) {
    let work = TempDir::new().unwrap();
    let scenario = work.path().join("nan.toml");
    std::fs::write(
        &scenario,
        format!(
            "name = \"nan\"\nstop_time = 1.0\nstep_size = 0.1\n{extra}\n\
             [[instance]]\nname = \"src\"\nfmu = \"{}\"\n",
            fmu.dir.display()
        ),
    )
    .unwrap();
    let output = Command::new(env!("CARGO_BIN_EXE_harness"))
        .arg("--fmu-dir")
        .arg(work.path())
        .args(options)
        .arg("run")
        .arg(&scenario)
        .arg("-o")
        .arg(work.path().join("out.csv"))
        .env("RUST_BACKTRACE", "0")
        .env_remove("RUST_LOG")
        .output()
        .unwrap();
    (output, work)
}

#[test]
fn the_cli_fails_a_nan_run_with_exit_code_1_and_names_it() {
    let fmu = NonFiniteFmu::build(&[]);
    let (output, _work) = harness_run(&fmu, "", &[]);
    let said = format!(
        "{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
    assert_eq!(output.status.code(), Some(1), "{said}");
    assert!(
        said.contains("'src'") && said.contains("'y'") && said.contains("t = 0.5"),
        "{said}"
    );
}

#[test]
fn the_cli_completes_an_allowed_nan_run_and_warns_once_per_variable() {
    let fmu = NonFiniteFmu::build(&[]);
    let allow = "allow_non_finite = [\"src.y\", \"src.v\"]";
    // A supervised worker (the default) completes it too.
    let (output, _work) = harness_run(&fmu, allow, &[]);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    // In process, the warnings reach the harness's logger.
    let (output, work) = harness_run(&fmu, allow, &["--in-process"]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    assert_eq!(stderr.matches("'src.y'").count(), 1, "{stderr}");
    assert_eq!(stderr.matches("'src.v[2]'").count(), 1, "{stderr}");
    let csv = std::fs::read_to_string(work.path().join("out.csv")).unwrap();
    assert_eq!(csv.lines().count(), 12, "{csv}");
}
