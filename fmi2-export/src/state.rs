//! The state machines of FMI 2.0.4 Co-Simulation (§4.2.4) and Model Exchange (§3.2.3) as one
//! table: each function has a mask of the states in which it may be called. The two
//! machines share Instantiated, InitializationMode, Terminated, Error and Fatal; a
//! Co-Simulation instance never enters EventMode or ContinuousTimeMode, a Model Exchange
//! instance never a Step* state, so each interface's functions are refused on the other's
//! instances by the same table.
//!
//! `StepInProgress` does not exist here: `fmi2DoStep` always runs synchronously, so it can
//! never be observed. `Fatal` has an empty row everywhere (the standard allows no further
//! call), except that `fmi2FreeInstance` is always honoured: it returns `void`, so refusing
//! it could only leak memory, and a caught panic leaves our memory intact.
use fmi_export::state::CONTINUOUS_READS;
use fmi_export::{Interface, Refusal};
pub use fmi_export::{State, StateMask};

use State::*;

/// Every state but `Fatal`, minus nothing: the functions that only read or that manage memory.
const ANY_BUT_FATAL: StateMask = StateMask::of(&[
    Instantiated,
    InitializationMode,
    StepComplete,
    StepFailed,
    StepCanceled,
    Terminated,
    Error,
    EventMode,
    ContinuousTimeMode,
]);
const GETTERS: StateMask = StateMask::of(&[
    InitializationMode,
    StepComplete,
    StepFailed,
    StepCanceled,
    Terminated,
    Error,
    EventMode,
    ContinuousTimeMode,
]);
/// Which variables may be set in which state is the per-variable rule of `rules`.
const SETTERS: StateMask = StateMask::of(&[
    Instantiated,
    InitializationMode,
    StepComplete,
    EventMode,
    ContinuousTimeMode,
]);
const STATUS_QUERIES: StateMask = StateMask::of(&[StepComplete, StepFailed, Terminated]);

fmi_export::function_table! {
    /// The FMI functions that take an instance (all but `fmi2GetTypesPlatform`,
    /// `fmi2GetVersion` and `fmi2Instantiate`), named as in C; each with the states in which
    /// it may be called.
    prefix = "fmi2", legal_states -> StateMask;
    SetDebugLogging => ANY_BUT_FATAL,
    FreeInstance => StateMask::of(&[
        Instantiated, InitializationMode, StepComplete, StepFailed, StepCanceled, Terminated,
        Error, Fatal, EventMode, ContinuousTimeMode,
    ]),
    SetupExperiment => StateMask::of(&[Instantiated]),
    EnterInitializationMode => StateMask::of(&[Instantiated]),
    ExitInitializationMode => StateMask::of(&[InitializationMode]),
    Terminate => StateMask::of(&[StepComplete, StepFailed, EventMode, ContinuousTimeMode]),
    Reset => ANY_BUT_FATAL,
    GetReal => GETTERS,
    GetInteger => GETTERS,
    GetBoolean => GETTERS,
    GetString => GETTERS,
    SetReal => SETTERS,
    SetInteger => SETTERS,
    SetBoolean => SETTERS,
    SetString => SETTERS,
    GetFMUstate => ANY_BUT_FATAL,
    SetFMUstate => ANY_BUT_FATAL,
    FreeFMUstate => ANY_BUT_FATAL,
    SerializedFMUstateSize => ANY_BUT_FATAL,
    SerializeFMUstate => ANY_BUT_FATAL,
    DeSerializeFMUstate => ANY_BUT_FATAL,
    GetDirectionalDerivative => GETTERS,
    SetRealInputDerivatives => SETTERS,
    GetRealOutputDerivatives => StateMask::of(&[StepComplete, StepFailed, StepCanceled, Terminated, Error]),
    DoStep => StateMask::of(&[StepComplete]),
    CancelStep => StateMask::of(&[]),
    GetStatus => STATUS_QUERIES,
    GetRealStatus => STATUS_QUERIES,
    GetIntegerStatus => STATUS_QUERIES,
    GetBooleanStatus => STATUS_QUERIES,
    GetStringStatus => STATUS_QUERIES,
    // Model Exchange
    EnterEventMode => StateMask::of(&[EventMode, ContinuousTimeMode]),
    NewDiscreteStates => StateMask::of(&[EventMode]),
    EnterContinuousTimeMode => StateMask::of(&[EventMode]),
    CompletedIntegratorStep => StateMask::of(&[ContinuousTimeMode]),
    SetTime => StateMask::of(&[EventMode, ContinuousTimeMode]),
    SetContinuousStates => StateMask::of(&[ContinuousTimeMode]),
    GetDerivatives => CONTINUOUS_READS,
    GetEventIndicators => CONTINUOUS_READS,
    GetContinuousStates => CONTINUOUS_READS,
    GetNominalsOfContinuousStates => CONTINUOUS_READS,
}

impl fmi_export::Function for Function {
    fn name(self) -> &'static str {
        Function::name(self)
    }

    /// The interface needs no check of its own: a Co-Simulation instance is never in a
    /// Model Exchange state and the reverse, so the states refuse the other interface's
    /// functions.
    #[inline(always)]
    fn admit(self, _interface: Interface, state: State) -> Result<(), Refusal> {
        if self.legal_states().contains(state) {
            Ok(())
        } else {
            Err(Refusal::IllegalState(state, state_name(state)))
        }
    }
}

/// A state as FMI 2.0.4 §4.2.4 and §3.2.3 name it.
pub const fn state_name(state: State) -> &'static str {
    match state {
        State::Instantiated => "Instantiated",
        State::InitializationMode => "InitializationMode",
        State::StepComplete => "StepComplete",
        State::StepFailed => "StepFailed",
        State::StepCanceled => "StepCanceled",
        State::Terminated => "Terminated",
        State::Error => "Error",
        State::Fatal => "Fatal",
        State::EventMode => "EventMode",
        State::ContinuousTimeMode => "ContinuousTimeMode",
    }
}

impl Function {
    /// The 10 functions of Model Exchange only (a Co-Simulation-only FMU does not export them).
    pub const MODEL_EXCHANGE: &'static [Function] = &[
        Function::EnterEventMode,
        Function::NewDiscreteStates,
        Function::EnterContinuousTimeMode,
        Function::CompletedIntegratorStep,
        Function::SetTime,
        Function::SetContinuousStates,
        Function::GetDerivatives,
        Function::GetEventIndicators,
        Function::GetContinuousStates,
        Function::GetNominalsOfContinuousStates,
    ];
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn forty_one_functions_take_an_instance_and_only_free_instance_when_fatal() {
        // 34 Co-Simulation functions minus GetTypesPlatform, GetVersion and Instantiate,
        // plus the 10 of Model Exchange.
        fmi_export::assert_function_table(Function::ALL, 41, "fmi2", Function::FreeInstance);
        assert_eq!(
            Function::DeSerializeFMUstate.name(),
            "fmi2DeSerializeFMUstate"
        );
    }

    #[test]
    fn model_exchange_functions_are_refused_in_co_simulation_states_and_back() {
        let cs_states = [StepComplete, StepFailed, StepCanceled];
        for f in [
            Function::SetContinuousStates,
            Function::NewDiscreteStates,
            Function::EnterContinuousTimeMode,
            Function::CompletedIntegratorStep,
            Function::SetTime,
        ] {
            for state in cs_states {
                assert!(
                    !f.legal_states().contains(state),
                    "{} in {state:?}",
                    f.name()
                );
            }
        }
        for state in [EventMode, ContinuousTimeMode] {
            assert!(!Function::DoStep.legal_states().contains(state));
        }
    }
}
