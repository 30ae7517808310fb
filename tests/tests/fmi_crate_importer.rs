//! The packaged FMUs in the importer of the `fmi` crate (rust-fmi 0.8): a Rust master we
//! did not write, with its own XML schema reader, its own bindings to the official headers
//! and its own callback functions.
// std's transcendental functions make test inputs here, outside any FMU (the
// workspace clippy.toml forbids them for the FMUs' sake).
#![allow(clippy::disallowed_methods)]
use fmi::fmi2::import::Fmi2Import;
use fmi::fmi2::instance::{CoSimulation, Common, InstanceCS};
use fmi::fmi2::Fmi2Res;
use fmi::schema::fmi2::{Causality, ScalarVariableElement};
use fmi::schema::traits::DefaultExperiment;
use fmi::traits::{FmiImport, FmiStatus};
use system_tests::{fmu_path, shipped_fmus};

const STEPS: u32 = 20;

fn import(model_identifier: &str) -> Fmi2Import {
    fmi::import::from_path(fmu_path(model_identifier)).unwrap_or_else(|e| {
        panic!("the fmi crate cannot import {model_identifier}: {e}");
    })
}

/// Value references of the Real outputs, as the fmi crate's own schema reader sees them.
fn real_outputs(import: &Fmi2Import) -> Vec<u32> {
    import
        .model_description()
        .get_model_variables()
        .filter(|v| v.causality == Causality::Output)
        .filter(|v| matches!(v.elem, ScalarVariableElement::Real(_)))
        .map(|v| v.value_reference)
        .collect()
}

/// The value reference of a variable by name, from the fmi crate's reading of the XML.
fn value_reference(import: &Fmi2Import, name: &str) -> u32 {
    import
        .model_description()
        .get_model_variables()
        .find(|v| v.name == name)
        .unwrap_or_else(|| panic!("no variable {name}"))
        .value_reference
}

fn initialize(instance: &mut InstanceCS) {
    instance.setup_experiment(None, 0.0, None).unwrap();
    instance.enter_initialization_mode().unwrap();
    instance.exit_initialization_mode().unwrap();
}

/// Steps `from..to` communication points of size `h` (t = i h, as an integer-counter master does).
fn step(instance: &mut InstanceCS, h: f64, from: u32, to: u32) {
    for i in from..to {
        let status = instance.do_step(f64::from(i) * h, h, true);
        assert!(
            matches!(status, Ok(Fmi2Res::OK | Fmi2Res::Warning)),
            "fmi2DoStep at step {i}: {status:?}"
        );
    }
}

fn get_reals(instance: &mut InstanceCS, vrs: &[u32]) -> Vec<f64> {
    let mut values = vec![f64::NAN; vrs.len()];
    instance.get_real(vrs, &mut values).unwrap();
    values
}

#[test]
fn every_fmu_loads_initializes_and_steps_in_the_fmi_crate() {
    for fmu in shipped_fmus() {
        let import = import(&fmu);
        let h = import.model_description().step_size().unwrap_or(1e-2);
        let outputs = real_outputs(&import);
        assert!(!outputs.is_empty(), "{} has no Real output", fmu);

        let mut instance = import.instantiate_cs("fmi-crate", false, false).unwrap();
        assert_eq!(instance.get_version(), "2.0");
        assert_eq!(instance.get_types_platform(), "default");
        initialize(&mut instance);
        step(&mut instance, h, 0, STEPS);
        let values = get_reals(&mut instance, &outputs);
        assert!(
            values.iter().all(|x| x.is_finite()),
            "{}: outputs after {STEPS} steps: {values:?}",
            fmu
        );
        let t_end = f64::from(STEPS) * h;
        let last = instance.last_successful_time().unwrap();
        assert!(
            (last - t_end).abs() <= 1e-9,
            "last successful time {last}, expected {t_end}"
        );
        assert!(!instance.terminated().unwrap());
        instance.terminate().unwrap();
    }
}

#[test]
fn oscillator_in_the_fmi_crate_follows_the_closed_form_and_restores_its_state() {
    let import = import("Oscillator");
    let vr = |name| value_reference(&import, name);
    let (x0, k, c) = (0.5, 4.0, 0.0);
    let h = 0.01;

    let mut instance = import.instantiate_cs("fmi-crate", false, false).unwrap();
    instance
        .set_real(&[vr("x0"), vr("k"), vr("c")], &[x0, k, c])
        .unwrap();
    initialize(&mut instance);

    // GIVEN no damping and no force, x = x0 cos(sqrt(k) t).
    step(&mut instance, h, 0, 100);
    let x_1s = get_reals(&mut instance, &[vr("x")])[0];
    let exact = x0 * (k.sqrt() * 1.0).cos();
    assert!(
        (x_1s - exact).abs() < 1e-9,
        "x(1 s) = {x_1s}, exact {exact}"
    );

    // WHEN the state at 1 s is saved, the run continued, and the state restored,
    let saved = instance.get_fmu_state().unwrap();
    step(&mut instance, h, 100, 150);
    let reference = get_reals(&mut instance, &[vr("x"), vr("v")]);
    instance.set_fmu_state(&saved).ok().unwrap();
    step(&mut instance, h, 100, 150);
    // THEN the continuation is bit for bit the same,
    assert_eq!(
        get_reals(&mut instance, &[vr("x"), vr("v")]),
        reference,
        "after fmi2SetFMUstate"
    );

    // AND the same holds for a state that went through serialization.
    let bytes = instance.serialize_fmu_state(&saved).unwrap();
    let restored = instance.deserialize_fmu_state(&bytes).unwrap();
    instance.set_fmu_state(&restored).ok().unwrap();
    step(&mut instance, h, 100, 150);
    assert_eq!(
        get_reals(&mut instance, &[vr("x"), vr("v")]),
        reference,
        "after fmi2DeSerializeFMUstate"
    );
    instance.terminate().unwrap();
}
