//! The loader against a C FMU written independently of our export layer (tests/fixtures/stub_fmu.c).
use crate::archives::STUB_DESCRIPTION;
use crate::common::StubFmu;
use fmi_import::{
    CallError, Failure, Fmu, LoadError, Status, StepStatus, Success, VariableError, VariableKind,
};

/// The error and its sources, as anyhow's `{:#}` prints them.
fn chain(error: &dyn std::error::Error) -> String {
    let mut text = error.to_string();
    let mut source = error.source();
    while let Some(cause) = source {
        text.push_str(": ");
        text.push_str(&cause.to_string());
        source = cause.source();
    }
    text
}

fn initialized(fmu: &Fmu, name: &str) -> fmi_import::Instance {
    let mut instance = fmu.instantiate(name, true).expect("instantiate");
    instance.setup_experiment(None, 0.0, None).unwrap();
    instance.enter_initialization_mode().unwrap();
    instance.exit_initialization_mode().unwrap();
    instance
}

#[test]
fn values_round_trip_by_reference_and_by_name() {
    let stub = StubFmu::standard();
    let fmu = Fmu::load(&stub.dir).unwrap();
    let mut instance = initialized(&fmu, "values");

    assert_eq!(instance.set_real(&[0], &[2.5]).unwrap(), Success::Ok);
    let mut x = [0.0];
    instance.get_real(&[0], &mut x).unwrap();
    assert_eq!(x, [2.5]);
    assert_eq!(instance.get_real_by_name("x").unwrap(), 2.5);

    instance.set_integer_by_name("n", 41).unwrap();
    assert_eq!(instance.get_integer_by_name("n").unwrap(), 41);
    // The stub returns n + vr, so the loader must pass the references through in order.
    let mut n = [0; 3];
    instance.get_integer(&[0, 1, 2], &mut n).unwrap();
    assert_eq!(n, [41, 42, 43]);

    instance.set_boolean_by_name("flag", true).unwrap();
    // The stub answers 7 for true: any non-zero fmi2Boolean is true.
    assert!(instance.get_boolean_by_name("flag").unwrap());
    instance.set_boolean(&[0], &[false]).unwrap();
    assert!(!instance.get_boolean_by_name("flag").unwrap());

    instance.set_string_by_name("label", "renamed").unwrap();
    assert_eq!(instance.get_string_by_name("label").unwrap(), "renamed");
}

#[test]
fn raw_booleans_pass_through_and_any_true_reads_as_one() {
    let stub = StubFmu::standard();
    let fmu = Fmu::load(&stub.dir).unwrap();
    let mut instance = initialized(&fmu, "raw booleans");
    let vr = [instance.variable("flag").unwrap().value_reference];
    instance.set_boolean_raw(&vr, &[1]).unwrap();
    // The stub answers 7 for true; the master's buffers hold 0 or 1, as recorded columns do.
    let mut flag = [-1];
    instance.get_boolean_raw(&vr, &mut flag).unwrap();
    assert_eq!(flag, [1]);
    instance.set_boolean_raw(&vr, &[0]).unwrap();
    instance.get_boolean_raw(&vr, &mut flag).unwrap();
    assert_eq!(flag, [0]);
    assert!(!instance.get_boolean_by_name("flag").unwrap());
    let error = instance.get_boolean_raw(&vr, &mut [0, 0]).unwrap_err();
    assert!(
        error
            .to_string()
            .contains("1 value references but 2 values"),
        "{error}"
    );
}

#[test]
fn empty_value_lists_are_accepted() {
    let stub = StubFmu::standard();
    let fmu = Fmu::load(&stub.dir).unwrap();
    let mut instance = initialized(&fmu, "empty");
    assert_eq!(instance.set_real(&[], &[]).unwrap(), Success::Ok);
    assert_eq!(instance.get_string(&[]).unwrap().0, Vec::<String>::new());
}

#[test]
fn mismatched_slices_are_refused_before_reaching_the_fmu() {
    let stub = StubFmu::standard();
    let fmu = Fmu::load(&stub.dir).unwrap();
    let mut instance = initialized(&fmu, "lengths");
    let error = instance.set_real(&[0, 0], &[1.0]).unwrap_err();
    assert!(matches!(
        error,
        CallError::InvalidArgument {
            function: "fmi2SetReal",
            ..
        }
    ));
    assert!(
        error
            .to_string()
            .contains("2 value references but 1 values"),
        "{error}"
    );
    let mut too_short = [0; 1];
    assert!(instance.get_integer(&[0, 0], &mut too_short).is_err());
}

#[test]
fn unknown_names_and_type_mismatches_name_the_variable() {
    let stub = StubFmu::standard();
    let fmu = Fmu::load(&stub.dir).unwrap();
    let mut instance = initialized(&fmu, "names");

    let unknown = instance.set_real_by_name("no_such", 1.0).unwrap_err();
    assert!(
        matches!(&unknown, CallError::Variable(VariableError::Unknown { name, .. }) if name == "no_such")
    );
    assert!(unknown.to_string().contains("'no_such'"), "{unknown}");

    let mismatch = instance.get_real_by_name("flag").unwrap_err();
    let text = mismatch.to_string();
    assert!(
        text.contains("'flag'") && text.contains("Boolean") && text.contains("Real"),
        "{text}"
    );
    assert_eq!(fmu.value_reference("n", VariableKind::Integer), Ok(0));
}

#[test]
fn a_refused_set_is_an_error_carrying_the_fmus_formatted_log_line() {
    let stub = StubFmu::standard();
    let fmu = Fmu::load(&stub.dir).unwrap();
    let mut instance = initialized(&fmu, "refuse");

    let error = instance.set_real_by_name("x", -1.5).unwrap_err();
    let CallError::Fmi(fmi) = &error else {
        panic!("expected an FMI error, got {error:?}");
    };
    assert_eq!(fmi.status, Failure::Error);
    assert_eq!(fmi.function, "fmi2SetReal");
    assert_eq!(fmi.instance, "refuse");
    // Only what was logged during the failing call, formatted by the C shim (%g, %u).
    assert_eq!(fmi.log.0.len(), 1, "{:?}", fmi.log);
    let line = &fmi.log.0[0];
    assert_eq!(
        line.message,
        "fmi2SetReal: x = -1.5 (vr 0) must not be negative"
    );
    assert_eq!(line.status, Status::Error);
    assert_eq!(line.category, "logStatusError");
    assert_eq!(line.instance_name, "refuse");
    let text = error.to_string();
    assert!(
        text.contains("fmi2Error") && text.contains("x = -1.5"),
        "{text}"
    );

    // The instance's own log keeps everything: the instantiation trace and the refusal.
    let all = instance.log_messages();
    assert!(
        all[0]
            .message
            .starts_with("fmi2Instantiate(type=1, resources=file:///"),
        "{all:?}"
    );
    assert!(all
        .iter()
        .any(|message| message.message.contains("must not be negative")));
}

#[test]
fn each_instance_has_its_own_log() {
    let stub = StubFmu::standard();
    let fmu = Fmu::load(&stub.dir).unwrap();
    let mut first = initialized(&fmu, "first");
    let second = initialized(&fmu, "second");
    first.set_real(&[0], &[-1.0]).unwrap_err();
    assert!(first
        .log_messages()
        .iter()
        .any(|m| m.message.contains("negative")));
    assert!(second
        .log_messages()
        .iter()
        .all(|m| m.instance_name == "second"));
    assert!(!second
        .log_messages()
        .iter()
        .any(|m| m.message.contains("negative")));
}

#[test]
fn a_failed_instantiation_carries_the_fmus_reason() {
    let description = STUB_DESCRIPTION.replace("guid=\"{stub}\"", "guid=\"{other}\"");
    let stub = StubFmu::build(&[], &description);
    let fmu = Fmu::load(&stub.dir).unwrap();
    let error = fmu.instantiate("guid", false).unwrap_err();
    assert!(matches!(error, CallError::InstantiationFailed { .. }));
    let text = error.to_string();
    assert!(
        text.contains("GUID {other} does not match {stub}"),
        "{text}"
    );
}

#[test]
fn a_discarded_step_reports_the_last_successful_time_and_termination() {
    let stub = StubFmu::standard();
    let fmu = Fmu::load(&stub.dir).unwrap();
    let mut instance = initialized(&fmu, "discard");
    assert_eq!(
        instance.do_step(0.0, 0.5).unwrap(),
        StepStatus::Complete(Success::Ok)
    );
    assert!(!instance.terminated().unwrap());
    // The stub stops at t = 1.
    let status = instance.do_step(0.5, 0.75).unwrap();
    assert_eq!(
        status,
        StepStatus::Discarded {
            last_successful_time: 1.0,
            terminated: true
        }
    );
    assert_eq!(instance.last_successful_time().unwrap(), 1.0);
}

#[test]
fn a_fatal_step_is_an_error_with_the_log() {
    let stub = StubFmu::standard();
    let fmu = Fmu::load(&stub.dir).unwrap();
    let mut instance = initialized(&fmu, "fatal");
    instance.set_integer_by_name("n", -3).unwrap();
    let error = instance.do_step(0.0, 0.1).unwrap_err();
    assert_eq!(error.status, Failure::Fatal);
    assert!(
        error.to_string().contains("n = -3 broke the model"),
        "{error}"
    );
}

#[test]
fn drop_frees_the_instance_and_every_state_it_still_holds() {
    let stub = StubFmu::standard();
    let fmu = Fmu::load(&stub.dir).unwrap();
    {
        let mut instance = initialized(&fmu, "drop");
        let kept = instance.get_fmu_state().unwrap();
        let _forgotten = instance.get_fmu_state().unwrap();
        assert_eq!(stub.counter("stub_live_instances"), 1);
        assert_eq!(stub.counter("stub_live_states"), 2);
        instance.free_fmu_state(kept).unwrap();
        assert_eq!(stub.counter("stub_live_states"), 1);
    }
    assert_eq!(stub.counter("stub_live_instances"), 0);
    assert_eq!(stub.counter("stub_live_states"), 0);
}

#[test]
fn fmu_states_restore_and_serialize() {
    let stub = StubFmu::standard();
    let fmu = Fmu::load(&stub.dir).unwrap();
    let mut instance = initialized(&fmu, "states");
    instance.set_real(&[0], &[3.0]).unwrap();
    let saved = instance.get_fmu_state().unwrap();
    instance.set_real(&[0], &[4.0]).unwrap();
    instance.set_fmu_state(&saved).unwrap();
    assert_eq!(instance.get_real_by_name("x").unwrap(), 3.0);

    instance.set_real(&[0], &[5.0]).unwrap();
    instance.update_fmu_state(&saved).unwrap();
    let bytes = instance.serialize_fmu_state(&saved).unwrap();
    instance.set_real(&[0], &[6.0]).unwrap();
    let restored = instance.deserialize_fmu_state(&bytes).unwrap();
    instance.set_fmu_state(&restored).unwrap();
    assert_eq!(instance.get_real_by_name("x").unwrap(), 5.0);

    let error = instance.deserialize_fmu_state(&bytes[1..]).unwrap_err();
    assert!(error.to_string().contains("bytes, expected"), "{error}");
}

#[test]
fn a_state_cannot_be_used_with_another_instance() {
    let stub = StubFmu::standard();
    let fmu = Fmu::load(&stub.dir).unwrap();
    let mut first = initialized(&fmu, "first");
    let mut second = initialized(&fmu, "second");
    let state = first.get_fmu_state().unwrap();
    let error = second.set_fmu_state(&state).unwrap_err();
    assert!(
        error.to_string().contains("belongs to another instance"),
        "{error}"
    );
    // ... and a freed state's token is gone with it (moved into free_fmu_state).
    first.free_fmu_state(state).unwrap();
}

#[test]
fn instances_outlive_the_fmu_handle_they_came_from() {
    let stub = StubFmu::standard();
    let mut instance = {
        let fmu = Fmu::load(&stub.dir).unwrap();
        initialized(&fmu, "orphan")
    };
    // The library stays loaded through the instance's shared handle.
    instance.set_real(&[0], &[1.25]).unwrap();
    assert_eq!(instance.get_real_by_name("x").unwrap(), 1.25);
}

#[test]
fn a_missing_function_is_named() {
    let stub = StubFmu::build(&["-DSTUB_OMIT_DO_STEP"], STUB_DESCRIPTION);
    let error = Fmu::load(&stub.dir).unwrap_err();
    assert!(
        matches!(
            error,
            LoadError::MissingSymbol {
                symbol: "fmi2DoStep",
                ..
            }
        ),
        "{error:?}"
    );
    let text = chain(&error);
    assert!(text.contains("does not export fmi2DoStep"), "{text}");
    // The cause, from the dynamic loader, is kept as the source.
    assert!(text.contains("undefined symbol: fmi2DoStep"), "{text}");
}

#[test]
fn a_binary_of_another_fmi_version_is_refused() {
    let stub = StubFmu::build(&["-DSTUB_VERSION=\"3.0\""], STUB_DESCRIPTION);
    let error = Fmu::load(&stub.dir).unwrap_err();
    let text = error.to_string();
    assert!(text.contains("fmi2GetVersion returned \"3.0\""), "{text}");
}

#[test]
fn a_model_exchange_description_needs_the_model_exchange_functions_not_the_co_simulation_ones() {
    // GIVEN the Co-Simulation stub described as Model Exchange only
    let description = STUB_DESCRIPTION.replace("CoSimulation", "ModelExchange");
    let stub = StubFmu::build(&[], &description);
    // THEN it is the first Model Exchange function it lacks that refuses it
    let text = chain(&Fmu::load(&stub.dir).unwrap_err());
    assert!(
        text.contains("does not export fmi2EnterEventMode"),
        "{text}"
    );
}

#[test]
fn a_description_with_neither_interface_is_refused() {
    let description = STUB_DESCRIPTION.replace("CoSimulation", "Unknown");
    let stub = StubFmu::build(&[], &description);
    let error = Fmu::load(&stub.dir).unwrap_err();
    assert!(
        matches!(error, LoadError::NotCoSimulation { .. }),
        "{error:?}"
    );
}

#[test]
fn a_description_of_another_fmi_version_is_refused() {
    let description = STUB_DESCRIPTION.replace("fmiVersion=\"2.0\"", "fmiVersion=\"3.0\"");
    let stub = StubFmu::build(&[], &description);
    let text = chain(&Fmu::load(&stub.dir).unwrap_err());
    // The model-description reader may refuse it first; either way the version is named.
    assert!(text.contains("3.0"), "{text}");
}

#[test]
fn a_missing_binary_names_the_expected_path() {
    let description =
        STUB_DESCRIPTION.replace("modelIdentifier=\"Stub\"", "modelIdentifier=\"Elsewhere\"");
    let stub = StubFmu::build(&[], &description);
    let error = Fmu::load(&stub.dir).unwrap_err();
    assert!(
        error.to_string().contains("binaries/linux64/Elsewhere.so"),
        "{error}"
    );
}

#[test]
fn a_broken_model_description_is_reported_with_its_path() {
    let stub = StubFmu::build(&[], "<fmiModelDescription fmiVersion=\"2.0\"");
    let error = Fmu::load(&stub.dir).unwrap_err();
    assert!(
        matches!(error, LoadError::ModelDescription { .. }),
        "{error:?}"
    );
    let text = chain(&error);
    assert!(text.contains("modelDescription.xml"), "{text}");
    assert!(
        text.contains("line 1"),
        "the XML parser's position is kept: {text}"
    );
}

#[test]
fn instances_are_send_and_run_on_their_own_threads() {
    let stub = StubFmu::standard();
    let fmu = Fmu::load(&stub.dir).unwrap();
    let handles: Vec<_> = (0..4)
        .map(|worker| {
            let mut instance = initialized(&fmu, &format!("worker{worker}"));
            std::thread::spawn(move || {
                let value = f64::from(worker) + 0.5;
                instance.set_real(&[0], &[value]).unwrap();
                instance.do_step(0.0, 0.25).unwrap();
                instance.get_real_by_name("x").unwrap() == value
            })
        })
        .collect();
    assert!(handles.into_iter().all(|handle| handle.join().unwrap()));
}
