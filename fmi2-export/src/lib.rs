//! Generic FMI 2.0 Co-Simulation export layer.
//!
//! A model crate implements [`Model`] (a static variable table plus a step function) and
//! invokes [`export_fmi2!`] once; this crate provides the 34 `fmi2*` C entry points, the
//! state machine, logging, FMU-state copies and serialization, and the model description.
//! This is the only crate of the FMUs with `unsafe` code.
pub mod model;
pub mod variable;

pub use model::{EnumerationDecl, Experiment, Level, Log, Model, ModelError, StepEnd};
pub use variable::{Access, Causality, Initial, Variability, Variable};
