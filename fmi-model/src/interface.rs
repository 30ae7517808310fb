//! The FMI interface an instance was created for, as every FMI version names it.
use serde::{Deserialize, Serialize};

/// Co-Simulation (the FMU integrates itself, the master steps it) or Model Exchange (the
/// master integrates the FMU's derivatives). An FMU state records it: a state of one
/// interface is no state of the other.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Interface {
    CoSimulation,
    ModelExchange,
}

impl Interface {
    /// The interface's name in the standard's words, for messages.
    pub const fn name(self) -> &'static str {
        match self {
            Interface::CoSimulation => "Co-Simulation",
            Interface::ModelExchange => "Model Exchange",
        }
    }
}

impl std::fmt::Display for Interface {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::Interface;

    #[test]
    fn interfaces_are_named_as_the_standard_names_them() {
        assert_eq!(Interface::CoSimulation.name(), "Co-Simulation");
        assert_eq!(Interface::ModelExchange.to_string(), "Model Exchange");
    }
}
