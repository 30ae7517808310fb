//! `terminalsAndIcons/terminalsAndIcons.xml` (FMI 3.0 §2.4.9) from a model's declared
//! terminals, and the description binaries' entry point that prints it beside the model
//! description.
use fmi_model::Model;
use std::fmt::Write;

/// The icon's coordinate system: the usual 200 x 200 units, 0.1 mm each (a 20 mm icon).
const EXTENT: f64 = 100.0;

/// The file: the icon's extent, and the terminals when the model declares any.
///
/// # Panics
/// If the terminals do not check against the declarations (`fmi_model::check_terminals`):
/// this runs when packaging, where a loud stop is the right answer.
pub fn terminals_and_icons_xml<M: Model>() -> String {
    if let Err(problems) = fmi_model::check_terminals::<M>() {
        panic!(
            "invalid terminals of {}:\n  {}",
            M::MODEL_NAME,
            problems.join("\n  ")
        );
    }
    let terminals = M::terminals();
    let mut xml = String::from("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    xml.push_str("<fmiTerminalsAndIcons fmiVersion=\"3.0\">\n");
    let _ = writeln!(
        xml,
        "  <GraphicalRepresentation>\n    <CoordinateSystem x1=\"{lo}\" y1=\"{lo}\" x2=\"{EXTENT}\" \
         y2=\"{EXTENT}\" suggestedScalingFactorTo_mm=\"0.1\"/>\n    <Icon x1=\"{lo}\" y1=\"{lo}\" \
         x2=\"{EXTENT}\" y2=\"{EXTENT}\"/>\n  </GraphicalRepresentation>",
        lo = -EXTENT
    );
    if terminals.is_empty() {
        xml.push_str("</fmiTerminalsAndIcons>\n");
        return xml;
    }
    xml.push_str("  <Terminals>\n");
    for terminal in terminals {
        let _ = writeln!(
            xml,
            "    <Terminal name=\"{}\" matchingRule=\"{}\" terminalKind=\"{}\" description=\"{}\">",
            escape(terminal.name),
            terminal.matching_rule.name(),
            escape(terminal.kind),
            escape(terminal.description)
        );
        for member in terminal.members {
            let _ = writeln!(
                xml,
                "      <TerminalMemberVariable variableName=\"{}\" memberName=\"{}\" \
                 variableKind=\"signal\"/>",
                escape(member.variable),
                escape(member.member)
            );
        }
        xml.push_str("    </Terminal>\n");
    }
    xml.push_str("  </Terminals>\n</fmiTerminalsAndIcons>\n");
    xml
}

fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// What an FMU crate's FMI 3.0 description binary prints: the model description (given by
/// the caller, with or without Model Exchange), or with the argument `terminals-and-icons`
/// the terminals file, which packaging puts beside it.
pub fn describe<M: Model>(model_description: fn() -> String) {
    match std::env::args().nth(1).as_deref() {
        Some("terminals-and-icons") => print!("{}", terminals_and_icons_xml::<M>()),
        _ => print!("{}", model_description()),
    }
}
