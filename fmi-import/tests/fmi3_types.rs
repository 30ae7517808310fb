//! Every FMI 3.0 variable type and Configuration Mode through the importer, against the C
//! stub of `fixtures/stub_fmu3.c` (written without our export layer).
#[path = "fixtures/stub_fmu3.rs"]
mod stub_fmu3;

use fmi_import::{word, CallError, Fmi3Type, Fmu, StepStatus};

fn stub() -> (tempfile::TempDir, Fmu) {
    let dir = tempfile::tempdir().unwrap();
    let root = stub_fmu3::build(dir.path());
    let fmu = Fmu::load(&root).unwrap();
    (dir, fmu)
}

fn initialized(fmu: &Fmu) -> fmi_import::Instance {
    let mut instance = fmu.instantiate("stub3", false).unwrap();
    instance.setup_experiment(None, 0.0, None).unwrap();
    instance.enter_initialization_mode().unwrap();
    instance.exit_initialization_mode().unwrap();
    instance
}

#[test]
fn every_word_type_crosses_the_c_abi_exactly_at_its_extremes() {
    let (_dir, fmu) = stub();
    let mut instance = initialized(&fmu);
    let cases: Vec<(&str, u64)> = vec![
        (
            "float32",
            word::from_float32(f64::from(1.0f32 / 3.0)).unwrap(),
        ),
        ("int8", word::from_integer(Fmi3Type::Int8, -128).unwrap()),
        ("uint8", 255),
        (
            "int16",
            word::from_integer(Fmi3Type::Int16, -32768).unwrap(),
        ),
        ("uint16", 65535),
        ("uint32", u64::from(u32::MAX)),
        ("int64", i64::MIN as u64),
        // Above i64::MAX: through neither f64 nor i64.
        ("uint64", u64::MAX - 5),
    ];
    for (name, word) in &cases {
        let info = *fmu.variable(&format!("{name}_in")).unwrap();
        assert!(info.is_word(), "{name}: {info:?}");
        instance
            .set_word_by_name(&format!("{name}_in"), *word)
            .unwrap();
    }
    instance.set_integer_by_name("int32_in", i32::MIN).unwrap();
    let bytes: &[u8] = &[0x00, 0xff, 0x10, 0x00];
    let binary_in = fmu.variable("binary_in").unwrap().value_reference;
    instance.set_binary(&[binary_in], &[bytes]).unwrap();
    assert!(matches!(
        instance.do_step(0.0, 0.5).unwrap(),
        StepStatus::Complete(_)
    ));
    for (name, word) in &cases {
        let out = instance.get_word_by_name(&format!("{name}_out")).unwrap();
        assert_eq!(out, *word, "{name}");
    }
    assert_eq!(instance.get_integer_by_name("int32_out").unwrap(), i32::MIN);
    let binary_out = fmu.variable("binary_out").unwrap().value_reference;
    let mut values = vec![Vec::new()];
    instance
        .get_binary_into(&[binary_out], &mut values)
        .unwrap();
    assert_eq!(values[0], bytes);
    // UInt64 `big` is 2^64 - 1 - steps: above 2^63, exact.
    assert_eq!(instance.get_word_by_name("big").unwrap(), u64::MAX - 1);
    assert_eq!(instance.get_word_by_name("steps").unwrap(), 1);
}

#[test]
fn a_word_its_type_cannot_hold_is_refused_before_the_fmu_is_called() {
    let (_dir, fmu) = stub();
    let mut instance = initialized(&fmu);
    let error = instance.set_word_by_name("uint8_in", 300).unwrap_err();
    let CallError::InvalidArgument { reason, .. } = &error else {
        panic!("{error:?}");
    };
    assert!(reason.contains("UInt8"), "{reason}");
    // A word type is not reached through the FMI 2.0-like functions of its counterpart.
    assert!(instance.set_integer_by_name("int16_in", 1).is_err());
    assert!(instance.set_real_by_name("float32_in", 1.0).is_err());
}

#[test]
fn the_view_shows_each_type_by_name_and_arrays_sized_by_the_structural_parameter() {
    let (_dir, fmu) = stub();
    assert_eq!(fmu.structural_parameters(), ["n"]);
    assert_eq!(fmu.variable("uint64_out").unwrap().type_name(), "UInt64");
    assert_eq!(fmu.variable("binary_in").unwrap().type_name(), "Binary");
    // Start value n = 2.
    assert!(fmu.variable("x[2]").is_ok() && fmu.variable("x[3]").is_err());
    let three = fmu.configured(&[("n".into(), "3".into())]).unwrap();
    assert!(three.variable("y[3]").is_ok() && three.variable("y[4]").is_err());
    // The FMU holds arrays of the configured extent: all three elements cross the ABI.
    let mut instance = initialized(&three);
    let x: Vec<u32> = (1..=3)
        .map(|i| three.variable(&format!("x[{i}]")).unwrap().value_reference)
        .collect();
    instance.set_real(&x, &[1.0, 2.0, 3.0]).unwrap();
    instance.do_step(0.0, 0.1).unwrap();
    let y: Vec<u32> = (1..=3)
        .map(|i| three.variable(&format!("y[{i}]")).unwrap().value_reference)
        .collect();
    let mut values = [0.0; 3];
    instance.get_real(&y, &mut values).unwrap();
    assert_eq!(values, [2.0, 4.0, 6.0]);
    // A reset keeps the configuration: the instance is configured again.
    instance.reset().unwrap();
    instance.setup_experiment(None, 0.0, None).unwrap();
    instance.enter_initialization_mode().unwrap();
    instance.exit_initialization_mode().unwrap();
    instance.set_real(&x, &[1.0, 1.0, 1.0]).unwrap();
    instance.do_step(0.0, 0.1).unwrap();
    instance.get_real(&y, &mut values).unwrap();
    assert_eq!(values, [2.0; 3]);
}

#[test]
fn a_configuration_the_fmu_or_the_description_refuses_says_why() {
    let (_dir, fmu) = stub();
    let text = |values: &[(&str, &str)]| {
        let values: Vec<(String, String)> = values
            .iter()
            .map(|(n, v)| (n.to_string(), v.to_string()))
            .collect();
        fmu.configured(&values).unwrap_err().to_string()
    };
    let wrong_type = text(&[("n", "2.5")]);
    assert!(
        wrong_type.contains("'n'") && wrong_type.contains("UInt64"),
        "{wrong_type}"
    );
    let negative = text(&[("n", "-1")]);
    assert!(negative.contains("-1"), "{negative}");
    let not_structural = text(&[("p16", "3")]);
    assert!(
        not_structural.contains("not a structural parameter"),
        "{not_structural}"
    );
    // The stub refuses n > 16 when Configuration Mode ends: instantiation fails with it.
    let big = fmu.configured(&[("n".into(), "17".into())]).unwrap();
    let error = big.instantiate("big", false).unwrap_err();
    let text = format!("{error:#}");
    assert!(text.contains("fmi3ExitConfigurationMode"), "{text}");
}
