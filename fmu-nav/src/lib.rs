//! LanderNav: the navigation errors between the lander plant and its GNC, as an FMI 2.0 and
//! FMI 3.0 Co-Simulation FMU. Its inputs are the plant's true navigation outputs, its outputs
//! the same signals as the GNC reads them: with white noise, bias, random walk, quantisation and
//! a latency of whole communication steps, per signal group, reproducible from a seed.
//!
//! [`errors`] holds the error models with no FMI in sight; [`fmu`] declares the variable
//! table and implements [`fmi_model::Model`]. See README.md for the equations and timing.
#![deny(unsafe_code)]

pub mod errors;
pub mod fmu;

pub use fmu::LanderNav;

fmi2_export::export_fmi2!(crate::LanderNav);
fmi3_export::export_fmi3!(crate::LanderNav);
