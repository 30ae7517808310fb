//! What a Model Exchange master asks of an instance besides values: the interface chosen at
//! instantiation and the answers of the event functions, version-neutral.

/// The interface an instance is made for (`fmi2Type`; `fmi3Instantiate<Interface>`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Interface {
    #[default]
    CoSimulation,
    ModelExchange,
}

/// Which vector of a Model Exchange instance to read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MeVector {
    States,
    Derivatives,
    EventIndicators,
    Nominals,
}

/// One step of the event iteration (`fmi2NewDiscreteStates`, `fmi3UpdateDiscreteStates`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EventUpdate {
    pub discrete_states_need_update: bool,
    pub terminate_simulation: bool,
    pub nominals_changed: bool,
    pub states_changed: bool,
    pub next_event_time: Option<f64>,
}

/// What `completedIntegratorStep` asks of the master.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StepEnd {
    pub enter_event_mode: bool,
    pub terminate_simulation: bool,
}
