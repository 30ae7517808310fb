//! `terminalsAndIcons/terminalsAndIcons.xml` (FMI 3.0 §2.4.9), read only: the terminals and
//! their member variables, which a master uses to connect two FMUs' groups in one step. The
//! graphical representation is skipped. Nested terminals are flattened, each named by its
//! path (`outer.inner`).
use crate::Error;
use xml::{reader::XmlEvent, ParserConfig};

/// One member variable of a terminal.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TerminalMember {
    /// The model variable that is connected.
    pub variable_name: String,
    /// The name matched against the other terminal's members (`plug`, `bus`); absent for
    /// `sequence`.
    pub member_name: Option<String>,
    /// `signal`, `inflow`, `outflow` or a kind of another standard.
    pub variable_kind: String,
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Terminal {
    /// The path of the terminal: its name, after its parents' names and a dot if nested.
    pub name: String,
    /// `plug`, `bus`, `sequence`, `none`, or a rule of another standard.
    pub matching_rule: String,
    pub terminal_kind: Option<String>,
    pub description: Option<String>,
    pub members: Vec<TerminalMember>,
}

/// Every terminal of the file, in document order (a parent before its children).
pub fn read_terminals(bytes: &[u8]) -> Result<Vec<Terminal>, Error> {
    crate::refuse_declarations(bytes)?;
    let config = ParserConfig::new()
        .trim_whitespace(true)
        .ignore_comments(true);
    let mut reader = config.create_reader(bytes);
    let mut stack: Vec<String> = Vec::new();
    // Indices into `terminals` of the open <Terminal> elements.
    let mut open: Vec<usize> = Vec::new();
    let mut terminals: Vec<Terminal> = Vec::new();
    loop {
        let event = reader.next().map_err(|e| Error::malformed(&e, &stack))?;
        match event {
            XmlEvent::StartElement {
                name, attributes, ..
            } => {
                let line = xml::common::Position::position(&reader).row + 1;
                let local = name.local_name;
                let get = |attribute: &str| {
                    attributes
                        .iter()
                        .find(|a| a.name.prefix.is_none() && a.name.local_name == attribute)
                        .map(|a| a.value.clone())
                };
                let required = |attribute: &str, element: &str| {
                    get(attribute).ok_or_else(|| Error::Invalid {
                        line,
                        element: element.to_owned(),
                        attribute: Some(attribute.to_owned()),
                        problem: "required attribute missing".into(),
                    })
                };
                match (stack.is_empty(), local.as_str()) {
                    (true, "fmiTerminalsAndIcons") => {}
                    (true, other) => {
                        return Err(Error::Invalid {
                            line,
                            element: other.to_owned(),
                            attribute: None,
                            problem: "the root of terminalsAndIcons.xml is \
                                      <fmiTerminalsAndIcons>"
                                .into(),
                        })
                    }
                    (false, "Terminal") => {
                        let own = required("name", "Terminal")?;
                        let name = match open.last() {
                            Some(&parent) => format!("{}.{own}", terminals[parent].name),
                            None => own,
                        };
                        let element = format!("Terminal '{name}'");
                        terminals.push(Terminal {
                            matching_rule: required("matchingRule", &element)?,
                            terminal_kind: get("terminalKind"),
                            description: get("description"),
                            members: Vec::new(),
                            name,
                        });
                        open.push(terminals.len() - 1);
                    }
                    (false, "TerminalMemberVariable") => {
                        let Some(&terminal) = open.last() else {
                            return Err(Error::Invalid {
                                line,
                                element: local,
                                attribute: None,
                                problem: "outside a <Terminal>".into(),
                            });
                        };
                        let element = format!(
                            "Terminal '{}' > TerminalMemberVariable",
                            terminals[terminal].name
                        );
                        let member = TerminalMember {
                            variable_name: required("variableName", &element)?,
                            member_name: get("memberName"),
                            variable_kind: required("variableKind", &element)?,
                        };
                        terminals[terminal].members.push(member);
                    }
                    _ => {}
                }
                stack.push(local);
            }
            XmlEvent::EndElement { name } => {
                if name.local_name == "Terminal" {
                    open.pop();
                }
                stack.pop();
            }
            XmlEvent::EndDocument => break,
            _ => {}
        }
    }
    Ok(terminals)
}

#[cfg(test)]
mod tests {
    use super::*;

    const FILE: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<fmiTerminalsAndIcons fmiVersion="3.0">
  <GraphicalRepresentation>
    <CoordinateSystem x1="-100" y1="-100" x2="100" y2="100" suggestedScalingFactorTo_mm="0.1"/>
  </GraphicalRepresentation>
  <Terminals>
    <Terminal name="navigation" matchingRule="plug" terminalKind="k">
      <TerminalMemberVariable variableName="r_true" memberName="r" variableKind="signal"/>
      <Terminal name="inner" matchingRule="bus">
        <TerminalMemberVariable variableName="m" memberName="m" variableKind="signal"/>
      </Terminal>
      <TerminalMemberVariable variableName="v" memberName="v" variableKind="signal"/>
    </Terminal>
  </Terminals>
</fmiTerminalsAndIcons>"#;

    #[test]
    fn terminals_and_nested_terminals_are_read_with_their_members() {
        let terminals = read_terminals(FILE.as_bytes()).unwrap();
        assert_eq!(terminals.len(), 2);
        let outer = &terminals[0];
        assert_eq!(
            (outer.name.as_str(), outer.matching_rule.as_str()),
            ("navigation", "plug")
        );
        assert_eq!(outer.terminal_kind.as_deref(), Some("k"));
        let members: Vec<(&str, Option<&str>)> = outer
            .members
            .iter()
            .map(|m| (m.variable_name.as_str(), m.member_name.as_deref()))
            .collect();
        assert_eq!(members, [("r_true", Some("r")), ("v", Some("v"))]);
        assert_eq!(terminals[1].name, "navigation.inner");
        assert_eq!(terminals[1].members[0].variable_name, "m");
    }

    #[test]
    fn a_missing_required_attribute_is_named_with_its_line() {
        let bad = FILE.replace(r#" matchingRule="bus""#, "");
        let text = read_terminals(bad.as_bytes()).unwrap_err().to_string();
        assert!(
            text.contains("line 9") && text.contains("matchingRule"),
            "{text}"
        );
    }

    #[test]
    fn another_root_is_refused() {
        let text = read_terminals(b"<fmiModelDescription/>")
            .unwrap_err()
            .to_string();
        assert!(text.contains("fmiTerminalsAndIcons"), "{text}");
    }
}
