//! Reading: a located diagnosis pass over the XML events, then serde-xml-rs for the mapping.
//!
//! serde-xml-rs's errors carry neither line nor element ("invalid digit found in string"),
//! so the diagnosis pass ([`crate::diagnose`]) checks every attribute we map first and
//! reports the element and attribute at fault; serde-xml-rs then runs on input it accepts.
use std::path::Path;

use crate::{diagnose, Error, ModelDescription};

impl ModelDescription {
    /// Reads any FMI 2.0 `modelDescription.xml`. Elements and attributes this crate does not
    /// model (vendor annotations, source files, ...) are skipped.
    pub fn from_xml(xml: &str) -> Result<Self, Error> {
        Self::from_bytes(xml.as_bytes())
    }

    /// Reads a `modelDescription.xml` file; the encoding declared in the file is honoured.
    pub fn from_file(path: impl AsRef<Path>) -> Result<Self, Error> {
        let path = path.as_ref();
        let bytes = std::fs::read(path).map_err(|source| Error::Io {
            path: path.to_owned(),
            source,
        })?;
        Self::from_bytes(&bytes)
    }

    fn from_bytes(bytes: &[u8]) -> Result<Self, Error> {
        crate::refuse_declarations(bytes)?;
        diagnose::check(bytes)?;
        serde_xml_rs::SerdeXml::new()
            // Tolerates other tools' stray elements between the ScalarVariables.
            .overlapping_sequences(true)
            .from_reader(bytes)
            .map_err(|e| Error::Unmapped(e.to_string()))
    }
}
