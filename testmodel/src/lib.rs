//! A damped spring-mass oscillator exported as the FMU "Oscillator" (FMI 2.0 Co-Simulation;
//! FMI 3.0 Co-Simulation and Model Exchange): the smallest model that exercises every path
//! of the export layers (all variable types and causalities, tunable and fixed parameters,
//! bounds, an enumeration, a constant, a calculated parameter, warnings, a model error, an
//! early stop and a state event).
#![deny(unsafe_code)]

mod dynamics;
mod oscillator;
mod variables;

pub use oscillator::{Crossing, Oscillator};

fmi2_export::export_fmi2!(crate::Oscillator);
fmi3_export::export_fmi3!(crate::Oscillator, model_exchange);
