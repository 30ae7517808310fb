//! The FMI 3.0 state machines of Co-Simulation (§4.2) and Model Exchange (§3.2) as one table:
//! for each function, the interfaces it belongs to and the states in which it may be called.
//!
//! Only what the FMUs implement has states: no configuration mode (no structural
//! parameters), no clocks, no intermediate update. Co-Simulation has Event Mode when the
//! master chose `eventModeUsed` (`fmi3ExitInitializationMode` then leads to Event Mode, and
//! `fmi3EnterEventMode` back to it from Step Mode); otherwise straight to Step Mode. A
//! function of such a feature is `Unsupported`: it answers `fmi3Error` with a log line
//! saying so, in every state. `Error` is entered when the model itself fails; `Fatal` after a
//! caught panic, where only `fmi3FreeInstance` is honoured (it returns `void`).
use fmi_export::state::CONTINUOUS_READS;
pub use fmi_export::{Interface, Refusal, State, StateMask};

/// Which interfaces a function belongs to, and whether we implement it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scope {
    Both(StateMask),
    ModelExchange(StateMask),
    CoSimulation(StateMask),
    /// Both interfaces, in different states.
    Each {
        model_exchange: StateMask,
        co_simulation: StateMask,
    },
    /// A feature none of our FMUs has (clocks, configuration mode, ...).
    Unsupported(&'static str),
}

use State::*;

const ANY_BUT_FATAL: StateMask = StateMask::of(&[
    Instantiated,
    InitializationMode,
    EventMode,
    ContinuousTimeMode,
    StepComplete,
    Terminated,
    Error,
]);
const GETTERS: StateMask = StateMask::of(&[
    InitializationMode,
    EventMode,
    ContinuousTimeMode,
    StepComplete,
    Terminated,
    Error,
]);
/// Which variables may be set in which of these states is the layer's per-variable rule.
const SETTERS: StateMask = StateMask::of(&[
    Instantiated,
    InitializationMode,
    EventMode,
    ContinuousTimeMode,
    StepComplete,
]);

/// A state as FMI 3.0 §3.2 and §4.2 name it.
pub const fn state_name(state: State) -> &'static str {
    match state {
        State::Instantiated => "Instantiated",
        State::InitializationMode => "Initialization Mode",
        State::StepComplete => "Step Mode",
        // Never entered by an FMI 3.0 instance.
        State::StepFailed | State::StepCanceled => "Step Mode (discarded)",
        State::Terminated => "Terminated",
        State::Error => "Error",
        State::Fatal => "Fatal",
        State::EventMode => "Event Mode",
        State::ContinuousTimeMode => "Continuous-Time Mode",
    }
}

impl fmi_export::Function for Function {
    fn name(self) -> &'static str {
        Function::name(self)
    }

    #[inline(always)]
    fn admit(self, interface: Interface, state: State) -> Result<(), Refusal> {
        Function::admit(self, interface, state)
    }
}

impl Function {
    /// `Ok` when the function may run on an instance of `interface` in `state`. Inlined,
    /// it folds to one mask test at each call site, where the function is a constant.
    #[inline]
    pub fn admit(self, interface: Interface, state: State) -> Result<(), Refusal> {
        let mask = match (self.scope(), interface) {
            (Scope::Unsupported(feature), _) => return Err(Refusal::Unsupported(feature)),
            (Scope::Both(mask), _) => mask,
            (Scope::Each { model_exchange, .. }, Interface::ModelExchange) => model_exchange,
            (Scope::Each { co_simulation, .. }, Interface::CoSimulation) => co_simulation,
            (Scope::ModelExchange(mask), Interface::ModelExchange) => mask,
            (Scope::CoSimulation(mask), Interface::CoSimulation) => mask,
            (Scope::ModelExchange(_), Interface::CoSimulation) => {
                return Err(Refusal::WrongInterface(Interface::CoSimulation))
            }
            (Scope::CoSimulation(_), Interface::ModelExchange) => {
                return Err(Refusal::WrongInterface(Interface::ModelExchange))
            }
        };
        if mask.contains(state) {
            Ok(())
        } else {
            Err(Refusal::IllegalState(state, state_name(state)))
        }
    }
}

const CLOCKS: Scope = Scope::Unsupported("clocks");

fmi_export::function_table! {
    /// The FMI 3.0 functions that take an instance, named as in C; each with its interfaces
    /// and states.
    prefix = "fmi3", scope -> Scope;
    SetDebugLogging => Scope::Both(ANY_BUT_FATAL),
    FreeInstance => Scope::Both(StateMask::of(&State::ALL)),
    EnterInitializationMode => Scope::Both(StateMask::of(&[Instantiated])),
    ExitInitializationMode => Scope::Both(StateMask::of(&[InitializationMode])),
    // Co-Simulation: only with eventModeUsed (checked by the function itself).
    EnterEventMode => Scope::Each {
        model_exchange: StateMask::of(&[ContinuousTimeMode]),
        co_simulation: StateMask::of(&[StepComplete]),
    },
    Terminate => Scope::Both(StateMask::of(&[EventMode, ContinuousTimeMode, StepComplete])),
    Reset => Scope::Both(ANY_BUT_FATAL),
    GetFloat32 => Scope::Both(GETTERS),
    GetFloat64 => Scope::Both(GETTERS),
    GetInt8 => Scope::Both(GETTERS),
    GetUInt8 => Scope::Both(GETTERS),
    GetInt16 => Scope::Both(GETTERS),
    GetUInt16 => Scope::Both(GETTERS),
    GetInt32 => Scope::Both(GETTERS),
    GetUInt32 => Scope::Both(GETTERS),
    GetInt64 => Scope::Both(GETTERS),
    GetUInt64 => Scope::Both(GETTERS),
    GetBoolean => Scope::Both(GETTERS),
    GetString => Scope::Both(GETTERS),
    GetBinary => Scope::Both(GETTERS),
    GetClock => CLOCKS,
    SetFloat32 => Scope::Both(SETTERS),
    SetFloat64 => Scope::Both(SETTERS),
    SetInt8 => Scope::Both(SETTERS),
    SetUInt8 => Scope::Both(SETTERS),
    SetInt16 => Scope::Both(SETTERS),
    SetUInt16 => Scope::Both(SETTERS),
    SetInt32 => Scope::Both(SETTERS),
    SetUInt32 => Scope::Both(SETTERS),
    SetInt64 => Scope::Both(SETTERS),
    SetUInt64 => Scope::Both(SETTERS),
    SetBoolean => Scope::Both(SETTERS),
    SetString => Scope::Both(SETTERS),
    SetBinary => Scope::Both(SETTERS),
    SetClock => CLOCKS,
    GetNumberOfVariableDependencies => Scope::Unsupported("variable dependencies at run time (see the model description)"),
    GetVariableDependencies => Scope::Unsupported("variable dependencies at run time (see the model description)"),
    GetFMUState => Scope::Both(ANY_BUT_FATAL),
    SetFMUState => Scope::Both(ANY_BUT_FATAL),
    FreeFMUState => Scope::Both(ANY_BUT_FATAL),
    SerializedFMUStateSize => Scope::Both(ANY_BUT_FATAL),
    SerializeFMUState => Scope::Both(ANY_BUT_FATAL),
    DeserializeFMUState => Scope::Both(ANY_BUT_FATAL),
    // Whether the model provides them is the function's own check.
    GetDirectionalDerivative => Scope::Both(GETTERS),
    GetAdjointDerivative => Scope::Both(GETTERS),
    EnterConfigurationMode => Scope::Unsupported("structural parameters"),
    ExitConfigurationMode => Scope::Unsupported("structural parameters"),
    GetIntervalDecimal => CLOCKS,
    GetIntervalFraction => CLOCKS,
    GetShiftDecimal => CLOCKS,
    GetShiftFraction => CLOCKS,
    SetIntervalDecimal => CLOCKS,
    SetIntervalFraction => CLOCKS,
    SetShiftDecimal => CLOCKS,
    SetShiftFraction => CLOCKS,
    EvaluateDiscreteStates => Scope::CoSimulation(StateMask::of(&[EventMode])),
    UpdateDiscreteStates => Scope::Both(StateMask::of(&[EventMode])),
    EnterContinuousTimeMode => Scope::ModelExchange(StateMask::of(&[EventMode])),
    CompletedIntegratorStep => Scope::ModelExchange(StateMask::of(&[ContinuousTimeMode])),
    SetTime => Scope::ModelExchange(StateMask::of(&[EventMode, ContinuousTimeMode])),
    SetContinuousStates => Scope::ModelExchange(StateMask::of(&[ContinuousTimeMode])),
    GetContinuousStateDerivatives => Scope::ModelExchange(CONTINUOUS_READS),
    GetEventIndicators => Scope::ModelExchange(CONTINUOUS_READS),
    GetContinuousStates => Scope::ModelExchange(CONTINUOUS_READS),
    GetNominalsOfContinuousStates => Scope::ModelExchange(CONTINUOUS_READS),
    GetNumberOfEventIndicators => Scope::Both(ANY_BUT_FATAL),
    GetNumberOfContinuousStates => Scope::Both(ANY_BUT_FATAL),
    EnterStepMode => Scope::CoSimulation(StateMask::of(&[EventMode])),
    GetOutputDerivatives => Scope::Unsupported("output derivatives"),
    DoStep => Scope::CoSimulation(StateMask::of(&[StepComplete])),
    ActivateModelPartition => Scope::Unsupported("Scheduled Execution"),
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seventy_one_functions_take_an_instance_and_only_free_instance_when_fatal() {
        // 75 exported functions minus fmi3GetVersion and the three fmi3Instantiate*.
        fmi_export::assert_function_table(Function::ALL, 71, "fmi3", Function::FreeInstance);
        let derivatives = Function::GetContinuousStateDerivatives.name();
        assert_eq!(derivatives, "fmi3GetContinuousStateDerivatives");
    }

    #[test]
    fn interface_functions_are_refused_on_the_other_interface() {
        assert_eq!(
            Function::DoStep.admit(Interface::ModelExchange, StepComplete),
            Err(Refusal::WrongInterface(Interface::ModelExchange))
        );
        assert_eq!(
            Function::SetContinuousStates.admit(Interface::CoSimulation, StepComplete),
            Err(Refusal::WrongInterface(Interface::CoSimulation))
        );
        let message = Function::DoStep
            .admit(Interface::ModelExchange, ContinuousTimeMode)
            .unwrap_err()
            .to_string();
        assert!(message.contains("Model Exchange"), "{message}");
    }

    #[test]
    fn unsupported_features_are_refused_in_every_state_naming_the_feature() {
        for state in State::ALL {
            let refusal = Function::GetClock
                .admit(Interface::CoSimulation, state)
                .unwrap_err();
            assert_eq!(refusal.to_string(), "not supported: this FMU has no clocks");
        }
    }

    #[test]
    fn the_model_exchange_cycle_is_legal_and_steps_are_not() {
        let me = Interface::ModelExchange;
        assert!(Function::SetContinuousStates
            .admit(me, ContinuousTimeMode)
            .is_ok());
        assert!(Function::EnterEventMode
            .admit(me, ContinuousTimeMode)
            .is_ok());
        assert!(Function::UpdateDiscreteStates.admit(me, EventMode).is_ok());
        assert!(Function::EnterContinuousTimeMode
            .admit(me, EventMode)
            .is_ok());
        assert_eq!(
            Function::SetContinuousStates.admit(me, EventMode),
            Err(Refusal::IllegalState(EventMode, "Event Mode"))
        );
        assert!(Function::DoStep
            .admit(Interface::CoSimulation, StepComplete)
            .is_ok());
        assert!(Function::DoStep
            .admit(Interface::CoSimulation, InitializationMode)
            .is_err());
    }
}
