//! The harness: an FMI 2.0 Co-Simulation master for the lander FMUs.
//!
//! [`loader`] loads any FMI 2.0 CS FMU through its C ABI; it is the only module with `unsafe`.
#![deny(unsafe_code)]

pub mod loader;
pub mod master;
pub mod memory;
pub mod metrics;
pub mod montecarlo;
pub mod paper;
pub mod plots;
pub mod report;
pub mod requirements;
pub mod results;
pub mod retarget;
pub mod scenarios;
pub mod system;
pub mod vars;
pub mod verdict;

pub use loader::{Fmu, Instance};
