//! Every function in every reachable state: legal or refused as an illegal call, exactly
//! as the table says; and the table itself against rows read off the standard.
//!
//! StepCanceled is unreachable (fmi2DoStep never returns fmi2Pending, so fmi2CancelStep is
//! never legal) and Fatal needs a panicking model: both are covered in fmi2-export's tests.
use crate::common;

use common::{vr, Fmu};
use fmi2_export::state::{Function, State};
use fmi_testkit::fmi2::*;
use fmu_testmodel as fmu;
use std::ptr::{null, null_mut};

/// A fresh instance driven into `state`.
fn in_state(state: State) -> Fmu {
    let fmu = Fmu::new(false);
    match state {
        State::Instantiated => {}
        State::InitializationMode => {
            fmu.setup(0.0, None);
            fmu.enter_init();
        }
        State::StepComplete => fmu.init(),
        State::StepFailed => {
            fmu.set_boolean(vr::STOP_AT_THRESHOLD, true);
            fmu.set_real(vr::THRESHOLD, 0.99999);
            fmu.init();
            assert_eq!(fmu.step(0.0, 0.01), fmi2Discard);
        }
        State::Terminated => {
            fmu.init();
            assert_eq!(unsafe { fmu::fmi2Terminate(fmu.c) }, fmi2OK);
        }
        State::Error => {
            fmu.set_boolean(vr::STOP_AT_THRESHOLD, true);
            fmu.set_real(vr::THRESHOLD, 1.0);
            fmu.setup(0.0, None);
            fmu.enter_init();
            assert_eq!(fmu.exit_init(), fmi2Error);
        }
        State::StepCanceled | State::Fatal => unreachable!("not reachable with this model"),
        State::EventMode | State::ContinuousTimeMode => {
            unreachable!("Model Exchange states: a Co-Simulation instance never enters them")
        }
    }
    fmu.clear();
    fmu
}

/// Calls `f` with valid arguments (any state-independent refusal is not "illegal call").
fn call(fmu: &Fmu, f: Function) -> fmi2Status {
    let c = fmu.c;
    let (x, label, stop) = (vr::X, vr::LABEL, vr::STOP_AT_THRESHOLD);
    let mut real = 0.0;
    let mut int = 0;
    let mut string: fmi2String = null();
    let mut status = fmi2OK;
    unsafe {
        match f {
            Function::SetDebugLogging => fmu::fmi2SetDebugLogging(c, fmi2True, 0, null()),
            Function::FreeInstance => unreachable!("returns void; tested on its own"),
            Function::SetupExperiment => fmu::fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0),
            Function::EnterInitializationMode => fmu::fmi2EnterInitializationMode(c),
            Function::ExitInitializationMode => fmu::fmi2ExitInitializationMode(c),
            Function::Terminate => fmu::fmi2Terminate(c),
            Function::Reset => fmu::fmi2Reset(c),
            Function::GetReal => fmu::fmi2GetReal(c, &x, 1, &mut real),
            Function::GetInteger => fmu::fmi2GetInteger(c, &vr::STEP_COUNT, 1, &mut int),
            Function::GetBoolean => fmu::fmi2GetBoolean(c, &stop, 1, &mut int),
            Function::GetString => fmu::fmi2GetString(c, &label, 1, &mut string),
            Function::SetReal => fmu::fmi2SetReal(c, &vr::U, 1, &0.5),
            Function::SetInteger => fmu::fmi2SetInteger(c, &vr::SUBSTEPS, 1, &4),
            Function::SetBoolean => fmu::fmi2SetBoolean(c, &stop, 1, &fmi2False),
            Function::SetString => fmu::fmi2SetString(c, &label, 1, &c"l".as_ptr()),
            Function::GetFMUstate => {
                let mut state = null_mut();
                let s = fmu::fmi2GetFMUstate(c, &mut state);
                fmu::fmi2FreeFMUstate(c, &mut state);
                s
            }
            Function::FreeFMUstate => fmu::fmi2FreeFMUstate(c, &mut null_mut()),
            Function::SetFMUstate
            | Function::SerializedFMUstateSize
            | Function::SerializeFMUstate
            | Function::DeSerializeFMUstate => {
                // GetFMUstate is legal wherever these are (checked by the table test).
                let mut state = null_mut();
                let got = fmu::fmi2GetFMUstate(c, &mut state);
                let mut bytes = vec![];
                if got == fmi2OK {
                    bytes = fmu.serialize(state);
                }
                fmu.clear();
                let mut size = 0;
                let s = match f {
                    Function::SetFMUstate => fmu::fmi2SetFMUstate(c, state),
                    Function::SerializedFMUstateSize => {
                        fmu::fmi2SerializedFMUstateSize(c, state, &mut size)
                    }
                    Function::SerializeFMUstate => fmu::fmi2SerializeFMUstate(
                        c,
                        state,
                        bytes.as_mut_ptr() as *mut fmi2Byte,
                        bytes.len(),
                    ),
                    _ => fmu::fmi2DeSerializeFMUstate(
                        c,
                        bytes.as_ptr() as *const fmi2Byte,
                        bytes.len(),
                        &mut state,
                    ),
                };
                fmu::fmi2FreeFMUstate(c, &mut state);
                s
            }
            Function::GetDirectionalDerivative => {
                fmu::fmi2GetDirectionalDerivative(c, &x, 1, &vr::U, 1, &1.0, &mut real)
            }
            Function::SetRealInputDerivatives => {
                fmu::fmi2SetRealInputDerivatives(c, &vr::U, 1, &1, &1.0)
            }
            Function::GetRealOutputDerivatives => {
                fmu::fmi2GetRealOutputDerivatives(c, &x, 1, &1, &mut real)
            }
            Function::DoStep => fmu::fmi2DoStep(c, 0.0, 0.01, fmi2True),
            Function::CancelStep => fmu::fmi2CancelStep(c),
            Function::GetStatus => fmu::fmi2GetStatus(c, fmi2DoStepStatus, &mut status),
            Function::GetRealStatus => fmu::fmi2GetRealStatus(c, fmi2LastSuccessfulTime, &mut real),
            Function::GetIntegerStatus => fmu::fmi2GetIntegerStatus(c, fmi2DoStepStatus, &mut int),
            Function::GetBooleanStatus => fmu::fmi2GetBooleanStatus(c, fmi2Terminated, &mut int),
            Function::GetStringStatus => {
                fmu::fmi2GetStringStatus(c, fmi2PendingStatus, &mut string)
            }
            // The Oscillator is Co-Simulation only: it does not export them (the plant's
            // Model Exchange tests call them).
            f if Function::MODEL_EXCHANGE.contains(&f) => unreachable!("{}", f.name()),
            _ => unreachable!(),
        }
    }
}

const REACHABLE: [State; 6] = [
    State::Instantiated,
    State::InitializationMode,
    State::StepComplete,
    State::StepFailed,
    State::Terminated,
    State::Error,
];

#[test]
fn every_function_in_every_state_is_legal_or_refused_as_the_table_says() {
    let mut checked = 0;
    for &f in Function::ALL {
        if f == Function::FreeInstance || Function::MODEL_EXCHANGE.contains(&f) {
            continue;
        }
        for state in REACHABLE {
            let fmu = in_state(state);
            let status = call(&fmu, f);
            let illegal_line = format!("{}: illegal call in state {state:?}", f.name());
            let refused = fmu.messages().contains(&illegal_line);
            let legal = f.legal_states().contains(state);
            assert_eq!(
                refused,
                !legal,
                "{} in {state:?}: {:?}",
                f.name(),
                fmu.messages()
            );
            if refused {
                assert_eq!(status, fmi2Error);
                assert_eq!(fmu.messages().len(), 1, "one line: {:?}", fmu.messages());
            }
            checked += 1;
        }
    }
    assert_eq!(checked, 30 * 6);
}

/// A refused call leaves the state alone: DoStep in Instantiated, then the normal path works.
#[test]
fn an_illegal_call_changes_nothing() {
    let fmu = in_state(State::Instantiated);
    assert_eq!(call(&fmu, Function::DoStep), fmi2Error);
    assert_eq!(call(&fmu, Function::ExitInitializationMode), fmi2Error);
    fmu.init();
    assert_eq!(fmu.step(0.0, 0.01), fmi2OK);
}

#[test]
fn free_instance_is_accepted_in_every_state() {
    for state in REACHABLE {
        let fmu = in_state(state);
        let _ = fmu.get_state(); // owned states are released with the instance
        drop(fmu);
    }
    unsafe { fmu::fmi2FreeInstance(null_mut()) };
}

/// Rows of the FMI 2.0.4 state tables, written out by hand from the standard (§4.2.4
/// Co-Simulation and §3.2.3 Model Exchange, whose EventMode and ContinuousTimeMode a
/// Co-Simulation instance never enters), independently of the masks in fmi2-export.
#[test]
fn table_rows_agree_with_the_standard_text() {
    use State::*;
    let rows: [(Function, &[State]); 9] = [
        (Function::DoStep, &[StepComplete]),
        (
            Function::SetReal,
            &[
                Instantiated,
                InitializationMode,
                StepComplete,
                EventMode,
                ContinuousTimeMode,
            ],
        ),
        (
            Function::GetReal,
            &[
                InitializationMode,
                StepComplete,
                StepFailed,
                StepCanceled,
                Terminated,
                Error,
                EventMode,
                ContinuousTimeMode,
            ],
        ),
        (Function::SetupExperiment, &[Instantiated]),
        (Function::EnterInitializationMode, &[Instantiated]),
        (Function::ExitInitializationMode, &[InitializationMode]),
        (
            Function::Terminate,
            &[StepComplete, StepFailed, EventMode, ContinuousTimeMode],
        ),
        (
            Function::Reset,
            &[
                Instantiated,
                InitializationMode,
                StepComplete,
                StepFailed,
                StepCanceled,
                Terminated,
                Error,
                EventMode,
                ContinuousTimeMode,
            ],
        ),
        (
            Function::GetBooleanStatus,
            &[StepComplete, StepFailed, Terminated],
        ),
    ];
    for (f, legal) in rows {
        for s in State::ALL {
            assert_eq!(
                f.legal_states().contains(s),
                legal.contains(&s),
                "{} in {s:?}",
                f.name()
            );
        }
    }
}

// ---- Both versions, through the kit's driver ----

use common::{Osc, Status, Version};

/// The name of a state in the version's messages: FMI 2.0's state names are the
/// export's own (the standard's state chart has no names for messages); FMI 3.0 names its
/// states (§3.2: "Initialization Mode", "Step Mode", "Event Mode", "Terminated").
fn state_name<D: Osc>(fmi2: &str, fmi3: &str) -> String {
    match D::VERSION {
        Version::Fmi2 => fmi2.into(),
        Version::Fmi3 => fmi3.into(),
    }
}

/// An illegal call is refused with fmi*Error and one line naming the function and the
/// state, and changes nothing: the normal path goes on.
fn illegal_calls_are_refused_by_state_name_and_change_nothing<D: Osc>() {
    let fmu = D::open(false);
    let illegal = |status: Status, function: &str, state: &str| {
        assert_eq!(status, Status::Error, "{:?}", fmu.messages());
        assert_eq!(
            fmu.messages(),
            vec![format!("{}: illegal call in state {state}", D::f(function))]
        );
        fmu.clear_log();
    };
    illegal(fmu.step(0.0, 0.01).status, "DoStep", "Instantiated");
    illegal(
        fmu.exit_initialization_mode(),
        "ExitInitializationMode",
        "Instantiated",
    );
    assert_eq!(fmu.enter_initialization_mode(0.0, None), Status::Ok);
    illegal(
        fmu.step(0.0, 0.01).status,
        "DoStep",
        &state_name::<D>("InitializationMode", "Initialization Mode"),
    );
    assert_eq!(fmu.exit_initialization_mode(), Status::Ok);
    illegal(
        fmu.exit_initialization_mode(),
        "ExitInitializationMode",
        &state_name::<D>("StepComplete", "Step Mode"),
    );
    // A fixed parameter after initialization is refused as not settable (no state line).
    assert_eq!(fmu.set_integer(vr::SUBSTEPS, 2), Status::Error);
    fmu.clear_log();
    assert_eq!(fmu.step(0.0, 0.01).status, Status::Ok, "nothing changed");
    assert_eq!(fmu.integer(vr::SUBSTEPS), 8);
    assert_eq!(fmu.terminate(), Status::Ok);
    illegal(fmu.step(0.01, 0.01).status, "DoStep", "Terminated");
    illegal(fmu.terminate(), "Terminate", "Terminated");
    assert_eq!(fmu.reset(), Status::Ok);
    fmu.initialize();
    assert_eq!(fmu.step(0.0, 0.01).status, Status::Ok);
}

/// The Error state: after a failed initialization only Reset (and FreeInstance, and the
/// gets) are accepted; a set is refused naming the state.
fn the_error_state_admits_reset_in_each_version<D: Osc>() {
    let fmu = D::open(false);
    fmu.set_boolean(vr::STOP_AT_THRESHOLD, true);
    fmu.set_real(vr::THRESHOLD, 1.0);
    fmu.enter_initialization_mode(0.0, None);
    assert_eq!(fmu.exit_initialization_mode(), Status::Error);
    fmu.clear_log();
    assert_eq!(fmu.set_real(vr::U, 1.0), Status::Error);
    assert_eq!(
        fmu.last_message(),
        format!("{}: illegal call in state Error", D::real_fn(true))
    );
    assert_eq!(fmu.real(vr::X), 1.0, "gets are legal in Error");
    assert_eq!(fmu.reset(), Status::Ok);
    fmu.initialize();
}

/// FreeInstance in every reachable state, with an FMU state still held.
fn free_instance_is_accepted_in_every_state_in_each_version<D: Osc>() {
    for stage in 0..4 {
        let fmu = D::open(false);
        if stage >= 1 {
            fmu.enter_initialization_mode(0.0, None);
        }
        if stage >= 2 {
            fmu.exit_initialization_mode();
            fmu.step(0.0, 0.01);
        }
        if stage >= 3 {
            fmu.terminate();
        }
        let _ = fmu.get_state(); // owned states are released with the instance
        drop(fmu);
    }
}

both!(
    illegal_calls_are_refused_by_state_name_and_change_nothing,
    the_error_state_admits_reset_in_each_version,
    free_instance_is_accepted_in_every_state_in_each_version,
);

// ---- FMI 3.0: every function in every reachable state, as fmi3-export's table says ----

mod fmi3_table {
    use super::common::{vr, FUNCTIONS3};
    use fmi3_export::state::{state_name, Function, Interface, Refusal, State};
    use fmi_testkit::fmi3_ffi::*;
    use fmi_testkit::{CoSimulationOptions, Fmi3Instance};

    fn open(interface: Interface) -> Fmi3Instance {
        let token = fmi3_export::instantiation_token::<fmu_testmodel::Oscillator>();
        match interface {
            // With Event Mode, so that a Co-Simulation instance can reach it.
            Interface::CoSimulation => {
                let options = CoSimulationOptions {
                    event_mode_used: true,
                    ..CoSimulationOptions::default()
                };
                Fmi3Instance::co_simulation(&FUNCTIONS3, "osc", &token, options)
            }
            Interface::ModelExchange => {
                Fmi3Instance::model_exchange(&FUNCTIONS3, "osc", &token, false)
            }
        }
        .unwrap_or_else(|log| panic!("{log:?}"))
    }

    /// A fresh instance of `interface` driven into `state`.
    fn in_state(interface: Interface, state: State) -> Fmi3Instance {
        let fmu = open(interface);
        let init = |fmu: &Fmi3Instance| {
            assert_eq!(fmu.enter_initialization_mode(0.0, None), fmi3OK);
            assert_eq!(
                fmu.exit_initialization_mode(),
                fmi3OK,
                "{:?}",
                fmu.messages()
            );
        };
        match state {
            State::Instantiated => {}
            State::InitializationMode => {
                assert_eq!(fmu.enter_initialization_mode(0.0, None), fmi3OK);
            }
            // After initialization Model Exchange is in Event Mode (FMI 3.0 §3.2), and so
            // is Co-Simulation with eventModeUsed (§4.2).
            State::EventMode => init(&fmu),
            State::StepComplete => {
                init(&fmu);
                assert_eq!(fmu.enter_step_mode(), fmi3OK, "{:?}", fmu.messages());
            }
            State::ContinuousTimeMode => {
                init(&fmu);
                assert_eq!(fmu.enter_continuous_time_mode(), fmi3OK);
            }
            State::Terminated => {
                init(&fmu);
                assert_eq!(fmu.terminate(), fmi3OK, "{:?}", fmu.messages());
            }
            State::Error => {
                let stop = [vr::STOP_AT_THRESHOLD];
                assert_eq!(fmu.set_booleans(&stop, &[true]), fmi3OK);
                assert_eq!(fmu.set_float64(&[vr::THRESHOLD], &[1.0]), fmi3OK);
                assert_eq!(fmu.enter_initialization_mode(0.0, None), fmi3OK);
                assert_eq!(fmu.exit_initialization_mode(), fmi3Error);
            }
            other => unreachable!("{other:?} is not reached by this model"),
        }
        fmu.logger().clear();
        fmu
    }

    /// The functions the kit calls, with valid arguments.
    const CALLED: [Function; 33] = [
        Function::SetDebugLogging,
        Function::EnterInitializationMode,
        Function::ExitInitializationMode,
        Function::EnterEventMode,
        Function::Terminate,
        Function::Reset,
        Function::GetFloat64,
        Function::GetInt32,
        Function::GetBoolean,
        Function::GetString,
        Function::SetFloat64,
        Function::SetInt32,
        Function::SetBoolean,
        Function::SetString,
        Function::GetFMUState,
        Function::SetFMUState,
        Function::FreeFMUState,
        Function::SerializedFMUStateSize,
        Function::SerializeFMUState,
        Function::DeserializeFMUState,
        Function::UpdateDiscreteStates,
        Function::EnterContinuousTimeMode,
        Function::CompletedIntegratorStep,
        Function::SetTime,
        Function::SetContinuousStates,
        Function::GetContinuousStateDerivatives,
        Function::GetEventIndicators,
        Function::GetContinuousStates,
        Function::GetNominalsOfContinuousStates,
        Function::GetNumberOfEventIndicators,
        Function::GetNumberOfContinuousStates,
        Function::EnterStepMode,
        Function::DoStep,
    ];

    fn call(fmu: &Fmi3Instance, f: Function) -> fmi3Status {
        match f {
            Function::SetDebugLogging => fmu.set_debug_logging(true),
            Function::EnterInitializationMode => fmu.enter_initialization_mode(0.0, None),
            Function::ExitInitializationMode => fmu.exit_initialization_mode(),
            Function::EnterEventMode => fmu.enter_event_mode(),
            Function::Terminate => fmu.terminate(),
            Function::Reset => fmu.reset(),
            Function::GetFloat64 => fmu.get_float64(&[vr::X], 1).0,
            Function::GetInt32 => fmu.get_int32(&[vr::STEP_COUNT]).0,
            Function::GetBoolean => fmu.get_booleans(&[vr::STOP_AT_THRESHOLD]).0,
            Function::GetString => fmu.get_string(vr::LABEL).0,
            Function::SetFloat64 => fmu.set_float64(&[vr::U], &[0.5]),
            Function::SetInt32 => fmu.set_int32(&[vr::SUBSTEPS], &[4]),
            Function::SetBoolean => fmu.set_booleans(&[vr::STOP_AT_THRESHOLD], &[false]),
            Function::SetString => fmu.set_string(vr::LABEL, "l"),
            Function::GetFMUState => {
                let (s, state) = fmu.get_state();
                fmu.free_state(state);
                s
            }
            Function::FreeFMUState => fmu.free_state(std::ptr::null_mut()),
            Function::SetFMUState
            | Function::SerializedFMUStateSize
            | Function::SerializeFMUState
            | Function::DeserializeFMUState => {
                // GetFMUState is legal wherever these are (the same mask in the table).
                let (_, state) = fmu.get_state();
                let (_, bytes) = fmu.serialize(state);
                fmu.logger().clear();
                let s = match f {
                    Function::SetFMUState => fmu.set_state(state),
                    Function::DeserializeFMUState => {
                        let (s, copy) = fmu.deserialize(&bytes);
                        fmu.free_state(copy);
                        s
                    }
                    // Size, then the bytes: the first refusal or the last status.
                    _ => fmu.serialize(state).0,
                };
                fmu.free_state(state);
                s
            }
            Function::UpdateDiscreteStates => fmu.update_discrete_states().status,
            Function::EnterContinuousTimeMode => fmu.enter_continuous_time_mode(),
            Function::CompletedIntegratorStep => fmu.completed_integrator_step().0,
            Function::SetTime => fmu.set_time(0.0),
            Function::SetContinuousStates => fmu.set_continuous_states(&[1.0, 0.0]),
            Function::GetContinuousStateDerivatives => fmu.derivatives(2).0,
            Function::GetEventIndicators => fmu.event_indicators(1).0,
            Function::GetContinuousStates => fmu.continuous_states(2).0,
            Function::GetNominalsOfContinuousStates => fmu.nominals(2).0,
            Function::GetNumberOfEventIndicators => fmu.number_of_event_indicators().0,
            Function::GetNumberOfContinuousStates => fmu.number_of_continuous_states().0,
            Function::EnterStepMode => fmu.enter_step_mode(),
            Function::DoStep => fmu.do_step(0.0, 0.01).status,
            other => unreachable!("{} is not called here", other.name()),
        }
    }

    fn reachable(interface: Interface) -> [State; 6] {
        use State::*;
        match interface {
            Interface::CoSimulation => [
                Instantiated,
                InitializationMode,
                EventMode,
                StepComplete,
                Terminated,
                Error,
            ],
            Interface::ModelExchange => [
                Instantiated,
                InitializationMode,
                EventMode,
                ContinuousTimeMode,
                Terminated,
                Error,
            ],
        }
    }

    #[test]
    fn every_function_in_every_state_is_legal_or_refused_as_the_table_says() {
        let mut checked = 0;
        for interface in [Interface::CoSimulation, Interface::ModelExchange] {
            for f in CALLED {
                for state in reachable(interface) {
                    let fmu = in_state(interface, state);
                    let status = call(&fmu, f);
                    let illegal_line =
                        format!("{}: illegal call in state {}", f.name(), state_name(state));
                    let refused = fmu.messages().contains(&illegal_line);
                    let illegal =
                        matches!(f.admit(interface, state), Err(Refusal::IllegalState(..)));
                    assert_eq!(
                        refused,
                        illegal,
                        "{} in {state:?} ({interface:?}): {:?}",
                        f.name(),
                        fmu.messages()
                    );
                    if refused {
                        assert_eq!(status, fmi3Error);
                        assert_eq!(fmu.messages().len(), 1, "one line: {:?}", fmu.messages());
                    }
                    checked += 1;
                }
            }
        }
        assert_eq!(checked, 33 * 6 * 2);
    }
}
