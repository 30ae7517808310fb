//! The elements of a small XML file as a flat list, each with its line, its depth and its
//! attributes by local name: the LS-REF files are read by what they hold, whatever
//! namespace prefixes a tool wrote and whatever elements a later draft adds.
use xml::{common::Position, reader::XmlEvent, ParserConfig};

#[derive(Debug, Clone, PartialEq)]
pub struct Element {
    /// The local name (`Related` of `ls:Related`).
    pub name: String,
    /// 0 for the root.
    pub depth: usize,
    /// 1-based.
    pub line: u64,
    /// `(local name, value)`: `fmi-ls:fmi-ls-name` is `fmi-ls-name`.
    pub attributes: Vec<(String, String)>,
}

impl Element {
    pub fn attribute(&self, name: &str) -> Option<&str> {
        self.attributes
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_str())
    }

    /// `<Name a="..">, line N`: where a message about the element points.
    pub fn at(&self, attribute: Option<&str>) -> String {
        match attribute.and_then(|a| self.attribute(a).map(|v| (a, v))) {
            Some((a, v)) => format!("<{} {a}=\"{v}\"> (line {})", self.name, self.line),
            None => format!("<{}> (line {})", self.name, self.line),
        }
    }
}

/// Every element of `bytes` in document order, or why the file is no XML.
pub fn parse(bytes: &[u8]) -> Result<Vec<Element>, String> {
    let mut reader = ParserConfig::new()
        .trim_whitespace(true)
        .ignore_comments(true)
        .create_reader(bytes);
    let mut elements = Vec::new();
    let mut depth = 0;
    loop {
        let event = reader.next().map_err(|e| {
            let at = Position::position(&e);
            format!("line {}, column {}: {e}", at.row + 1, at.column + 1)
        })?;
        match event {
            XmlEvent::StartElement {
                name, attributes, ..
            } => {
                elements.push(Element {
                    name: name.local_name,
                    depth,
                    line: Position::position(&reader).row + 1,
                    attributes: attributes
                        .into_iter()
                        .map(|a| (a.name.local_name, a.value))
                        .collect(),
                });
                depth += 1;
            }
            XmlEvent::EndElement { .. } => depth -= 1,
            XmlEvent::EndDocument => return Ok(elements),
            _ => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn prefixed_attributes_are_read_by_their_local_name() {
        let xml = br#"<?xml version="1.0"?>
<fmiReferences xmlns:fmi-ls="http://fmi-standard.org/fmi-ls-manifest"
    fmi-ls:fmi-ls-name="org.fmi-standard.fmi-ls-ref">
  <!-- a comment -->
  <Related source="a.csv" role="result"/>
</fmiReferences>"#;
        let elements = parse(xml).unwrap();
        assert_eq!(elements.len(), 2);
        assert_eq!(
            elements[0].attribute("fmi-ls-name"),
            Some("org.fmi-standard.fmi-ls-ref")
        );
        assert_eq!(
            (elements[1].name.as_str(), elements[1].depth),
            ("Related", 1)
        );
        assert_eq!(elements[1].line, 5);
        assert_eq!(
            elements[1].at(Some("source")),
            "<Related source=\"a.csv\"> (line 5)"
        );
    }

    #[test]
    fn a_file_that_is_no_xml_says_where() {
        let error = parse(b"<a>\n<b></a>").unwrap_err();
        assert!(error.starts_with("line 2"), "{error}");
    }
}
