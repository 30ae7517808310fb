//! The bad-input table: one test per class of bad input, for every FMU the workspace
//! packages (its `[package.metadata.fmu]`), through its packaged C ABI; where a class needs
//! an FMU's own knowledge (which parameters its model refuses together), the five lander
//! FMUs are named. Each asserts the returned status and that the
//! log names the function and the variable or value; where a refusal must leave the instance
//! untouched, that is checked too.
use crate::common;

use common::assert_refused;
use model_description::{Causality, VariableKind};
use robustness_tests::ffi::*;
use robustness_tests::instance::{Fmu, Instance};
use robustness_tests::package::Lander;
use robustness_tests::reference::{legal_run, Wiring};
use std::ffi::CString;
use std::ptr;

fn every(test: impl Fn(&Fmu)) {
    for lander in Lander::all() {
        test(&Fmu::load(lander).expect("packaged FMU (run `cargo xtask fmus`)"));
    }
}

/// A settable input of each FMU (docs/interface.md).
fn an_input(fmu: &Fmu) -> &'static str {
    match fmu.lander() {
        Lander::Gnc => "q_body_to_nue[1]",
        Lander::Plant => "thrust_cmd",
        Lander::Nav => "q_body_to_nue_true[1]",
        Lander::Sensors => "q_body_to_nue[1]",
        Lander::Filter => "altimeter_range",
        _ => first_real(fmu, Causality::Input),
    }
}

/// The first Real variable of `causality` an FMU this table names no variable of declares
/// (leaked: a test process reads a handful).
fn first_real(fmu: &Fmu, causality: Causality) -> &'static str {
    let v = fmu
        .package
        .variables
        .iter()
        .find(|v| v.causality == causality && v.kind == VariableKind::Real)
        .unwrap_or_else(|| {
            panic!(
                "{} declares no Real {causality:?}",
                fmu.lander().model_identifier()
            )
        });
    Box::leak(v.name.clone().into_boxed_str())
}

/// An output of each FMU (docs/interface.md).
fn an_output(fmu: &Fmu) -> &'static str {
    match fmu.lander() {
        Lander::Gnc => "thrust_cmd",
        Lander::Plant => "r_nue[2]",
        Lander::Nav => "q_body_to_nue[3]",
        Lander::Sensors => "altimeter_range",
        Lander::Filter => "covariance_diag[1]",
        _ => first_real(fmu, Causality::Output),
    }
}

fn initialized(fmu: &Fmu) -> Instance<'_> {
    let inst = fmu.instantiate("bad-input", false);
    assert_eq!(inst.init_at(0.0), fmi2OK, "{:?}", inst.take_log());
    inst.take_log();
    inst
}

/// The reference: the legal run of a new instance.
fn reference(fmu: &Fmu) -> Vec<u64> {
    legal_run(&fmu.instantiate("reference", false), 10).expect("legal run")
}

#[test]
fn unknown_value_reference_is_refused_in_get_and_set() {
    every(|fmu| {
        let inst = initialized(fmu);
        let unknown = 9_999_999u32;
        let input = fmu.vr(an_input(fmu));
        let (_, before) = inst.get_reals(&[input]);
        let status = inst.set_reals(&[input, unknown], &[before[0] + 1.5, 2.0]);
        assert_refused(&inst, status, "fmi2SetReal", &["9999999"]);
        let (status, _) = inst.get_reals(&[unknown]);
        assert_refused(&inst, status, "fmi2GetReal", &["9999999"]);
        // All or nothing: the valid first pair of the refused set was not applied.
        let (status, after) = inst.get_reals(&[input]);
        assert_eq!(status, fmi2OK);
        assert_eq!(after[0].to_bits(), before[0].to_bits());
    });
}

#[test]
fn a_value_reference_of_another_type_is_refused() {
    every(|fmu| {
        let inst = initialized(fmu);
        // A Real input through the Integer and Boolean functions.
        let vr = fmu.vr(an_input(fmu));
        if !fmu
            .package
            .variables
            .iter()
            .any(|v| v.value_reference == vr && v.kind != model_description::VariableKind::Real)
        {
            let status = inst.set_integers(&[vr], &[1]);
            assert_refused(
                &inst,
                status,
                "fmi2SetInteger",
                &[&vr.to_string(), "Integer"],
            );
            let (status, _) = inst.get_booleans(&[vr]);
            assert_refused(
                &inst,
                status,
                "fmi2GetBoolean",
                &[&vr.to_string(), "Boolean"],
            );
        }
        let status = inst.set_strings(&[vr], &[c"text"]);
        assert_refused(&inst, status, "fmi2SetString", &[&vr.to_string(), "String"]);
    });
}

/// Neither lander declares a constant (the test model's own table covers that row); the
/// variables that are never settable are outputs and calculated parameters.
#[test]
fn a_variable_that_is_never_settable_is_refused_by_name() {
    every(|fmu| {
        let inst = fmu.instantiate("not-settable", false);
        let output = an_output(fmu);
        let status = inst.set_real_by_name(output, 1.0);
        assert_refused(&inst, status, "fmi2SetReal", &[output, "output"]);
        if fmu.lander() == Lander::Plant {
            let status = inst.set_real_by_name("rcs_torque_limit", 1.0);
            assert_refused(
                &inst,
                status,
                "fmi2SetReal",
                &["rcs_torque_limit", "calculated parameter"],
            );
        }
    });
}

#[test]
fn a_fixed_parameter_after_initialization_is_refused_and_unchanged() {
    every(|fmu| {
        let inst = initialized(fmu);
        let name = match fmu.lander() {
            Lander::Gnc => "phi_cmd",
            Lander::Plant => "m0",
            Lander::Nav => "r_nue_noise_sigma",
            Lander::Sensors => "accel_bias_sigma",
            Lander::Filter => "r0_sigma",
            // The conformance suite sets every fixed parameter of every FMU after
            // initialization; this table adds the packaged library's log for the five.
            _ => return,
        };
        let (_, before) = inst.get_reals(&[fmu.vr(name)]);
        let status = inst.set_real_by_name(name, 0.5);
        assert_refused(&inst, status, "fmi2SetReal", &[name, "fixed parameter"]);
        let (_, after) = inst.get_reals(&[fmu.vr(name)]);
        assert_eq!(before[0].to_bits(), after[0].to_bits());
    });
}

#[test]
fn non_finite_inputs_are_refused_naming_variable_and_value() {
    every(|fmu| {
        let inst = initialized(fmu);
        let name = an_input(fmu);
        for (value, shown) in [
            (f64::NAN, "NaN"),
            (f64::INFINITY, "inf"),
            (f64::NEG_INFINITY, "-inf"),
        ] {
            let status = inst.set_real_by_name(name, value);
            assert_refused(&inst, status, "fmi2SetReal", &[name, shown]);
        }
        // The instance goes on: the last finite value is still in place and a step works.
        assert_eq!(inst.step(0.0, 0.01), fmi2OK, "{:?}", inst.take_log());
    });
}

/// One call with harmless arguments, to probe the state machine.
#[derive(Debug, Clone, Copy)]
enum Call {
    Setup,
    EnterInit,
    ExitInit,
    Terminate,
    DoStep,
    SetReal,
    GetReal,
    LastSuccessfulTime,
    CancelStep,
}

impl Call {
    fn name(self) -> &'static str {
        match self {
            Call::Setup => "fmi2SetupExperiment",
            Call::EnterInit => "fmi2EnterInitializationMode",
            Call::ExitInit => "fmi2ExitInitializationMode",
            Call::Terminate => "fmi2Terminate",
            Call::DoStep => "fmi2DoStep",
            Call::SetReal => "fmi2SetReal",
            Call::GetReal => "fmi2GetReal",
            Call::LastSuccessfulTime => "fmi2GetRealStatus",
            Call::CancelStep => "fmi2CancelStep",
        }
    }

    fn run(self, inst: &Instance, t: f64) -> fmi2Status {
        let input = inst.fmu.vr(an_input(inst.fmu));
        match self {
            Call::Setup => inst.setup(0.0, None),
            Call::EnterInit => inst.enter_init(),
            Call::ExitInit => inst.exit_init(),
            Call::Terminate => inst.terminate(),
            Call::DoStep => inst.step(t, 0.01),
            Call::SetReal => inst.set_reals(&[input], &[0.5]),
            Call::GetReal => inst.get_reals(&[input]).0,
            Call::LastSuccessfulTime => inst.real_status(fmi2LastSuccessfulTime).0,
            // SAFETY: a live component.
            Call::CancelStep => unsafe { (inst.fmu.api.co_simulation.cancel_step)(inst.c) },
        }
    }
}

/// Puts a new instance in the named state; `None` where the FMU cannot reach it.
fn in_state<'a>(fmu: &'a Fmu, state: &str) -> Option<(Instance<'a>, f64)> {
    let inst = fmu.instantiate(state, false);
    let t = match state {
        "Instantiated" => 0.0,
        "InitializationMode" => {
            assert_eq!(inst.setup(0.0, None), fmi2OK);
            assert_eq!(inst.enter_init(), fmi2OK);
            0.0
        }
        "StepComplete" => {
            assert_eq!(inst.init_at(0.0), fmi2OK);
            0.0
        }
        "StepFailed" => {
            // Only the plant ends a step early (touchdown); the others always complete.
            if fmu.lander() != Lander::Plant {
                return None;
            }
            assert_eq!(inst.setup(0.0, None), fmi2OK);
            assert_eq!(inst.enter_init(), fmi2OK);
            assert_eq!(inst.set_real_by_name("r0_nue[2]", 0.5), fmi2OK);
            assert_eq!(inst.exit_init(), fmi2OK);
            assert_eq!(inst.step(0.0, 2.0), fmi2Discard, "{:?}", inst.take_log());
            inst.real_status(fmi2LastSuccessfulTime).1
        }
        "Terminated" => {
            assert_eq!(inst.init_at(0.0), fmi2OK);
            assert_eq!(inst.terminate(), fmi2OK);
            0.0
        }
        "Error" => {
            // A model failure: exit initialization with parameters the model refuses
            // together (each is within its own declared bounds).
            assert_eq!(inst.setup(0.0, None), fmi2OK);
            assert_eq!(inst.enter_init(), fmi2OK);
            let (bad, value) = match fmu.lander() {
                Lander::Gnc => ("thrust_min", 2000.0),
                Lander::Plant => ("dry_mass", 950.0),
                // Above the default max_latency_steps (0).
                Lander::Nav => ("mass_latency", 3.0),
                // A terrain normal pointing down.
                Lander::Sensors => ("terrain_slope_normal_nue[2]", -1.0),
                // An initial attitude that is no rotation (norm 0.5).
                Lander::Filter => ("q0_body_to_nue[1]", 0.5),
                // How to make another FMU's model fail is its own knowledge.
                _ => return None,
            };
            assert_eq!(inst.set_parameter(bad, value), fmi2OK);
            assert_eq!(inst.exit_init(), fmi2Error);
            0.0
        }
        other => panic!("unknown state {other}"),
    };
    inst.take_log();
    Some((inst, t))
}

#[test]
fn calls_in_each_illegal_state_are_refused_naming_the_function_and_the_state() {
    use Call::*;
    let table: [(&str, &[Call]); 6] = [
        (
            "Instantiated",
            &[
                ExitInit,
                Terminate,
                DoStep,
                GetReal,
                LastSuccessfulTime,
                CancelStep,
            ],
        ),
        (
            "InitializationMode",
            &[Setup, EnterInit, Terminate, DoStep, LastSuccessfulTime],
        ),
        ("StepComplete", &[Setup, EnterInit, ExitInit, CancelStep]),
        ("StepFailed", &[Setup, EnterInit, ExitInit, DoStep, SetReal]),
        (
            "Terminated",
            &[Setup, EnterInit, ExitInit, Terminate, DoStep, SetReal],
        ),
        (
            "Error",
            &[
                Setup,
                EnterInit,
                ExitInit,
                Terminate,
                DoStep,
                SetReal,
                LastSuccessfulTime,
            ],
        ),
    ];
    every(|fmu| {
        for (state, calls) in table {
            for call in calls {
                let Some((inst, t)) = in_state(fmu, state) else {
                    continue;
                };
                let status = call.run(&inst, t);
                assert_refused(
                    &inst,
                    status,
                    call.name(),
                    &["illegal call in state", state],
                );
            }
        }
    });
}

/// Every FMU with the next one of [`Lander::all`] (the last with the first).
fn pairs() -> Vec<(Fmu, Fmu)> {
    let load = |l: Lander| Fmu::load(l).expect("packaged FMU");
    let all = Lander::all();
    let n = all.len();
    (0..n)
        .map(|i| (load(all[i]), load(all[(i + 1) % n])))
        .collect()
}

#[test]
fn a_guid_mismatch_returns_null_and_says_why() {
    for (fmu, foreign) in &pairs() {
        let sink = Box::<robustness_tests::logger::LogSink>::default();
        let callbacks = sink.callbacks();
        // SAFETY: valid strings and callbacks for the duration of the call.
        let c = unsafe {
            (fmu.api.instantiate)(
                c"wrong-guid".as_ptr(),
                fmi2CoSimulation,
                foreign.guid().as_ptr(),
                ptr::null(),
                &callbacks,
                0,
                0,
            )
        };
        assert!(c.is_null());
        common::assert_refused_log(
            &sink.take(),
            fmi2Error,
            "fmi2Instantiate",
            &["fmuGUID", &foreign.package.guid],
        );
    }
}

#[test]
fn null_callbacks_or_a_null_logger_return_null() {
    every(|fmu| {
        let sink = Box::<robustness_tests::logger::LogSink>::default();
        let mut no_logger = sink.callbacks();
        no_logger.logger = None;
        for functions in [ptr::null(), &no_logger as *const fmi2CallbackFunctions] {
            // SAFETY: valid strings; the callbacks are NULL or a valid struct.
            let c = unsafe {
                (fmu.api.instantiate)(
                    c"no-callbacks".as_ptr(),
                    fmi2CoSimulation,
                    fmu.guid().as_ptr(),
                    ptr::null(),
                    functions,
                    0,
                    1,
                )
            };
            assert!(c.is_null());
        }
        // Nothing could be logged, and nothing was sent to the sink behind the NULL logger.
        assert!(sink.is_empty());
    });
}

#[test]
fn step_size_zero_negative_or_not_a_number_is_refused() {
    every(|fmu| {
        let inst = initialized(fmu);
        for (h, shown) in [
            (0.0, "0"),
            (-0.01, "-0.01"),
            (f64::NAN, "NaN"),
            (f64::INFINITY, "inf"),
        ] {
            let status = inst.step(0.0, h);
            assert_refused(
                &inst,
                status,
                "fmi2DoStep",
                &["communicationStepSize", shown],
            );
        }
        // Refusals moved nothing: the step from 0 is still the next one.
        assert_eq!(inst.step(0.0, 0.01), fmi2OK);
    });
}

#[test]
fn a_wrong_communication_point_is_refused_within_tolerance_accepted() {
    every(|fmu| {
        let inst = initialized(fmu);
        assert_eq!(inst.step(0.0, 0.01), fmi2OK);
        for t in [0.0, 0.02, 0.5, -1.0] {
            let status = inst.step(t, 0.01);
            assert_refused(
                &inst,
                status,
                "fmi2DoStep",
                &["currentCommunicationPoint", &t.to_string()],
            );
        }
        // A master's accumulated rounding (a few ulps) is not an error.
        assert_eq!(
            inst.step(0.01 - 1e-15, 0.01),
            fmi2OK,
            "{:?}",
            inst.take_log()
        );
    });
}

#[test]
fn truncated_corrupted_or_foreign_serialized_states_are_refused() {
    for (fmu, other) in &pairs() {
        let inst = initialized(fmu);
        assert_eq!(inst.step(0.0, 0.01), fmi2OK);
        let (_, state) = inst.get_fmu_state();
        let bytes = inst.serialize(state).expect("serialize");
        let foreign = {
            let o = initialized(other);
            let (_, s) = o.get_fmu_state();
            o.serialize(s).expect("serialize")
        };
        let mut bad_magic = bytes.clone();
        bad_magic[0] ^= 0x20;
        let mut flipped_payload = bytes.clone();
        *flipped_payload.last_mut().unwrap() ^= 0x01;
        let mut huge_length = bytes.clone();
        huge_length[32..40].copy_from_slice(&u64::MAX.to_le_bytes());
        let cases: [(&str, Vec<u8>, &str); 8] = [
            ("empty", Vec::new(), "shorter than"),
            ("header cut", bytes[..20].to_vec(), "shorter than"),
            (
                "one byte short",
                bytes[..bytes.len() - 1].to_vec(),
                "header announces",
            ),
            (
                "one byte more",
                [bytes.as_slice(), &[0]].concat(),
                "header announces",
            ),
            ("bad magic", bad_magic, "magic"),
            ("flipped payload bit", flipped_payload, "checksum"),
            ("length field u64::MAX", huge_length, "header announces"),
            ("the other FMU's state", foreign, "different FMU"),
        ];
        for (what, buffer, reason) in cases {
            let (status, made) = inst.deserialize(&buffer);
            assert!(made.is_null(), "{what}: a state was made");
            assert_refused(&inst, status, "fmi2DeSerializeFMUstate", &[reason]);
        }
        // Still usable: the genuine buffer restores the state exactly.
        let (status, restored) = inst.deserialize(&bytes);
        assert_eq!(status, fmi2OK);
        assert_eq!(inst.serialize(restored).expect("serialize"), bytes);
    }
}

/// Parameters set in initialization mode (name, value), then the variable the refusal must
/// name and the value it must show.
type ParameterCase = (&'static [(&'static str, f64)], &'static str, &'static str);

/// Each case's parameters set in a fresh instance make fmi2ExitInitializationMode refuse,
/// naming the parameter and what is shown; fmi2Reset then gives back an instance that flies
/// the legal run as `expected`.
fn assert_each_refused_at_exit(
    fmu: &Fmu,
    instance_name: &str,
    cases: &[ParameterCase],
    expected: &[u64],
) {
    for (sets, name, shown) in cases {
        let inst = fmu.instantiate(instance_name, false);
        assert_eq!(inst.setup(0.0, None), fmi2OK);
        assert_eq!(inst.enter_init(), fmi2OK);
        for (n, v) in *sets {
            assert_eq!(inst.set_parameter(n, *v), fmi2OK, "{n} = {v}");
        }
        let status = inst.exit_init();
        assert_refused(&inst, status, "fmi2ExitInitializationMode", &[name, shown]);
        assert_eq!(inst.reset(), fmi2OK);
        assert_eq!(legal_run(&inst, 10).expect("legal run"), expected);
    }
}

#[test]
fn out_of_range_plant_parameters_are_refused_by_name_and_reset_recovers() {
    let fmu = Fmu::load(Lander::Plant).expect("packaged FMU");
    let expected = reference(&fmu);
    // Outside the declared bounds: refused by the set itself.
    for (name, value, shown) in [
        ("m0", -5.0, "-5"),
        ("inertia_body[2]", -300.0, "-300"),
        ("inertia_body[1]", 0.0, "0"),
    ] {
        let inst = fmu.instantiate("plant-params", false);
        let status = inst.set_real_by_name(name, value);
        assert_refused(&inst, status, "fmi2SetReal", &[name, shown]);
    }
    // Within their bounds but refused together by exit initialization.
    let cases: [ParameterCase; 3] = [
        (&[("inertia_body[3]", 900.0)], "inertia_body[3]", "900"),
        (&[("engine_thrust_min", 900.0)], "engine_thrust_min", "900"),
        (&[("dry_mass", 950.0)], "m0", "dry_mass"),
    ];
    for (sets, name, shown) in cases {
        let inst = fmu.instantiate("plant-params", false);
        assert_eq!(inst.setup(0.0, None), fmi2OK);
        assert_eq!(inst.enter_init(), fmi2OK);
        for (n, v) in sets {
            assert_eq!(inst.set_real_by_name(n, *v), fmi2OK, "{n} = {v}");
        }
        let status = inst.exit_init();
        assert_refused(&inst, status, "fmi2ExitInitializationMode", &[name, shown]);
        // The instance is in state Error; fmi2Reset brings it back to a fresh one.
        assert_eq!(inst.reset(), fmi2OK);
        assert_eq!(legal_run(&inst, 10).expect("legal run"), expected);
    }
}

#[test]
fn out_of_range_gnc_parameters_are_refused_by_name_and_reset_recovers() {
    let fmu = Fmu::load(Lander::Gnc).expect("packaged FMU");
    let expected = reference(&fmu);
    // Outside the declared bounds (> 0): refused by the set itself, the bound included.
    for (name, value, shown) in [
        ("control_bandwidth", -1.0, "-1"),
        ("control_damping", -0.5, "-0.5"),
        ("inertia_body[2]", -300.0, "-300"),
        ("control_bandwidth", 0.0, "0"),
        ("control_damping", 0.0, "0"),
        ("guidance_bandwidth", 0.0, "0"),
        ("inertia_body[3]", 0.0, "0"),
    ] {
        let inst = fmu.instantiate("gnc-params", false);
        let status = inst.set_real_by_name(name, value);
        assert_refused(&inst, status, "fmi2SetReal", &[name, shown]);
    }
    // Accepted by the set, refused as a whole by exit initialization.
    let at_exit: [ParameterCase; 3] = [
        (&[("guidance_bandwidth", 6.0)], "guidance_bandwidth", "6"),
        (
            &[("control_bandwidth", 1e300)],
            "control_bandwidth",
            "= 1e300: gives gains whose torques overflow",
        ),
        (&[("thrust_min", 2000.0)], "thrust_max", "1600"),
    ];
    for (sets, name, shown) in at_exit {
        let inst = fmu.instantiate("gnc-params", false);
        assert_eq!(inst.setup(0.0, None), fmi2OK);
        assert_eq!(inst.enter_init(), fmi2OK);
        for (n, v) in sets {
            assert_eq!(inst.set_real_by_name(n, *v), fmi2OK, "{n} = {v}");
        }
        let status = inst.exit_init();
        assert_refused(&inst, status, "fmi2ExitInitializationMode", &[name, shown]);
        assert_eq!(inst.reset(), fmi2OK);
        assert_eq!(legal_run(&inst, 10).expect("legal run"), expected);
    }
}

#[test]
fn out_of_range_nav_parameters_are_refused_by_name_and_reset_recovers() {
    let fmu = Fmu::load(Lander::Nav).expect("packaged FMU");
    let expected = reference(&fmu);
    // Outside their own ranges: refused by the set itself (Integers through fmi2SetInteger).
    for (name, value, function, shown) in [
        ("r_nue_noise_sigma", -0.1, "fmi2SetReal", "-0.1"),
        ("attitude_random_walk", -1e-3, "fmi2SetReal", "-0.001"),
        ("mass_quantum", f64::NAN, "fmi2SetReal", "NaN"),
        ("omega_body_bias[2]", f64::INFINITY, "fmi2SetReal", "inf"),
        ("seed", -1.0, "fmi2SetInteger", "-1"),
        ("v_nue_latency", 10_001.0, "fmi2SetInteger", "10001"),
        ("max_latency_steps", -2.0, "fmi2SetInteger", "-2"),
    ] {
        let inst = fmu.instantiate("nav-params", false);
        assert_eq!(inst.setup(0.0, None), fmi2OK);
        assert_eq!(inst.enter_init(), fmi2OK);
        let status = inst.set_parameter(name, value);
        assert_refused(&inst, status, function, &[name, shown]);
        // Refused values are not kept: initialization goes on with the defaults.
        assert_eq!(inst.exit_init(), fmi2OK, "{:?}", inst.take_log());
    }
    // Accepted one by one, refused together (or as overflowing) by exit initialization.
    let at_exit: [ParameterCase; 3] = [
        (
            &[("max_latency_steps", 2.0), ("attitude_latency", 3.0)],
            "attitude_latency",
            "max_latency_steps",
        ),
        (
            &[("r_nue_noise_sigma", 1e308)],
            "r_nue_noise_sigma",
            "overflow",
        ),
        // Finite, but its rotation angle is not (found by the fuzzer: a NaN quaternion).
        (
            &[("attitude_bias[1]", -1e300)],
            "attitude_noise_sigma",
            "overflow",
        ),
    ];
    assert_each_refused_at_exit(&fmu, "nav-params", &at_exit, &expected);
}

/// A random walk over an enormous communication step would overflow: LanderNav refuses that
/// step with its outputs untouched (the instance is then in state Error, as after any
/// fmi2Error), and fmi2Reset brings back a fresh instance.
#[test]
fn a_nav_step_whose_random_walk_would_overflow_is_refused_and_reset_recovers() {
    let fmu = Fmu::load(Lander::Nav).expect("packaged FMU");
    let expected = reference(&fmu);
    let inst = fmu.instantiate("overflow", false);
    assert_eq!(inst.setup(0.0, None), fmi2OK);
    assert_eq!(inst.enter_init(), fmi2OK);
    assert_eq!(inst.set_parameter("seed", 3.0), fmi2OK);
    assert_eq!(inst.set_parameter("v_nue_random_walk", 1e200), fmi2OK);
    assert_eq!(inst.exit_init(), fmi2OK, "{:?}", inst.take_log());
    let estimates = Wiring::of(&fmu).outputs;
    let (_, before) = inst.get_reals(&estimates);
    let status = inst.step(0.0, 1e300);
    assert_refused(
        &inst,
        status,
        "fmi2DoStep",
        &["v_nue_random_walk", "overflow"],
    );
    let (status, after) = inst.get_reals(&estimates);
    assert_eq!(status, fmi2OK, "{:?}", inst.take_log());
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&after), bits(&before));
    assert_eq!(inst.reset(), fmi2OK);
    assert_eq!(legal_run(&inst, 10).expect("legal run"), expected);
}

#[test]
fn a_non_finite_phi_cmd_is_refused_at_once() {
    let fmu = Fmu::load(Lander::Gnc).expect("packaged FMU");
    let inst = fmu.instantiate("phi-cmd", false);
    assert_eq!(inst.setup(0.0, None), fmi2OK);
    assert_eq!(inst.enter_init(), fmi2OK);
    for (value, shown) in [
        (f64::NAN, "NaN"),
        (f64::INFINITY, "inf"),
        (f64::NEG_INFINITY, "-inf"),
    ] {
        let status = inst.set_real_by_name("phi_cmd", value);
        assert_refused(&inst, status, "fmi2SetReal", &["phi_cmd", shown]);
    }
    // The default (0) is untouched and initialization goes on.
    assert_eq!(inst.get_reals(&[fmu.vr("phi_cmd")]).1, vec![0.0]);
    assert_eq!(inst.exit_init(), fmi2OK);
}

/// docs/interface.md: degenerate first inputs (a master that zeroes every input) give a warning
/// and safe commands, never NaN and never an error.
#[test]
fn degenerate_gnc_inputs_give_a_warning_and_safe_commands() {
    let fmu = Fmu::load(Lander::Gnc).expect("packaged FMU");
    let inst = initialized(&fmu);
    let wiring = Wiring::of(&fmu);
    assert_eq!(
        inst.set_reals(&wiring.inputs, &vec![0.0; wiring.inputs.len()]),
        fmi2OK
    );
    let commands: Vec<u32> = [
        "thrust_cmd",
        "torque_cmd_body[1]",
        "torque_cmd_body[2]",
        "torque_cmd_body[3]",
    ]
    .iter()
    .map(|n| fmu.vr(n))
    .collect();
    let (status, values) = inst.get_reals(&commands);
    assert_eq!(status, fmi2Warning);
    let (_, thrust_min) = inst.get_reals(&[fmu.vr("thrust_min")]);
    assert_eq!(values, vec![thrust_min[0], 0.0, 0.0, 0.0]);
    assert!(inst
        .take_log()
        .iter()
        .any(|r| r.status == fmi2Warning && r.message().starts_with("fmi2GetReal")));
    // The step meets the same fault: counted, not logged again, so OK.
    assert_eq!(inst.step(0.0, 0.01), fmi2OK);
    assert!(inst.take_log().iter().all(|r| r.status != fmi2Warning));
}

#[test]
fn null_arrays_with_a_count_are_refused() {
    every(|fmu| {
        let inst = initialized(fmu);
        let vr = fmu.vr(an_input(fmu));
        let value = 1.0f64;
        // SAFETY: a live component; the NULL arrays are what is being tested.
        let status = unsafe { (fmu.api.set_real)(inst.c, ptr::null(), 1, &value) };
        assert_refused(&inst, status, "fmi2SetReal", &["vr", "NULL"]);
        let status = unsafe { (fmu.api.get_real)(inst.c, &vr, 1, ptr::null_mut()) };
        assert_refused(&inst, status, "fmi2GetReal", &["value", "NULL"]);
        // A count of zero needs no arrays.
        let status = unsafe { (fmu.api.get_real)(inst.c, ptr::null(), 0, ptr::null_mut()) };
        assert_eq!(status, fmi2OK);
    });
}

#[test]
fn a_null_or_foreign_component_is_refused_without_a_crash() {
    every(|fmu| {
        let not_an_instance = Box::new([0u64; 16]);
        let name = CString::new("x").unwrap();
        for c in [ptr::null_mut(), not_an_instance.as_ptr() as fmi2Component] {
            // SAFETY: NULL or readable memory that is not an instance: what is being tested.
            unsafe {
                assert_eq!((fmu.api.co_simulation.do_step)(c, 0.0, 0.01, 1), fmi2Error);
                assert_eq!((fmu.api.reset)(c), fmi2Error);
                assert_eq!((fmu.api.enter_initialization_mode)(c), fmi2Error);
                (fmu.api.free_instance)(c);
            }
        }
        drop(name);
    });
}

/// A huge communication step (1e300 s) must not hang the master's call. The plant, climbing
/// at 1e6 m/s, would stay aloft for 1.2e6 s of RK4 sub-steps; it refuses the step instead.
#[test]
fn a_huge_communication_step_returns_at_once() {
    let dog = robustness_tests::fuzz::Watchdog::start(std::time::Duration::from_secs(10));
    every(|fmu| {
        let inst = fmu.instantiate("huge-step", false);
        assert_eq!(inst.setup(0.0, None), fmi2OK);
        assert_eq!(inst.enter_init(), fmi2OK);
        if fmu.lander() == Lander::Plant {
            assert_eq!(inst.set_real_by_name("v0_nue[2]", 1e6), fmi2OK);
        }
        assert_eq!(inst.exit_init(), fmi2OK);
        inst.take_log();
        let status = dog.watch("fmi2DoStep(h = 1e300)", || inst.step(0.0, 1e300));
        match fmu.lander() {
            Lander::Plant => assert_refused(
                &inst,
                status,
                "fmi2DoStep",
                &["communicationStepSize", "sub-steps"],
            ),
            // The filter's position would overflow (gravity over 1e300 s): refused.
            Lander::Filter => assert_refused(
                &inst,
                status,
                "fmi2DoStep",
                &["communicationStepSize 1e300", "not be finite"],
            ),
            // The GNC's, LanderNav's (errors off) and the sensors' steps cost the same
            // whatever their size (the sensors' bias walk over 1e300 s is 1e145: finite).
            Lander::Gnc | Lander::Nav | Lander::Sensors => {
                assert_eq!(status, fmi2OK, "{:?}", inst.take_log())
            }
            // Another FMU takes the step (OK), or warns or refuses saying why, and never
            // fails: what it makes of such a step is its own knowledge.
            _ => {
                let log = inst.take_log();
                assert!(
                    status == fmi2OK
                        || ((status == fmi2Warning
                            || status == fmi2Error
                            || status == fmi2Discard)
                            && log.iter().any(|r| r.message().starts_with("fmi2DoStep:"))),
                    "{}: {} {log:#?}",
                    fmu.lander().model_identifier(),
                    status.label()
                );
            }
        }
    });
}

/// Parameters are validated at fmi2ExitInitializationMode, but a get in initialization mode
/// already evaluates the model with them: crossed limits must not make it fail (found by the
/// fuzzer: fmi2GetReal answered fmi2Fatal after thrust_max < thrust_min).
#[test]
fn a_get_in_initialization_mode_with_inconsistent_parameters_is_not_fatal() {
    let fmu = Fmu::load(Lander::Gnc).expect("packaged FMU");
    let inst = fmu.instantiate("crossed-limits", false);
    assert_eq!(inst.setup(0.0, None), fmi2OK);
    assert_eq!(inst.enter_init(), fmi2OK);
    assert_eq!(inst.set_real_by_name("thrust_max", 489.0), fmi2OK);
    let (status, values) = inst.get_reals(&[fmu.vr("thrust_cmd")]);
    assert!(
        status == fmi2OK || status == fmi2Warning,
        "{}: {:?}",
        status.label(),
        inst.take_log()
    );
    assert!(values[0].is_finite());
    let status = inst.exit_init();
    assert_refused(
        &inst,
        status,
        "fmi2ExitInitializationMode",
        &["thrust_max", "489"],
    );
}

/// In initialization mode the outputs already carry the first interval's errors, before
/// exit_initialization validates them: parameters it will refuse must not make a read
/// publish a non-finite estimate (found by the fuzzer: a NaN quaternion from
/// attitude_bias[1] = -1e300).
#[test]
fn a_nav_get_in_initialization_mode_with_overflowing_errors_is_finite() {
    let fmu = Fmu::load(Lander::Nav).expect("packaged FMU");
    for (name, value) in [("attitude_bias[1]", -1e300), ("r_nue_noise_sigma", 1e308)] {
        let inst = fmu.instantiate("overflow-in-init", false);
        assert_eq!(inst.setup(0.0, None), fmi2OK);
        assert_eq!(inst.enter_init(), fmi2OK);
        assert_eq!(inst.set_parameter(name, value), fmi2OK);
        let (status, values) = inst.get_reals(&Wiring::of(&fmu).outputs);
        assert_eq!(status, fmi2OK, "{:?}", inst.take_log());
        assert!(values.iter().all(|v| v.is_finite()), "{name}: {values:?}");
        let status = inst.exit_init();
        assert_refused(&inst, status, "fmi2ExitInitializationMode", &["overflow"]);
    }
}

#[test]
fn out_of_range_sensors_parameters_are_refused_by_name_and_reset_recovers() {
    let fmu = Fmu::load(Lander::Sensors).expect("packaged FMU");
    let expected = reference(&fmu);
    // Outside their declared bounds: refused by the set itself.
    for (name, value, function, shown) in [
        ("accel_bias_sigma", -1.0, "fmi2SetReal", "-1"),
        ("imu_sample_period", 0.0, "fmi2SetReal", "0"),
        ("altimeter_dropout_probability", 1.5, "fmi2SetReal", "1.5"),
        ("gyro_misalignment[2]", 0.2, "fmi2SetReal", "0.2"),
        ("accel_scale_factor_sigma", 0.06, "fmi2SetReal", "0.06"),
        ("gyro_misalignment_sigma", -1e-3, "fmi2SetReal", "-0.001"),
        ("velocimeter_max_range", f64::NAN, "fmi2SetReal", "NaN"),
        ("seed", -1.0, "fmi2SetInteger", "-1"),
    ] {
        let inst = fmu.instantiate("sensors-params", false);
        assert_eq!(inst.setup(0.0, None), fmi2OK);
        assert_eq!(inst.enter_init(), fmi2OK);
        let status = inst.set_parameter(name, value);
        assert_refused(&inst, status, function, &[name, shown]);
        assert_eq!(inst.exit_init(), fmi2OK, "{:?}", inst.take_log());
    }
    // Accepted one by one, refused by exit initialization: directions without one.
    let at_exit: [ParameterCase; 3] = [
        (
            &[("altimeter_beam_body[2]", 0.0)],
            "altimeter_beam_body",
            "length",
        ),
        (
            &[
                ("velocimeter_beam_2_body[1]", 0.0),
                ("velocimeter_beam_2_body[2]", 0.0),
                ("velocimeter_beam_2_body[3]", 0.0),
            ],
            "velocimeter_beam_2_body",
            "length",
        ),
        (
            &[("terrain_slope_normal_nue[2]", -1.0)],
            "terrain_slope_normal_nue",
            "Up",
        ),
    ];
    assert_each_refused_at_exit(&fmu, "sensors-params", &at_exit, &expected);
}

#[test]
fn out_of_range_filter_parameters_are_refused_by_name_and_reset_recovers() {
    let fmu = Fmu::load(Lander::Filter).expect("packaged FMU");
    let expected = reference(&fmu);
    for (name, value, shown) in [
        ("altimeter_noise_sigma", 0.0, "0"),
        ("velocimeter_noise_sigma", -0.02, "-0.02"),
        ("gravity", -1.62, "-1.62"),
        ("q0_body_to_nue[1]", 1.5, "1.5"),
        ("chi2_gate", 0.0, "0"),
        ("attitude0_sigma", f64::INFINITY, "inf"),
        ("gyro_scale_factor_sigma", 0.2, "0.2"),
        ("accel_misalignment_sigma", -1e-3, "-0.001"),
    ] {
        let inst = fmu.instantiate("filter-params", false);
        assert_eq!(inst.setup(0.0, None), fmi2OK);
        assert_eq!(inst.enter_init(), fmi2OK);
        let status = inst.set_parameter(name, value);
        assert_refused(&inst, status, "fmi2SetReal", &[name, shown]);
        assert_eq!(inst.exit_init(), fmi2OK, "{:?}", inst.take_log());
    }
    let at_exit: [ParameterCase; 4] = [
        (&[("q0_body_to_nue[1]", 0.5)], "q0_body_to_nue", "0.5"),
        // Within its bounds, but the white noise variance of one sample overflows.
        (
            &[("imu_sample_period", 5e-324)],
            "imu_sample_period",
            "overflows",
        ),
        (
            &[("terrain_slope_normal_nue[2]", 0.0)],
            "terrain_slope_normal_nue",
            "length",
        ),
        (
            &[("altimeter_beam_body[2]", 0.0)],
            "altimeter_beam_body",
            "length",
        ),
    ];
    assert_each_refused_at_exit(&fmu, "filter-params", &at_exit, &expected);
}

/// docs/sensors.md: a quaternion input that is no rotation shows as no measurement with a
/// warning naming it, and the step from there is refused with that reason.
#[test]
fn a_sensors_quaternion_that_is_no_rotation_warns_at_the_read_and_refuses_the_step() {
    let fmu = Fmu::load(Lander::Sensors).expect("packaged FMU");
    let inst = initialized(&fmu);
    let wiring = Wiring::of(&fmu);
    assert_eq!(wiring.set_inputs(&inst, 0.0), fmi2OK);
    assert_eq!(inst.set_real_by_name("q_body_to_nue[1]", 0.5), fmi2OK);
    let (status, outputs) = wiring.get_outputs(&inst);
    assert_eq!(status, fmi2Warning, "{:?}", inst.take_log());
    assert!(outputs.reals.iter().all(|v| *v == 0.0), "{outputs:?}");
    assert!(
        outputs.booleans.iter().all(|b| *b == fmi2False),
        "{outputs:?}"
    );
    assert!(inst.take_log().iter().any(|r| r.status == fmi2Warning
        && r.message().starts_with("fmi2GetReal")
        && r.message().contains("q_body_to_nue")));
    let status = inst.step(0.0, 0.01);
    assert_refused(&inst, status, "fmi2DoStep", &["q_body_to_nue", "norm"]);
}

/// LanderFilter refuses a step whose estimate would not be finite with its outputs untouched
/// (docs/filter.md), and fmi2Reset brings back a fresh instance.
#[test]
fn a_filter_step_whose_estimate_would_overflow_is_refused_and_reset_recovers() {
    let fmu = Fmu::load(Lander::Filter).expect("packaged FMU");
    let expected = reference(&fmu);
    let inst = initialized(&fmu);
    let wiring = Wiring::of(&fmu);
    assert_eq!(wiring.set_inputs(&inst, 0.0), fmi2OK);
    assert_eq!(inst.set_real_by_name("accel_body_meas[2]", 1e300), fmi2OK);
    let (_, before) = wiring.get_outputs(&inst);
    let status = inst.step(0.0, 1e10);
    assert_refused(&inst, status, "fmi2DoStep", &["not be finite"]);
    let (status, after) = wiring.get_outputs(&inst);
    assert_eq!(status, fmi2OK, "{:?}", inst.take_log());
    assert_eq!(
        after.bits().collect::<Vec<_>>(),
        before.bits().collect::<Vec<_>>()
    );
    assert_eq!(inst.reset(), fmi2OK);
    assert_eq!(legal_run(&inst, 10).expect("legal run"), expected);
}
