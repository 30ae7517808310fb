//! Generic FMI 2.0 Co-Simulation export layer.
//!
//! A model crate implements [`Model`] (a static variable table plus a step function) and
//! invokes [`export_fmi2!`] once; this crate provides the 34 `fmi2*` C entry points
//! ([`abi`]), the state machine ([`state`]), logging, FMU-state copies and serialization
//! ([`snapshot`]), and the model description ([`model_description`], [`guid`],
//! [`check_table`]). It is the only crate of the FMUs with `unsafe` code, confined to
//! [`abi`] and the logger call.
#![deny(unsafe_code)]

pub mod abi;
mod check;
mod description;
mod error;
mod export;
pub mod ffi;
mod index;
mod instance;
pub mod logging;
pub mod model;
mod rules;
pub mod snapshot;
pub mod state;
mod units;
pub mod variable;

pub use check::{check_table, effective_initial, initial_rule, TableError};
pub use description::{guid, interface_uuid, model_description, model_description_xml};
pub use model::{
    Dependencies, EnumerationDecl, Experiment, Level, Log, Model, ModelError, StepEnd,
};
pub use units::base_unit;
pub use variable::{Access, Causality, Initial, Variability, Variable};
