//! Adaptive, error-controlled ODE integration for FMI Model Exchange, free of FMI code.
//!
//! Two methods of its own, in pure Rust with no numerical dependency: variable-order BDF
//! (1..5) for stiff systems and Tsitouras 5(4) for non-stiff ones. Around them, what an FMU
//! master needs: a `&mut` black-box right-hand side with finite-difference Jacobians, one
//! accepted step per call, bit-exact stop times, FMI-style state-event location on the dense
//! output, and errors instead of panics.

mod backend;
mod bdf;
mod differences;
mod error;
mod eval;
mod events;
mod integrator;
mod lu;
mod norm;
mod step_control;
mod tsit5;

pub use error::SolverError;
pub use integrator::Integrator;

/// What the integrator advances: an FMU in continuous-time mode, or a test ODE.
pub trait OdeSystem {
    fn state_count(&self) -> usize;
    fn indicator_count(&self) -> usize;
    /// dx/dt at (t, x). An Err stops the integration and is returned to the caller.
    fn derivatives(&mut self, t: f64, x: &[f64], dx: &mut [f64]) -> Result<(), String>;
    /// Event indicators z(t, x). An event is `events::crossed(before, after)`.
    fn indicators(&mut self, t: f64, x: &[f64], z: &mut [f64]) -> Result<(), String>;
    /// The Jacobian df/dx at (t, x), when the system has one of its own (an FMU's directional
    /// derivatives): `jac[i + j n]` = d f_i / d x_j (column-major), and `Ok(true)`. The
    /// default, `Ok(false)`, leaves BDF to finite differences.
    fn jacobian(&mut self, _t: f64, _x: &[f64], _jac: &mut [f64]) -> Result<bool, String> {
        Ok(false)
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Method {
    /// Variable-order (1..5) BDF with Newton iterations on the system's Jacobian or a
    /// finite-difference one: stiff.
    Bdf,
    /// Tsitouras 5(4) explicit Runge-Kutta with 4th-order dense output: non-stiff.
    Tsit45,
}

#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Tolerances {
    pub relative: f64,
    pub absolute: f64,
    /// Width of the time bracket a state event is located to.
    pub event_time: f64,
}

impl Default for Tolerances {
    fn default() -> Self {
        Self {
            relative: 1e-6,
            absolute: 1e-8,
            event_time: 1e-10,
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
pub enum Advance {
    /// One accepted internal step ended at `t` (t < t_stop); states available via state().
    Step { t: f64 },
    /// t_stop reached; `t` and `time()` are bit-exactly t_stop.
    Reached { t: f64 },
    /// Indicators in `which` crossed inside the last step. `t` is the right end of a bracket
    /// no wider than `event_time`, so they already show their new sign there; state() is
    /// the (interpolated) state at `t`, and integration continues from there.
    StateEvent { t: f64, which: Vec<usize> },
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Statistics {
    /// Accepted internal steps.
    pub steps: u64,
    /// Calls of `OdeSystem::derivatives`, including those for finite differences.
    pub rhs_evaluations: u64,
    /// Jacobians formed: finite-difference ones (each costs n + 1 derivative calls) and the
    /// system's own.
    pub jacobian_evaluations: u64,
    /// Of those, the system's own ([`OdeSystem::jacobian`]).
    pub system_jacobians: u64,
    /// Steps rejected by the error test or by a failed Newton iteration.
    pub rejected_steps: u64,
    /// Calls of `OdeSystem::indicators`.
    pub indicator_evaluations: u64,
    /// Restarts: `reset` calls.
    pub restarts: u64,
}
