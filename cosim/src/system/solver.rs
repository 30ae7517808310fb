//! How a Model Exchange instance is integrated: part of the system's description.

use ode_solver::{Method, Tolerances};

/// How the master integrates one Model Exchange instance (a scenario's `solver`,
/// `relative_tolerance`, `absolute_tolerance`, `event_tolerance`).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SolverSettings {
    pub method: Method,
    pub tolerances: Tolerances,
}

impl Default for SolverSettings {
    fn default() -> Self {
        Self {
            method: Method::Tsit45,
            tolerances: Tolerances {
                relative: 1e-8,
                absolute: 1e-10,
                event_time: 1e-10,
            },
        }
    }
}
