//! The located check that runs before serde-xml-rs: walks the XML events with xml-rs and
//! checks, against a table of the FMI 2.0 attributes this crate maps, that each is present
//! when required and lexically valid, and that each ScalarVariable and SimpleType has
//! exactly one type element. Failures name line, element and attribute.
//!
//! Elements outside the table (annotations, source files, other tools' extensions) are
//! walked but not checked, which is what "unknown elements are ignored" means on read.
use std::collections::BTreeMap;

use xml::{common::Position, reader::XmlEvent, ParserConfig};

use crate::{xsd, Error};

const ROOT: &str = "fmiModelDescription";

/// The lexical space an attribute value must belong to, as serde-xml-rs will parse it.
#[derive(Clone, Copy)]
enum Lexical {
    Text,
    UnsignedInt,
    Int,
    Double,
    Boolean,
    /// Whitespace-separated `xs:unsignedInt`s (ModelStructure `dependencies`).
    UnsignedIntList,
    OneOf(&'static [&'static str]),
    /// `fmiVersion`: refused early when not 2.x, because an FMI 1.0 or 3.0 file would
    /// otherwise fail later with a message about some other attribute.
    Fmi2Version,
}

struct Attr {
    name: &'static str,
    lexical: Lexical,
    required: bool,
}

const fn req(name: &'static str, lexical: Lexical) -> Attr {
    Attr {
        name,
        lexical,
        required: true,
    }
}

const fn opt(name: &'static str, lexical: Lexical) -> Attr {
    Attr {
        name,
        lexical,
        required: false,
    }
}

use Lexical::{Boolean, Double, Fmi2Version, Int, OneOf, Text, UnsignedInt, UnsignedIntList};

pub(crate) const CAUSALITIES: &[&str] = &[
    "parameter",
    "calculatedParameter",
    "input",
    "output",
    "local",
    "independent",
];
pub(crate) const VARIABILITIES: &[&str] =
    &["constant", "fixed", "tunable", "discrete", "continuous"];
pub(crate) const INITIALS: &[&str] = &["exact", "approx", "calculated"];

/// The type elements of which a ScalarVariable or SimpleType holds exactly one.
const TYPE_ELEMENTS: &[&str] = &["Real", "Integer", "Boolean", "String", "Enumeration"];

/// Child elements that may appear at most once, by parent path below the root. The type
/// elements of ScalarVariable and SimpleType are counted separately.
fn at_most_once(parent: &[&str]) -> &'static [&'static str] {
    match parent {
        [] => &[
            "ModelExchange",
            "CoSimulation",
            "UnitDefinitions",
            "TypeDefinitions",
            "LogCategories",
            "DefaultExperiment",
            "VendorAnnotations",
            "ModelVariables",
            "ModelStructure",
        ],
        ["ModelStructure"] => &["Outputs", "Derivatives", "InitialUnknowns"],
        ["UnitDefinitions", "Unit"] => &["BaseUnit"],
        ["TypeDefinitions", "SimpleType", "Enumeration"] | ["ModelVariables", "ScalarVariable"] => {
            &["Annotations"]
        }
        _ => &[],
    }
}

/// Attribute rules by element path below the root (the root itself is the empty path).
fn rules(path: &[&str]) -> Option<&'static [Attr]> {
    const CO_SIMULATION: &[Attr] = &[
        req("modelIdentifier", Text),
        opt("needsExecutionTool", Boolean),
        opt("canHandleVariableCommunicationStepSize", Boolean),
        opt("canInterpolateInputs", Boolean),
        opt("maxOutputDerivativeOrder", UnsignedInt),
        opt("canRunAsynchronuously", Boolean),
        opt("canBeInstantiatedOnlyOncePerProcess", Boolean),
        opt("canNotUseMemoryManagementFunctions", Boolean),
        opt("canGetAndSetFMUstate", Boolean),
        opt("canSerializeFMUstate", Boolean),
        opt("providesDirectionalDerivative", Boolean),
    ];
    const BASE_UNIT: &[Attr] = &[
        opt("kg", Int),
        opt("m", Int),
        opt("s", Int),
        opt("A", Int),
        opt("K", Int),
        opt("mol", Int),
        opt("cd", Int),
        opt("rad", Int),
        opt("factor", Double),
        opt("offset", Double),
    ];
    const SCALAR_VARIABLE: &[Attr] = &[
        req("name", Text),
        req("valueReference", UnsignedInt),
        opt("causality", OneOf(CAUSALITIES)),
        opt("variability", OneOf(VARIABILITIES)),
        opt("initial", OneOf(INITIALS)),
        opt("canHandleMultipleSetPerTimeInstant", Boolean),
    ];
    const REAL_VARIABLE: &[Attr] = &[
        opt("min", Double),
        opt("max", Double),
        opt("nominal", Double),
        opt("start", Double),
        opt("derivative", UnsignedInt),
    ];
    const INTEGER_VARIABLE: &[Attr] = &[opt("min", Int), opt("max", Int), opt("start", Int)];
    const ENUMERATION_VARIABLE: &[Attr] = &[
        req("declaredType", Text),
        opt("min", Int),
        opt("max", Int),
        opt("start", Int),
    ];
    const UNKNOWN: &[Attr] = &[
        req("index", UnsignedInt),
        opt("dependencies", UnsignedIntList),
    ];
    const NAMED: &[Attr] = &[req("name", Text)];
    const ROOT_ATTRS: &[Attr] = &[
        req("fmiVersion", Fmi2Version),
        req("modelName", Text),
        req("guid", Text),
        opt("numberOfEventIndicators", UnsignedInt),
    ];
    const MODEL_EXCHANGE: &[Attr] = &[req("modelIdentifier", Text)];
    const DISPLAY_UNIT: &[Attr] = &[
        req("name", Text),
        opt("factor", Double),
        opt("offset", Double),
    ];
    const REAL_TYPE: &[Attr] = &[opt("min", Double), opt("max", Double)];
    const INTEGER_TYPE: &[Attr] = &[opt("min", Int), opt("max", Int)];
    const ITEM: &[Attr] = &[req("name", Text), req("value", Int)];
    const DEFAULT_EXPERIMENT: &[Attr] = &[
        opt("startTime", Double),
        opt("stopTime", Double),
        opt("tolerance", Double),
        opt("stepSize", Double),
    ];
    const BOOLEAN_VARIABLE: &[Attr] = &[opt("start", Boolean)];

    Some(match path {
        [] => ROOT_ATTRS,
        ["ModelExchange"] => MODEL_EXCHANGE,
        ["CoSimulation"] => CO_SIMULATION,
        ["UnitDefinitions", "Unit"] => NAMED,
        ["UnitDefinitions", "Unit", "BaseUnit"] => BASE_UNIT,
        ["UnitDefinitions", "Unit", "DisplayUnit"] => DISPLAY_UNIT,
        ["TypeDefinitions", "SimpleType"] => NAMED,
        ["TypeDefinitions", "SimpleType", "Real"] => REAL_TYPE,
        ["TypeDefinitions", "SimpleType", "Integer"] => INTEGER_TYPE,
        ["TypeDefinitions", "SimpleType", "Enumeration", "Item"] => ITEM,
        ["LogCategories", "Category"] => NAMED,
        ["DefaultExperiment"] => DEFAULT_EXPERIMENT,
        ["ModelVariables", "ScalarVariable"] => SCALAR_VARIABLE,
        ["ModelVariables", "ScalarVariable", "Real"] => REAL_VARIABLE,
        ["ModelVariables", "ScalarVariable", "Integer"] => INTEGER_VARIABLE,
        ["ModelVariables", "ScalarVariable", "Boolean"] => BOOLEAN_VARIABLE,
        ["ModelVariables", "ScalarVariable", "Enumeration"] => ENUMERATION_VARIABLE,
        ["ModelStructure", "Outputs" | "Derivatives" | "InitialUnknowns", "Unknown"] => UNKNOWN,
        _ => return None,
    })
}

/// Whether elements at this path hold exactly one of [`TYPE_ELEMENTS`].
fn holds_one_type(path: &[&str]) -> bool {
    matches!(
        path,
        ["ModelVariables", "ScalarVariable"] | ["TypeDefinitions", "SimpleType"]
    )
}

/// One open element during the walk.
struct Frame {
    name: String,
    /// How a message names this element, e.g. `ScalarVariable 'x' (index 3)`.
    label: String,
    /// Whether the label identifies the element on its own (it carries a name or index),
    /// so a description can start here instead of at the root.
    anchored: bool,
    line: u64,
    /// Number of child elements seen so far, per child name (for ordinals).
    children: BTreeMap<String, u32>,
}

/// Checks `bytes` as described in the module documentation.
pub(crate) fn check(bytes: &[u8]) -> Result<(), Error> {
    let config = ParserConfig::new()
        .trim_whitespace(true)
        .ignore_comments(true);
    let mut reader = config.create_reader(bytes);
    // Frames of the open elements, root first.
    let mut stack: Vec<Frame> = Vec::new();
    loop {
        let event = match reader.next() {
            Ok(event) => event,
            Err(e) => {
                let position = e.position();
                return Err(Error::Malformed {
                    line: position.row + 1,
                    column: position.column + 1,
                    inside: (!stack.is_empty()).then(|| describe(&stack)),
                    message: malformed_message(&e),
                });
            }
        };
        match event {
            XmlEvent::StartElement {
                name, attributes, ..
            } => {
                let line = reader.position().row + 1;
                let local = name.local_name;
                if stack.is_empty() && local != ROOT {
                    return Err(Error::WrongRoot { found: local });
                }
                let ordinal = match stack.last_mut() {
                    Some(parent) => {
                        let count = parent.children.entry(local.clone()).or_insert(0);
                        *count += 1;
                        *count
                    }
                    None => 1,
                };
                let lookup = |attr: &str| {
                    attributes
                        .iter()
                        .find(|a| a.name.prefix.is_none() && a.name.local_name == attr)
                        .map(|a| a.value.as_str())
                };
                let (label, anchored) = label(&local, lookup("name"), ordinal);
                stack.push(Frame {
                    name: local,
                    label,
                    anchored,
                    line,
                    children: BTreeMap::new(),
                });
                let path = path_below_root(&stack);
                if let Some((name, parent)) = path.split_last() {
                    if ordinal > 1 && at_most_once(parent).contains(name) {
                        return Err(invalid(&stack, None, "appears more than once".to_owned()));
                    }
                }
                if let Some(attrs) = rules(&path) {
                    for attr in attrs {
                        check_attribute(&stack, attr, lookup(attr.name))?;
                    }
                }
            }
            XmlEvent::EndElement { .. } => {
                let path = path_below_root(&stack);
                if holds_one_type(&path) {
                    check_one_type_element(&stack)?;
                }
                stack.pop();
            }
            XmlEvent::EndDocument => return Ok(()),
            _ => {}
        }
    }
}

fn path_below_root(stack: &[Frame]) -> Vec<&str> {
    stack.iter().skip(1).map(|f| f.name.as_str()).collect()
}

fn label(element: &str, name: Option<&str>, ordinal: u32) -> (String, bool) {
    match (element, name) {
        ("ScalarVariable", Some(name)) => {
            (format!("ScalarVariable '{name}' (index {ordinal})"), true)
        }
        ("ScalarVariable", None) => (format!("ScalarVariable (index {ordinal})"), true),
        ("Unknown", _) => (format!("Unknown #{ordinal}"), false),
        (_, Some(name)) => (format!("{element} '{name}'"), true),
        (_, None) => (element.to_owned(), false),
    }
}

/// Names the innermost open element, starting from its outermost anchored ancestor so the
/// message carries just enough context (`ScalarVariable 'x' (index 3) > Real`).
fn describe(stack: &[Frame]) -> String {
    if stack.len() == 1 {
        return stack[0].label.clone();
    }
    let below_root = &stack[1..];
    let start = below_root.iter().position(|f| f.anchored).unwrap_or(0);
    below_root[start..]
        .iter()
        .map(|f| f.label.as_str())
        .collect::<Vec<_>>()
        .join(" > ")
}

fn invalid(stack: &[Frame], attribute: Option<&str>, problem: String) -> Error {
    Error::Invalid {
        line: stack.last().map_or(0, |f| f.line),
        element: describe(stack),
        attribute: attribute.map(str::to_owned),
        problem,
    }
}

fn check_attribute(stack: &[Frame], attr: &Attr, value: Option<&str>) -> Result<(), Error> {
    let Some(value) = value else {
        return if attr.required {
            Err(invalid(
                stack,
                Some(attr.name),
                "required but missing".to_owned(),
            ))
        } else {
            Ok(())
        };
    };
    let problem = match attr.lexical {
        Text => None,
        UnsignedInt => value
            .parse::<u32>()
            .err()
            .map(|e| format!("\"{value}\" is not an unsigned integer: {e}")),
        Int => value
            .parse::<i32>()
            .err()
            .map(|e| format!("\"{value}\" is not a 32-bit integer: {e}")),
        Double => xsd::parse_double(value).err(),
        // The spellings serde-xml-rs accepts, which are exactly xs:boolean's.
        Boolean => (!matches!(value, "true" | "false" | "1" | "0"))
            .then(|| format!("\"{value}\" is not a boolean (true, false, 1 or 0)")),
        UnsignedIntList => value
            .split_ascii_whitespace()
            .find(|item| item.parse::<u32>().is_err())
            .map(|item| format!("\"{item}\" in \"{value}\" is not an unsigned integer")),
        Fmi2Version => (!value.starts_with("2."))
            .then(|| format!("\"{value}\" is not FMI 2.0, the only version this reader reads")),
        OneOf(allowed) => (!allowed.contains(&value))
            .then(|| format!("\"{value}\" is not one of {}", allowed.join(", "))),
    };
    match problem {
        Some(problem) => Err(invalid(stack, Some(attr.name), problem)),
        None => Ok(()),
    }
}

fn check_one_type_element(stack: &[Frame]) -> Result<(), Error> {
    let Some(frame) = stack.last() else {
        return Ok(());
    };
    let present: Vec<String> = TYPE_ELEMENTS
        .iter()
        .filter_map(|t| frame.children.get(*t).map(|n| (t, *n)))
        .flat_map(|(t, n)| std::iter::repeat_n(format!("<{t}>"), n as usize))
        .collect();
    match present.len() {
        1 => Ok(()),
        0 => Err(invalid(
            stack,
            None,
            "has no type element (expected one of <Real>, <Integer>, <Boolean>, <String>, <Enumeration>)"
                .to_owned(),
        )),
        _ => Err(invalid(
            stack,
            None,
            format!("has {} type elements ({}), expected exactly one", present.len(), present.join(", ")),
        )),
    }
}

fn malformed_message(e: &xml::reader::Error) -> String {
    use xml::reader::ErrorKind;
    match e.kind() {
        ErrorKind::Syntax(message) => message.to_string(),
        ErrorKind::UnexpectedEof => "unexpected end of file (truncated?)".to_owned(),
        ErrorKind::Utf8(reason) => format!("invalid UTF-8: {reason}"),
        ErrorKind::Io(io) => io.to_string(),
        _ => e.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Causality, Initial, Variability};

    /// The diagnosis must accept exactly the spellings serde maps onto the enums.
    #[test]
    fn enumerated_attribute_lists_match_the_serde_enums() {
        fn parses<T: serde::de::DeserializeOwned>(text: &str) -> bool {
            let xml = format!("<x v=\"{text}\"/>");
            #[derive(serde::Deserialize)]
            struct Holder<T> {
                #[serde(rename = "@v")]
                #[allow(dead_code)]
                v: T,
            }
            serde_xml_rs::from_str::<Holder<T>>(&xml).is_ok()
        }
        assert!(CAUSALITIES.iter().all(|c| parses::<Causality>(c)));
        assert!(VARIABILITIES.iter().all(|v| parses::<Variability>(v)));
        assert!(INITIALS.iter().all(|i| parses::<Initial>(i)));
        // And the lists are complete: every variant is listed.
        assert_eq!(CAUSALITIES.len(), 6);
        assert_eq!(VARIABILITIES.len(), 5);
        assert_eq!(INITIALS.len(), 3);
        assert!(!parses::<Causality>("internal"), "an FMI 1.0 causality");
    }
}
