//! The FMI 2.0 layer (Co-Simulation, and Model Exchange for a model that implements
//! [`fmi_model::ContinuousModel`]), generated from a model's declarations on the export core.
//!
//! A model crate implements [`fmi_model::Model`] (declarations plus a step function) and
//! invokes [`export_fmi2!`] once. What is FMI 2.0's own lives here: the 44 `fmi2*` C entry
//! points and their argument unpacking ([`abi`], [`model_exchange`]), the state table
//! ([`state`]), the scalar view of the declarations ([`variables`]) and the model
//! description ([`model_description`], [`guid`], [`check_table`]). What FMI 2.0 shares with
//! FMI 3.0 (the instance, the call guard, the step rules, FMU states, setter checks, the
//! Model Exchange accessors, the unit table) is the core's, [`fmi_export`].
#![deny(unsafe_code)]

pub mod abi;
mod check;
mod description;
mod export;
mod index;
pub mod model_exchange;
mod model_exchange_description;
pub mod state;
pub mod variable;
pub mod version;

/// The FMI 2.0 C types (one copy, in `fmi-abi`).
pub use fmi_abi::fmi2 as ffi;
/// The export core, for the symbols [`export_fmi2!`] generates through it.
pub use fmi_export;
/// The version-neutral core the models are written against.
pub use fmi_model::{
    self as model, decl, Causality, Declaration, Dependencies, EnumItem, EnumType, Enumeration,
    Experiment, Initial, Level, Limit, Log, Model, ModelError, Shape, StepEnd, Variability,
};

pub use check::{check_table, TableError};
pub use description::{guid, interface_uuid, model_description, model_description_xml};
pub use fmi_export::base_unit;
pub use model_exchange_description::{model_description_me, model_description_xml_me};
pub use variable::{effective_initial, initial_rule};
pub use variable::{variables, Access, Variable};
pub use version::Fmi2;

/// Magic bytes of a serialized FMI 2.0 FMU state (see [`fmi_export::snapshot`]).
pub const SNAPSHOT_MAGIC: [u8; 8] = *b"FMI2SNAP";
