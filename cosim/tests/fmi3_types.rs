//! Every FMI 3.0 numeric type through the master: set from a scenario (refused before the
//! run when its type cannot hold the value), connected between equal types, recorded
//! exactly in CSV and Arrow; and a structural parameter that sizes the arrays recorded. The
//! FMU is the importer's C stub (fmi-import/tests/fixtures/stub_fmu3.c).
#[path = "../../fmi-import/tests/fixtures/stub_fmu3.rs"]
mod stub_fmu3;

use cosim::master::{MasterError, Simulation, Trajectory};
use cosim::results::{self, ColumnType, Format};
use cosim::system::{Connection, InstanceDesc, Ordering, ParamValue, SystemDescription};
use std::path::{Path, PathBuf};

/// The word types the stub echoes (Int32, Float64 and Boolean keep their own buffers).
const WORDS: [&str; 8] = [
    "float32", "int8", "uint8", "int16", "uint16", "uint32", "int64", "uint64",
];

fn instance(name: &str, fmu: &Path, parameters: Vec<(&str, ParamValue)>) -> InstanceDesc {
    InstanceDesc {
        name: name.into(),
        fmu: fmu.to_path_buf(),
        parameters: parameters
            .into_iter()
            .map(|(n, v)| (n.to_owned(), v))
            .collect(),
        connectors: None,
        model_exchange: None,
        interface_named: false,
    }
}

fn system(
    instances: Vec<InstanceDesc>,
    connections: Vec<Connection>,
    record: &[&str],
) -> SystemDescription {
    SystemDescription {
        name: "fmi3-types".into(),
        start_time: 0.0,
        stop_time: 0.3,
        step_size: 0.1,
        ordering: Ordering::GaussSeidel,
        instances,
        connections,
        record: Some(record.iter().map(|r| r.to_string()).collect()),
        limits: Default::default(),
        allow_non_finite: Vec::new(),
        events: Vec::new(),
        inputs: None,
        package: None,
    }
}

fn stub() -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let root = stub_fmu3::build(dir.path());
    (dir, root)
}

/// The extremes of each type, as a scenario gives them (a UInt64 above i64::MAX as text).
fn extremes() -> Vec<(&'static str, ParamValue)> {
    vec![
        ("float32_in", ParamValue::Real(0.1)),
        ("int8_in", ParamValue::Integer(-128)),
        ("uint8_in", ParamValue::Integer(255)),
        ("int16_in", ParamValue::Integer(-32768)),
        ("uint16_in", ParamValue::Integer(65535)),
        ("uint32_in", ParamValue::Integer(4_294_967_295)),
        ("int64_in", ParamValue::Integer(i64::MIN)),
        (
            "uint64_in",
            ParamValue::String("18446744073709551614".into()),
        ),
        ("int32_in", ParamValue::Integer(1000)),
        ("boolean_in", ParamValue::Boolean(true)),
    ]
}

#[test]
fn every_word_type_is_set_connected_and_recorded_exactly() {
    let (_dir, fmu) = stub();
    let connections = WORDS
        .iter()
        .chain(&["int32", "boolean", "float64"])
        .map(|t| Connection {
            from: format!("a.{t}_out"),
            to: format!("b.{t}_in"),
        })
        .collect();
    let system = system(
        vec![instance("a", &fmu, extremes()), instance("b", &fmu, vec![])],
        connections,
        &["b.*_out", "a.big", "a.steps"],
    );
    let mut simulation = Simulation::new(system, Path::new(".")).unwrap();
    let names = simulation.column_names().to_vec();
    let types = simulation.column_types();
    let mut trajectory = Trajectory {
        names: names.clone(),
        ..Default::default()
    };
    simulation.run(&mut trajectory).unwrap();
    let column = |name: &str| names.iter().position(|n| n == name).unwrap();
    let last = trajectory.row(trajectory.len() - 1);
    let uint64 = column("b.uint64_out");
    assert_eq!(types[uint64], ColumnType::UInt64);
    assert_eq!(
        ColumnType::UInt64.integer(last[uint64]),
        i128::from(u64::MAX - 1)
    );
    assert_eq!(
        ColumnType::Int64.integer(last[column("b.int64_out")]),
        i128::from(i64::MIN)
    );
    assert_eq!(last[column("b.int8_out")], -128.0);
    assert_eq!(last[column("b.uint32_out")], 4_294_967_295.0);
    assert_eq!(types[column("b.float32_out")], ColumnType::Float32);
    assert_eq!(last[column("b.float32_out")], f64::from(0.1f32));
    // 2^64 - 1 - steps after three steps.
    assert_eq!(
        ColumnType::UInt64.integer(last[column("a.big")]),
        i128::from(u64::MAX - 3)
    );
    assert!(
        !names
            .iter()
            .any(|n| n.contains("string") || n.contains("binary")),
        "{names:?}"
    );

    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("r.csv");
    results::write_typed(&csv, &trajectory, &[], &types, Format::Csv).unwrap();
    let text = std::fs::read_to_string(&csv).unwrap();
    let header: Vec<&str> = text.lines().next().unwrap().split(',').collect();
    let row: Vec<&str> = text.lines().last().unwrap().split(',').collect();
    let field = |name: &str| row[header.iter().position(|h| *h == name).unwrap()];
    assert_eq!(field("b.uint64_out"), "18446744073709551614");
    assert_eq!(field("b.int64_out"), i64::MIN.to_string());
    assert_eq!(field("b.int32_out"), "1000");
    assert_eq!(field("b.int8_out"), "-128");
    assert_eq!(field("b.boolean_out"), "1");
    let back = results::read_csv_typed(&csv, &types).unwrap();
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&back.values), bits(&trajectory.values));

    let arrow = dir.path().join("r.arrow");
    results::write_typed(&arrow, &trajectory, &[], &types, Format::Arrow).unwrap();
    let (back, read_types) = results::read_arrow_typed(&arrow).unwrap();
    assert_eq!(read_types, types);
    assert_eq!(bits(&back.values), bits(&trajectory.values));
}

#[test]
fn values_a_type_cannot_hold_are_refused_before_the_run_naming_all() {
    let (_dir, fmu) = stub();
    let system = system(
        vec![instance(
            "a",
            &fmu,
            vec![
                ("uint8_in", ParamValue::Integer(300)),
                ("p16", ParamValue::Real(1.5)),
                ("uint64_in", ParamValue::Integer(-1)),
            ],
        )],
        vec![],
        &["a.steps"],
    );
    let Err(MasterError::Resolve { problems, .. }) = Simulation::new(system, Path::new(".")) else {
        panic!("out-of-range values were not refused");
    };
    let text = problems.join("\n");
    for expected in [
        "instance 'a': parameter 'uint8_in' is UInt8",
        "300 is outside the range of UInt8 [0, 255]",
        "parameter 'p16' is Int16",
        "1.5",
        "parameter 'uint64_in' is UInt64",
        "-1 is outside the range of UInt64",
    ] {
        assert!(text.contains(expected), "{expected:?} not in:\n{text}");
    }
}

#[test]
fn a_structural_parameter_given_in_the_scenario_sizes_the_arrays_recorded() {
    let (_dir, fmu) = stub();
    let parameters = vec![
        ("n", ParamValue::Integer(3)),
        ("x[1]", ParamValue::Real(1.0)),
        ("x[2]", ParamValue::Real(2.0)),
        ("x[3]", ParamValue::Real(3.0)),
        ("p16", ParamValue::Integer(-100)),
    ];
    let three = system(vec![instance("a", &fmu, parameters)], vec![], &["a.y"]);
    let mut simulation = Simulation::new(three, Path::new(".")).unwrap();
    assert_eq!(simulation.column_names(), ["a.y[1]", "a.y[2]", "a.y[3]"]);
    let mut trajectory = Trajectory {
        names: simulation.column_names().to_vec(),
        ..Default::default()
    };
    simulation.run(&mut trajectory).unwrap();
    assert_eq!(trajectory.row(trajectory.len() - 1), [2.0, 4.0, 6.0]);
    // Run again (the instances are reset and configured again).
    simulation.run(&mut trajectory).unwrap();
    assert_eq!(trajectory.row(trajectory.len() - 1), [2.0, 4.0, 6.0]);
    let error = simulation
        .set_parameter("a", "n", ParamValue::Integer(4))
        .unwrap_err()
        .to_string();
    assert!(error.contains("structural parameter"), "{error}");

    // Without n the start value (2) holds: x[3] does not exist.
    let two = system(
        vec![instance("a", &fmu, vec![("x[3]", ParamValue::Real(3.0))])],
        vec![],
        &["a.y"],
    );
    let Err(MasterError::Resolve { problems, .. }) = Simulation::new(two, Path::new(".")) else {
        panic!("x[3] resolved with n = 2");
    };
    assert!(problems.join("\n").contains("x[3]"), "{problems:?}");
}

#[test]
fn strings_and_binaries_are_connected_and_streamed_to_result_files_as_text_and_hex() {
    let (_dir, fmu) = stub();
    let connections = ["string", "binary"]
        .iter()
        .map(|t| Connection {
            from: format!("a.{t}_out"),
            to: format!("b.{t}_in"),
        })
        .collect();
    let text = "a, \"quoted\" text";
    let parameters = vec![
        ("string_in", ParamValue::String(text.into())),
        ("binary_in", ParamValue::String("00FF10".into())),
    ];
    let texts = system(
        vec![instance("a", &fmu, parameters), instance("b", &fmu, vec![])],
        connections,
        &["b.string_out", "b.binary_out", "a.steps"],
    );
    let mut simulation = Simulation::new(texts, Path::new(".")).unwrap();
    let types = simulation.column_types();
    assert_eq!(&types[..2], [ColumnType::String, ColumnType::Binary]);
    let dir = tempfile::tempdir().unwrap();
    for format in [Format::Csv, Format::Arrow] {
        let path = dir.path().join(format!("r.{}", format.extension()));
        let mut stream =
            results::Stream::create_typed(&path, simulation.column_names(), &[], &types, format)
                .unwrap();
        simulation.run(&mut stream).unwrap();
        assert_eq!(stream.finish().unwrap(), 4);
        if format == Format::Csv {
            let csv = std::fs::read_to_string(&path).unwrap();
            let last = csv.lines().last().unwrap();
            assert_eq!(last, "0.3,\"a, \"\"quoted\"\" text\",00ff10,3", "{csv}");
        } else {
            let reader =
                arrow_ipc::reader::FileReader::try_new(std::fs::File::open(&path).unwrap(), None)
                    .unwrap();
            let batch = reader.into_iter().next().unwrap().unwrap();
            use arrow_array::cast::AsArray;
            let strings = batch.column(1).as_string::<i32>();
            assert_eq!(strings.value(3), text);
            let bytes = batch.column(2).as_binary::<i32>();
            assert_eq!(bytes.value(3), [0x00, 0xff, 0x10]);
        }
    }
    // A String and a Binary are not connected to each other.
    let crossed = system(
        vec![instance("a", &fmu, vec![]), instance("b", &fmu, vec![])],
        vec![Connection {
            from: "a.string_out".into(),
            to: "b.binary_in".into(),
        }],
        &["a.steps"],
    );
    let Err(MasterError::Resolve { problems, .. }) = Simulation::new(crossed, Path::new("."))
    else {
        panic!("a String was connected to a Binary");
    };
    assert!(
        problems
            .join("\n")
            .contains("type mismatch (String -> Binary)"),
        "{problems:?}"
    );
}

#[test]
fn an_input_table_drives_no_word_string_or_binary_input() {
    let (_dir, fmu) = stub();
    let mut table_system = system(vec![instance("a", &fmu, vec![])], vec![], &["a.steps"]);
    table_system.inputs = Some(
        cosim::system::input_table::InputTable::parse_csv(
            "time,a.uint8_in,a.string_in,a.x[1]\n0,1,2,3\n1,1,2,3\n",
        )
        .unwrap(),
    );
    let Err(MasterError::Resolve { problems, .. }) = Simulation::new(table_system, Path::new("."))
    else {
        panic!("a table drove a UInt8 and a String");
    };
    let text = problems.join("\n");
    assert!(text.contains("'a.uint8_in': the input is UInt8"), "{text}");
    assert!(
        text.contains("'a.string_in': the input is String"),
        "{text}"
    );
    assert!(!text.contains("x[1]"), "a Float64 input is driven: {text}");
}

#[test]
fn an_ssd_connector_may_declare_an_fmi3_variable_by_its_type_or_its_fmi2_counterpart() {
    let (_dir, fmu) = stub();
    let declared = |name: &str, type_name: &str| cosim::system::DeclaredConnector {
        name: name.into(),
        kind: "output".into(),
        type_name: Some(type_name.into()),
        dimensions: Vec::new(),
    };
    let mut ssd = system(vec![instance("a", &fmu, vec![])], vec![], &["a.steps"]);
    ssd.instances[0].connectors = Some(vec![
        declared("binary_out", "Binary"),
        declared("uint64_out", "Integer"),
        declared("steps", "Int64"),
        declared("int8_out", "Boolean"),
    ]);
    let Err(MasterError::Resolve { problems, .. }) = Simulation::new(ssd, Path::new(".")) else {
        panic!("an Int8 declared Boolean was accepted");
    };
    assert_eq!(
        problems,
        [
            "component 'a': connector 'int8_out' is declared Boolean but the FMU's variable is \
          Int8"
        ]
    );
}

#[test]
fn a_float32_output_that_is_not_a_number_ends_the_run_as_a_float64_one_does() {
    let (_dir, fmu) = stub();
    let nan = system(
        vec![instance(
            "a",
            &fmu,
            vec![("float32_in", ParamValue::Real(f64::INFINITY))],
        )],
        vec![],
        &["a.float32_out", "a.steps"],
    );
    let mut simulation = Simulation::new(nan, Path::new(".")).unwrap();
    let mut trajectory = Trajectory {
        names: simulation.column_names().to_vec(),
        ..Default::default()
    };
    let error = simulation.run(&mut trajectory).unwrap_err();
    let MasterError::NonFinite {
        instance,
        variable,
        value,
        ..
    } = &error
    else {
        panic!("{error}");
    };
    assert_eq!((instance.as_str(), variable.as_str()), ("a", "float32_out"));
    assert_eq!(*value, f64::INFINITY);
    assert_eq!(trajectory.len(), 1, "the row of the value is the last");
}

#[test]
fn connectors_written_for_an_ssd_use_the_ssp_1_0_types() {
    let (_dir, fmu) = stub();
    let connections = ["float32", "uint64", "binary"]
        .iter()
        .map(|t| Connection {
            from: format!("a.{t}_out"),
            to: format!("b.{t}_in"),
        })
        .collect();
    let wired = system(
        vec![instance("a", &fmu, vec![]), instance("b", &fmu, vec![])],
        connections,
        &["a.steps"],
    );
    let simulation = Simulation::new(wired, Path::new(".")).unwrap();
    let types: Vec<(&str, &str)> = simulation
        .connectors()
        .iter()
        .map(|c| (c.name.as_str(), c.type_name))
        .collect();
    assert_eq!(
        types,
        [
            ("float32_out", "Real"),
            ("float32_in", "Real"),
            ("uint64_out", "Integer"),
            ("uint64_in", "Integer"),
            ("binary_out", "Binary"),
            ("binary_in", "Binary"),
        ]
    );
}

#[test]
fn a_run_that_exchanges_words_is_not_saved_or_continued_without_them() {
    // GIVEN two stubs connected by every word type
    let (dir, fmu) = stub();
    let connections = WORDS
        .iter()
        .map(|t| Connection {
            from: format!("a.{t}_out"),
            to: format!("b.{t}_in"),
        })
        .collect();
    let system = system(
        vec![instance("a", &fmu, vec![]), instance("b", &fmu, vec![])],
        connections,
        &["b.*_out"],
    );
    let mut simulation = Simulation::new(system, Path::new(".")).unwrap();
    // WHEN a save is asked for
    let error = simulation
        .set_checkpoints(cosim::master::Checkpoints {
            resume: None,
            save: Some(cosim::master::SaveRequest {
                path: dir.path().join("saved.run"),
                at: None,
            }),
        })
        .unwrap_err()
        .to_string();
    // THEN it is refused before the run, naming the instance and why: the saved buffers
    // would leave the words behind
    assert!(
        error.contains("instance 'a' exchanges or records values of FMI 3.0 types")
            && error.contains("a saved run does not carry yet"),
        "{error}"
    );
}
