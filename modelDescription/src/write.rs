//! Writing: serde-xml-rs's serializer with xml-rs's indenting emitter.
//!
//! Checked against what a reviewer needs from the checked-in XML: the UTF-8 declaration,
//! one element per line with two-space indentation, `<>&"'` and line breaks escaped in
//! attribute values (xml-rs does this), booleans as `true`/`false`, doubles in the
//! round-trip form of [`crate::xsd`].
//!
//! Post-processing, because xml-rs leaves two gaps in attribute escaping: a raw tab is
//! replaced by `&#x9;` (every reader would normalise it to a space; the output holds tabs
//! nowhere else, as it indents with spaces and has no text content), and the control
//! characters XML 1.0 cannot represent at all are refused instead of written.
use crate::{Error, ModelDescription};

impl ModelDescription {
    /// The model description as an indented, deterministic `modelDescription.xml`.
    ///
    /// Writing is mechanical: call [`ModelDescription::validate`] first to catch a
    /// description that other tools would refuse.
    pub fn to_xml(&self) -> Result<String, Error> {
        let emitter = xml::EmitterConfig::new()
            .perform_indent(true)
            .pad_self_closing(false);
        let text = serde_xml_rs::SerdeXml::new()
            .emitter(emitter)
            .to_string(self)
            .map_err(|e| Error::Write(e.to_string()))?;
        if let Some((line_number, line)) = text
            .lines()
            .enumerate()
            .find(|(_, line)| line.chars().any(not_representable))
        {
            return Err(Error::Write(format!(
                "line {} holds a control character XML 1.0 cannot represent: {}",
                line_number + 1,
                line.trim_start().escape_debug()
            )));
        }
        let mut text = text.replace('\t', "&#x9;");
        text.push('\n');
        Ok(text)
    }
}

/// Characters outside XML 1.0's `Char` production, even as character references.
fn not_representable(c: char) -> bool {
    matches!(c, '\u{0}'..='\u{8}' | '\u{B}' | '\u{C}' | '\u{E}'..='\u{1F}' | '\u{FFFE}' | '\u{FFFF}')
}
