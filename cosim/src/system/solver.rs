//! How a Model Exchange instance is integrated: part of the system's description.

use ode_solver::{Method, Tolerances};

/// How the master integrates one Model Exchange instance (a scenario's `solver`,
/// `relative_tolerance`, `absolute_tolerance`, `event_tolerance`, `jacobian`).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SolverSettings {
    pub method: Method,
    pub tolerances: Tolerances,
    pub jacobian: JacobianSource,
}

/// Where BDF's Jacobian comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub enum JacobianSource {
    /// The FMU's directional derivatives, a column per state (only the rows its
    /// `ModelStructure` declares dependent), when its description declares them; else
    /// finite differences.
    #[default]
    Fmu,
    /// Finite differences of the derivatives, whatever the FMU provides.
    Differences,
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
            jacobian: JacobianSource::Fmu,
        }
    }
}
