//! A damped spring-mass oscillator exported as the FMU "Oscillator": the smallest model
//! that exercises every path of the `fmi2-export` layer (all variable types and
//! causalities, tunable and fixed parameters, bounds, an enumeration, a constant, a
//! calculated parameter, warnings, a model error and an early stop).
#![deny(unsafe_code)]

mod dynamics;
mod oscillator;
mod variables;

pub use oscillator::{Crossing, Oscillator};

fmi2_export::export_fmi2!(crate::Oscillator);
