//! The states of an instance, named once for both FMI versions. Each version's own table
//! (its `Function` type) says in which of them each of its functions may be called, and
//! gives each state the name its standard uses (FMI 2.0 "StepComplete", FMI 3.0 "StepMode").
use serde::{Deserialize, Serialize};

/// The interface an instance was created for (version-neutral, in `fmi-model`).
pub use fmi_model::Interface;

/// States of an instance. The discriminants are the bits of a [`StateMask`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[repr(u16)]
pub enum State {
    Instantiated = 1 << 0,
    InitializationMode = 1 << 1,
    /// Co-Simulation between steps (FMI 2.0 stepComplete, FMI 3.0 Step Mode).
    StepComplete = 1 << 2,
    /// FMI 2.0 Co-Simulation after a step that ended early (`fmi2Discard`).
    StepFailed = 1 << 3,
    /// FMI 2.0 Co-Simulation after `fmi2CancelStep` (never reached: steps are synchronous).
    StepCanceled = 1 << 4,
    Terminated = 1 << 5,
    Error = 1 << 6,
    Fatal = 1 << 7,
    /// Model Exchange, and FMI 3.0 Co-Simulation with `eventModeUsed`.
    EventMode = 1 << 8,
    /// Model Exchange only.
    ContinuousTimeMode = 1 << 9,
}

impl State {
    pub const ALL: [State; 10] = [
        State::Instantiated,
        State::InitializationMode,
        State::StepComplete,
        State::StepFailed,
        State::StepCanceled,
        State::Terminated,
        State::Error,
        State::Fatal,
        State::EventMode,
        State::ContinuousTimeMode,
    ];

    /// Before the end of initialization: fixed parameters may still be set.
    pub const fn initializing(self) -> bool {
        matches!(self, State::Instantiated | State::InitializationMode)
    }
}

/// Where both standards let a Model Exchange master read the continuous part (states,
/// derivatives, event indicators, nominals).
pub const CONTINUOUS_READS: StateMask = StateMask::of(&[
    State::InitializationMode,
    State::EventMode,
    State::ContinuousTimeMode,
    State::Terminated,
    State::Error,
]);

/// A set of [`State`]s.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StateMask(u16);

impl StateMask {
    pub const fn of(states: &[State]) -> StateMask {
        let mut bits = 0;
        let mut i = 0;
        while i < states.len() {
            bits |= states[i] as u16;
            i += 1;
        }
        StateMask(bits)
    }

    /// Every state but `states`.
    pub const fn all_but(states: &[State]) -> StateMask {
        StateMask(StateMask::of(&State::ALL).0 & !StateMask::of(states).0)
    }

    pub const fn contains(self, state: State) -> bool {
        self.0 & state as u16 != 0
    }

    /// The states as bits (each `State as u16`).
    pub const fn bits(self) -> u16 {
        self.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn all_but_leaves_out_exactly_the_named_states() {
        let mask = StateMask::all_but(&[State::StepFailed, State::Fatal]);
        for s in State::ALL {
            assert_eq!(
                mask.contains(s),
                !matches!(s, State::StepFailed | State::Fatal)
            );
        }
    }

    #[test]
    fn the_bits_of_the_states_are_distinct() {
        let mut seen = 0u16;
        for s in State::ALL {
            assert_eq!(seen & s as u16, 0);
            seen |= s as u16;
        }
    }
}
