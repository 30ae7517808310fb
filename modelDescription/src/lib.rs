//! Typed FMI 2.0 model description (`modelDescription.xml`); FMI 3.0 files are read (only) by
//! [`fmi3::Fmi3ModelDescription`].
//!
//! One set of types serves both directions: our FMUs' XML is *written* from them and a
//! master *reads* any FMU's XML into them. Attribute fields are named `@attr` as
//! `serde-xml-rs` 0.8 requires.
//!
//! - Writing: [`ModelDescription::to_xml`] gives indented, deterministic XML whose doubles
//!   parse back to the same bits (see `xsd.rs` for the number format).
//! - Reading: [`ModelDescription::from_xml`] and [`ModelDescription::from_file`] accept
//!   other tools' files (unknown elements and attributes, comments, processing
//!   instructions, aliases, `0`/`1` booleans). A file that cannot be read gives an
//!   [`Error`] naming line, element and attribute, e.g.
//!   `line 15: ScalarVariable 'x' (index 2): attribute valueReference: "1a" is not an
//!   unsigned integer: invalid digit found in string`.
//! - Checking: [`ModelDescription::validate`] lists the semantic problems the schema cannot
//!   express (units, declared types, start values, ModelStructure indices, ...).
//! - Querying: [`ModelDescription::variable`], [`ScalarVariable::kind`],
//!   [`ScalarVariable::start`], the FMI defaults (`causality_or_default`, ...) and the
//!   lookups a master needs.
#![deny(unsafe_code)]

mod date_time;
mod declarations;
mod diagnose;
mod error;
pub mod fmi3;
mod query;
mod read;
pub mod terminals;
mod types;
mod validate;
mod write;
mod xsd;

pub use date_time::iso8601_utc;
pub use declarations::refuse_declarations;
pub use error::Error;
pub use query::{StartValue, VariableKind};
pub use types::*;
