//! FMU states of FMI 3.0 instances through the importer, as of FMI 2.0 ones: get, set,
//! serialize and deserialize into another instance, in Step Mode and in Event Mode; and the
//! refusal, before any call, of an FMU that declares it cannot serialize its state.
use crate::common::{fmu_dir, unzip_to};
use fmi_import::{CallError, Fmu, Instance, InstanceOptions, StepStatus, VariableKind};
use tempfile::TempDir;

const H: f64 = 0.01;

/// The FMI 3.0 LanderPlant, initialized, under a constant command.
fn plant(fmu: &Fmu, name: &str, same_instant: bool) -> Instance {
    let options = InstanceOptions {
        same_instant_feedthrough: same_instant,
        ..Default::default()
    };
    let mut plant = fmu.instantiate_with(name, options).unwrap();
    plant.setup_experiment(None, 0.0, Some(100.0)).unwrap();
    plant.enter_initialization_mode().unwrap();
    plant.exit_initialization_mode().unwrap();
    plant
}

/// Steps `from..to` (step numbers), setting the command first at each point; the altitude
/// and speed after each step, as bits.
fn fly(fmu: &Fmu, plant: &mut Instance, from: u32, to: u32) -> Vec<(u64, u64)> {
    let thrust = fmu
        .value_reference("thrust_cmd", VariableKind::Real)
        .unwrap();
    let up = fmu.value_reference("r_nue[2]", VariableKind::Real).unwrap();
    let climb = fmu.value_reference("v_nue[2]", VariableKind::Real).unwrap();
    let mut flown = Vec::new();
    for k in from..to {
        // A command that changes every step, so a restored state that kept the wrong one shows.
        plant.set_real(&[thrust], &[1500.0 + f64::from(k)]).unwrap();
        let stepped = plant.do_step(f64::from(k) * H, H).unwrap();
        assert!(matches!(stepped, StepStatus::Complete(_)), "{stepped:?}");
        let mut values = [0.0; 2];
        plant.get_real(&[up, climb], &mut values).unwrap();
        flown.push((values[0].to_bits(), values[1].to_bits()));
    }
    flown
}

#[test]
fn an_fmi3_state_set_back_and_deserialized_elsewhere_continues_bit_for_bit() {
    let fmu = Fmu::load(fmu_dir().join("fmi3/LanderPlant.fmu")).unwrap();
    for same_instant in [false, true] {
        let mut plant = plant(&fmu, "saved", same_instant);
        fly(&fmu, &mut plant, 0, 100);
        let saved = plant.get_fmu_state().unwrap();
        let first = fly(&fmu, &mut plant, 100, 150);

        // Set back: the outputs return to what they were, and the flight repeats.
        plant.set_fmu_state(&saved).unwrap();
        let again = fly(&fmu, &mut plant, 100, 150);
        assert_eq!(first, again, "set back (Event Mode used: {same_instant})");

        // Serialized, then continued in a fresh instance that has flown nothing.
        let bytes = plant.serialize_fmu_state(&saved).unwrap();
        let mut other = self::plant(&fmu, "restored", same_instant);
        let restored = other.deserialize_fmu_state(&bytes).unwrap();
        other.set_fmu_state(&restored).unwrap();
        let elsewhere = fly(&fmu, &mut other, 100, 150);
        assert_eq!(
            first, elsewhere,
            "deserialized (Event Mode used: {same_instant})"
        );
        other.free_fmu_state(restored).unwrap();
        plant.free_fmu_state(saved).unwrap();
    }
}

#[test]
fn a_restored_fmi3_state_gives_back_the_outputs_it_was_saved_with() {
    let fmu = Fmu::load(fmu_dir().join("fmi3/LanderPlant.fmu")).unwrap();
    let mut plant = plant(&fmu, "outputs", false);
    fly(&fmu, &mut plant, 0, 50);
    let at_save = plant.get_real_by_name("r_nue[2]").unwrap();
    let saved = plant.get_fmu_state().unwrap();
    let bytes = plant.serialize_fmu_state(&saved).unwrap();
    fly(&fmu, &mut plant, 50, 80);
    assert_ne!(plant.get_real_by_name("r_nue[2]").unwrap(), at_save);
    let restored = plant.deserialize_fmu_state(&bytes).unwrap();
    plant.set_fmu_state(&restored).unwrap();
    assert_eq!(
        plant.get_real_by_name("r_nue[2]").unwrap().to_bits(),
        at_save.to_bits()
    );
}

#[test]
fn bytes_that_are_no_importer_fmi3_state_are_refused_without_calling_the_fmu() {
    let fmu = Fmu::load(fmu_dir().join("fmi3/LanderPlant.fmu")).unwrap();
    let mut plant = plant(&fmu, "foreign", false);
    let error = plant.deserialize_fmu_state(b"not a state").unwrap_err();
    assert_eq!(error.function, "fmi3DeserializeFMUState");
    assert!(error.to_string().contains("no header"), "{error}");
}

/// The LanderPlant of `file` (under target/fmu) unpacked with its description's
/// `attribute="true"` made false: an FMU that says it cannot do what its binary does.
fn declaring_false_in(file: &str, attribute: &str) -> (TempDir, Fmu) {
    let dir = TempDir::new().unwrap();
    unzip_to(&fmu_dir().join(file), dir.path());
    let path = dir.path().join("modelDescription.xml");
    let description = std::fs::read_to_string(&path).unwrap();
    let flag = format!("{attribute}=\"true\"");
    assert!(description.contains(&flag), "the plant declares {flag}");
    std::fs::write(
        &path,
        description.replace(&flag, &format!("{attribute}=\"false\"")),
    )
    .unwrap();
    let fmu = Fmu::load(dir.path()).unwrap();
    (dir, fmu)
}

fn declaring_false(attribute: &str) -> (TempDir, Fmu) {
    declaring_false_in("fmi3/LanderPlant.fmu", attribute)
}

#[test]
fn an_fmu_that_declares_it_cannot_serialize_is_refused_with_the_reason() {
    let (_dir, fmu) = declaring_false("canSerializeFMUState");
    let mut plant = plant(&fmu, "unserializable", false);
    assert!(plant.fmu_state_refusal(false).is_none());
    let reason = plant.fmu_state_refusal(true).unwrap();
    assert!(reason.contains("canSerializeFMUState"), "{reason}");
    // Get and set still work: the FMU declares those.
    let saved = plant.get_fmu_state().unwrap();
    let error = plant.serialize_fmu_state(&saved).unwrap_err();
    let CallError::Fmi(error) = error else {
        panic!("not an FMI error: {error:?}")
    };
    assert_eq!(error.function, "fmi3SerializeFMUState");
    assert!(error.to_string().contains("not called"), "{error}");
    assert!(
        error.to_string().contains("canSerializeFMUState"),
        "{error}"
    );

    let (_dir, fmu) = declaring_false("canGetAndSetFMUState");
    let mut plant = self::plant(&fmu, "stateless", false);
    let error = plant.get_fmu_state().unwrap_err();
    assert!(
        error.to_string().contains("canGetAndSetFMUState"),
        "{error}"
    );
}

#[test]
fn an_fmi2_fmu_that_declares_it_cannot_serialize_is_refused_as_well() {
    let (_dir, fmu) = declaring_false_in("LanderPlant.fmu", "canSerializeFMUstate");
    let mut plant = fmu.instantiate("unserializable", false).unwrap();
    let saved = plant.get_fmu_state().unwrap();
    let error = plant.serialize_fmu_state(&saved).unwrap_err().to_string();
    assert!(error.contains("fmi2SerializeFMUstate"), "{error}");
    assert!(error.contains("canSerializeFMUstate"), "{error}");
    let error = plant
        .deserialize_fmu_state(&[0; 8])
        .unwrap_err()
        .to_string();
    assert!(error.contains("not called"), "{error}");
}
