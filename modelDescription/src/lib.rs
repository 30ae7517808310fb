//! Typed FMI 2.0 model description (`modelDescription.xml`).
//!
//! One set of types serves both directions: our FMUs' XML is *written* from them
//! (see [`ModelDescription::to_xml`]) and the harness *reads* any FMU's XML into them
//! (see [`ModelDescription::from_xml`]). Attribute fields are named `@attr` as
//! `serde-xml-rs` 0.8 requires.
#![deny(unsafe_code)]

mod diagnose;
mod error;
mod query;
mod read;
mod types;
mod validate;
mod write;
mod xsd;

pub use error::Error;
pub use query::{StartValue, VariableKind};
pub use types::*;
