//! The FMI 2.0 Co-Simulation layer, generated from a model's declarations.
//!
//! A model crate implements [`fmi_model::Model`] (declarations plus a step function) and
//! invokes [`export_fmi2!`] once; this crate provides the 34 `fmi2*` C entry points
//! ([`abi`]), the state machine ([`state`]), logging, FMU-state copies and serialization,
//! the FMI 2.0 scalar view of the declarations ([`variables`]) and the model description
//! ([`model_description`], [`guid`], [`check_table`]). It is the only crate of the FMUs
//! with `unsafe` code, confined to [`abi`] and the logger call.
#![deny(unsafe_code)]

pub mod abi;
mod check;
mod description;
mod error;
mod export;
mod index;
mod instance;
pub mod logging;
pub mod model_exchange;
mod model_exchange_description;
mod restore;
mod rules;
pub mod state;
mod units;
pub mod variable;

/// The FMI 2.0 C types (one copy, in `fmi-abi`).
pub use fmi_abi::fmi2 as ffi;
/// The version-neutral core the models are written against.
pub use fmi_model::{
    self as model, decl, Causality, Declaration, Dependencies, EnumItem, EnumType, Enumeration,
    Experiment, Initial, Level, Limit, Log, Model, ModelError, Shape, StepEnd, Variability,
};

pub use check::{check_table, effective_initial, initial_rule, TableError};
pub use description::{guid, interface_uuid, model_description, model_description_xml};
pub use model_exchange_description::{model_description_me, model_description_xml_me};
pub use units::base_unit;
pub use variable::{variables, Access, Variable};

/// Magic bytes of a serialized FMI 2.0 FMU state (see [`fmi_model::snapshot`]).
pub const SNAPSHOT_MAGIC: [u8; 8] = *b"FMI2SNAP";
