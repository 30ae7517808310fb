//! The FMI 3.0 layer (Co-Simulation, and Model Exchange for a model that implements
//! [`fmi_model::ContinuousModel`]), generated from the same declarations as the FMI 2.0
//! layer. A model crate invokes [`export_fmi3!`] once; this crate provides the 75 `fmi3*`
//! C entry points ([`abi`], [`me`]), the state machine as a table ([`state`]), logging,
//! FMU-state copies and serialization, and the model description ([`description`]). Unlike
//! FMI 2.0, a vector declaration is one variable: a Float64 array with one `Dimension`.
#![deny(unsafe_code)]

pub mod abi;
pub mod description;
mod error;
mod export;
mod instance;
pub mod logging;
pub mod me;
mod restore;
pub mod state;
pub mod variables;

pub use description::{instantiation_token, model_description_xml, model_description_xml_me};
/// The FMI 3.0 C types (one copy, in `fmi-abi`).
pub use fmi_abi::fmi3 as ffi;
pub use me::no_me;

/// Magic bytes of a serialized FMI 3.0 FMU state (see [`fmi_model::snapshot`]).
pub const SNAPSHOT_MAGIC: [u8; 8] = *b"FMI3SNAP";
