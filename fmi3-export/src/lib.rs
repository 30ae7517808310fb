//! The FMI 3.0 layer (Co-Simulation, and Model Exchange for a model that implements
//! [`fmi_model::ContinuousModel`]), generated from the same declarations as the FMI 2.0
//! layer, on the same export core ([`fmi_export`]). A model crate invokes [`export_fmi3!`]
//! once. What is FMI 3.0's own lives here: the 75 `fmi3*` C entry points and their argument
//! unpacking ([`abi`], [`me`]), the state table ([`state`]), the variable view (a vector is
//! one Float64 array with one `Dimension`, [`variables`]) and the model description
//! ([`description`]).
#![deny(unsafe_code)]

pub mod abi;
pub mod description;
mod export;
pub mod me;
pub mod state;
pub mod terminals;
pub mod variables;
pub mod version;

pub use description::{instantiation_token, model_description_xml, model_description_xml_me};
/// The FMI 3.0 C types (one copy, in `fmi-abi`).
pub use fmi_abi::fmi3 as ffi;
/// The export core, for the symbols [`export_fmi3!`] generates through it.
pub use fmi_export;
pub use me::no_me;
pub use terminals::{describe, terminals_and_icons_xml};
pub use version::Fmi3;

/// Magic bytes of a serialized FMI 3.0 FMU state (see [`fmi_export::snapshot`]).
pub const SNAPSHOT_MAGIC: [u8; 8] = *b"FMI3SNAP";
