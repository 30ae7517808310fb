//! LanderPlant: the 6-DOF lunar-lander plant of "Decoupled Thrust Axis Control" (Section II,
//! Tables I-II, with the corrections of `docs/paper-notes.md`) as an FMI 2.0 Co-Simulation FMU.
//!
//! [`physics`] holds the equations of motion, actuators, RK4 integration and events, with no
//! FMI in sight; [`fmu`] declares the variable table and implements [`fmi2_export::Model`].
#![deny(unsafe_code)]

pub mod fmu;
pub mod physics;

pub use fmu::LanderPlant;

fmi2_export::export_fmi2!(crate::LanderPlant, model_exchange);
fmi3_export::export_fmi3!(crate::LanderPlant, model_exchange);
