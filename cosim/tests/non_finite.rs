//! A value that is not a number, returned with fmi2OK by an output the master reads, ends the
//! run with an error naming the instance, the variable and the time, unless the scenario
//! allows it for that variable (then a warning, once per variable and run). The FMU is
//! tests/fixtures/non_finite_fmu.c, compiled by tests/non_finite_fmu.rs.
use cosim::master::{MasterError, Simulation, Trajectory};
use cosim::system::{Connection, InstanceDesc, Ordering, ParamValue, SystemDescription};
use std::path::Path;
use std::sync::{Mutex, OnceLock};

use crate::non_finite_fmu::NonFiniteFmu;

fn instance(name: &str, fmu: &NonFiniteFmu) -> InstanceDesc {
    InstanceDesc {
        name: name.into(),
        fmu: fmu.dir.clone(),
        parameters: Vec::new(),
        connectors: None,
        model_exchange: None,
        interface_named: false,
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
        events: Vec::new(),
        inputs: None,
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
