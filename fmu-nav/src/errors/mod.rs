//! The navigation error models, with no FMI in sight: parameters and their validation,
//! the counter-based draws, the error of a signal group, the attitude rotation, the latency
//! history, and [`navigation::NavErrors`] that combines them (with the timing).
pub mod attitude;
pub mod draws;
pub mod history;
pub mod navigation;
mod normal;
pub mod parameters;
pub mod signal;

pub use navigation::{NavErrors, Navigation};
pub use parameters::{Group, GroupErrors, NavParameters, ParameterError, LATENCY_CAP_STEPS};
