//! `documentation/index.html`: the repository's prose on the signal contract and on the paper
//! (`docs/interface.md`, `docs/paper-notes.md`, compiled in), then the interface rendered from
//! the model description, so that the variable table and the FMU can never disagree. An FMU
//! handed on alone still carries how to wire it and what it implements.
use model_description::{Causality, ModelDescription, ScalarVariable, StartValue};
use std::fmt::Write;

/// The prose every FMU's page carries: (anchor, Markdown), in reading order.
const PROSE: [(&str, &str); 2] = [
    ("interface", include_str!("../../docs/interface.md")),
    ("paper-notes", include_str!("../../docs/paper-notes.md")),
];

/// The order in which a user reads an FMU's interface: what they set, then what they get.
const CAUSALITY_ORDER: [Causality; 6] = [
    Causality::Parameter,
    Causality::CalculatedParameter,
    Causality::Input,
    Causality::Output,
    Causality::Local,
    Causality::Independent,
];

/// What the page of an FMI 3.0 FMU says about it: the same model (one declaration of each
/// variable) with the facts of its own description. The variables are read from the FMI 2.0
/// description, where every array element is a variable of its own.
pub struct Fmi3Facts {
    pub instantiation_token: String,
    pub generation_tool: Option<String>,
}

/// The page of an FMI 2.0 FMU.
pub fn render(md: &ModelDescription) -> String {
    render_page(md, None)
}

/// The page of the FMI 3.0 FMU of the model `md` (its FMI 2.0 description) describes.
pub fn render_fmi3(md: &ModelDescription, facts: &Fmi3Facts) -> String {
    render_page(md, Some(facts))
}

fn render_page(md: &ModelDescription, fmi3: Option<&Fmi3Facts>) -> String {
    let mut html = String::new();
    let title = escape(&md.model_name);
    // `write!` into a String cannot fail; the results are ignored for that reason only.
    let _ = write!(
        html,
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <title>{title}</title>\n<style>\n\
         body {{ font-family: sans-serif; margin: 2em; }}\n\
         table {{ border-collapse: collapse; }}\n\
         th, td {{ border: 1px solid #999; padding: 0.2em 0.5em; text-align: left; }}\n\
         </style>\n</head>\n<body>\n<h1>{title}</h1>\n"
    );
    if let Some(description) = &md.description {
        let _ = writeln!(html, "<p>{}</p>", escape(description));
    }
    render_facts(&mut html, md, fmi3);
    html.push_str(
        "<p>Contents: <a href=\"#interface\">signal contract</a>, \
         <a href=\"#paper-notes\">the paper as implemented</a>, ",
    );
    if md.model_exchange.is_some() {
        html.push_str("<a href=\"#model-exchange\">Model Exchange</a>, ");
    }
    html.push_str("<a href=\"#variables\">variables</a>.</p>\n");
    for (anchor, markdown) in PROSE {
        render_markdown(&mut html, anchor, markdown);
    }
    render_model_exchange(&mut html, md, fmi3.is_some());
    render_enumerations(&mut html, md);
    if fmi3.is_some() {
        html.push_str(
            "<p>This FMU is the FMI 3.0 unit of the model below. The table lists each array \
             element as a variable of its own (<code>r_nue[1]</code>, <code>r_nue[2]</code>, \
             ...), as the FMI 2.0 unit declares them; this FMU declares each array once \
             (<code>r_nue</code>, dimension 3) with its own value references, given in its \
             <code>modelDescription.xml</code>. Names, units, causalities, start values and \
             ranges are the same: both come from one declaration.</p>\n",
        );
    }
    render_variables(&mut html, md);
    html.push_str("</body>\n</html>\n");
    html
}

/// One Markdown document as a section. Links between the docs become links within the page;
/// links to repository files, which the FMU does not contain, stay as text.
fn render_markdown(html: &mut String, anchor: &str, markdown: &str) {
    use pulldown_cmark::{Event, Options, Parser, Tag, TagEnd};
    let mut in_foreign_link = false;
    let events =
        Parser::new_ext(markdown, Options::ENABLE_TABLES).filter_map(|event| match event {
            Event::Start(Tag::Link { dest_url, .. }) => {
                let local = PROSE
                    .iter()
                    .map(|(a, _)| *a)
                    .find(|a| dest_url.as_ref() == format!("{a}.md"));
                match local {
                    Some(a) => Some(Event::Html(format!("<a href=\"#{a}\">").into())),
                    None => {
                        in_foreign_link = true;
                        None
                    }
                }
            }
            Event::End(TagEnd::Link) if in_foreign_link => {
                in_foreign_link = false;
                None
            }
            Event::End(TagEnd::Link) => Some(Event::Html("</a>".into())),
            // Raw HTML in the docs is not ours to pass into the page.
            Event::Html(text) | Event::InlineHtml(text) => Some(Event::Text(text)),
            other => Some(other),
        });
    let _ = writeln!(html, "<section id=\"{anchor}\">");
    pulldown_cmark::html::push_html(html, events);
    html.push_str("</section>\n");
}

fn render_facts(html: &mut String, md: &ModelDescription, fmi3: Option<&Fmi3Facts>) {
    let mut facts: Vec<(&str, String)> = match fmi3 {
        None => vec![
            ("FMI version", md.fmi_version.clone()),
            ("GUID", md.guid.clone()),
        ],
        Some(f) => vec![
            ("FMI version", "3.0".to_owned()),
            ("Instantiation token", f.instantiation_token.clone()),
        ],
    };
    if let Some(me) = &md.model_exchange {
        facts.insert(
            0,
            (
                "Model Exchange model identifier",
                me.model_identifier.clone(),
            ),
        );
    }
    if let Some(cs) = &md.co_simulation {
        facts.insert(
            0,
            (
                "Co-simulation model identifier",
                cs.model_identifier.clone(),
            ),
        );
    }
    let tool = match fmi3 {
        None => md.generation_tool.as_ref(),
        Some(f) => f.generation_tool.as_ref(),
    };
    if let Some(tool) = tool {
        facts.push(("Generated by", tool.clone()));
    }
    if let Some(experiment) = &md.default_experiment {
        let time = |t: Option<f64>| t.map_or_else(|| "-".to_owned(), |t| format!("{t} s"));
        facts.push((
            "Default experiment",
            format!(
                "start {}, stop {}, step {}",
                time(experiment.start_time),
                time(experiment.stop_time),
                time(experiment.step_size)
            ),
        ));
    }
    html.push_str("<table>\n");
    for (key, value) in facts {
        let _ = writeln!(html, "<tr><th>{key}</th><td>{}</td></tr>", escape(&value));
    }
    html.push_str("</table>\n");
}

/// For a model with Model Exchange: its continuous states in the order the state vector holds
/// them (the order of `<Derivatives>`), and its event indicators.
fn render_model_exchange(html: &mut String, md: &ModelDescription, fmi3: bool) {
    if md.model_exchange.is_none() {
        return;
    }
    let variables = &md.model_variables.variables;
    let by_index = |index: u32| variables.get((index as usize).wrapping_sub(1));
    html.push_str("<section id=\"model-exchange\">\n<h2>Model Exchange</h2>\n");
    let _ = writeln!(
        html,
        "<p>A solver of the importer's integrates the equations of motion. The state vector \
         (<code>{}GetContinuousStates</code>, <code>{}SetContinuousStates</code>) holds these \
         variables in this order; the derivative of each is the variable beside it:</p>",
        if fmi3 { "fmi3" } else { "fmi2" },
        if fmi3 { "fmi3" } else { "fmi2" },
    );
    html.push_str(
        "<table>\n<tr><th>#</th><th>state</th><th>unit</th><th>derivative</th>\
         <th>description</th></tr>\n",
    );
    let derivatives = md
        .model_structure
        .derivatives
        .as_ref()
        .map_or(&[][..], |list| list.unknowns.as_slice());
    for (k, unknown) in derivatives.iter().enumerate() {
        let Some(derivative) = by_index(unknown.index) else {
            continue;
        };
        let state = derivative
            .real
            .as_ref()
            .and_then(|r| r.derivative)
            .and_then(by_index);
        let (state_name, unit, description) =
            state.map_or((String::from("?"), String::new(), String::new()), |v| {
                (
                    v.name.clone(),
                    type_start_unit(md, v).2,
                    v.description.clone().unwrap_or_default(),
                )
            });
        let _ = writeln!(
            html,
            "<tr><td>{}</td><td><code>{}</code></td><td>{}</td><td><code>{}</code></td>\
             <td>{}</td></tr>",
            k + 1,
            escape(&state_name),
            escape(&unit),
            escape(&derivative.name),
            escape(&description)
        );
    }
    html.push_str("</table>\n");
    let indicators = md.number_of_event_indicators.unwrap_or(0);
    let shown: Vec<String> = variables
        .iter()
        .filter(|v| {
            v.description
                .as_deref()
                .is_some_and(|d| d.starts_with("Event indicator"))
        })
        .map(|v| format!("<code>{}</code>", escape(&v.name)))
        .collect();
    let _ = write!(
        html,
        "<p>Event indicators: {indicators}; a sign change from positive to non-positive is a \
         state event (the importer locates it and calls the event update)."
    );
    if shown.len() == indicators as usize && indicators > 0 {
        let _ = write!(
            html,
            " In order, their values are shown by the variables {}.",
            shown.join(", ")
        );
    }
    html.push_str("</p>\n</section>\n");
}

fn render_enumerations(html: &mut String, md: &ModelDescription) {
    let Some(types) = &md.type_definitions else {
        return;
    };
    for simple_type in &types.simple_types {
        let Some(enumeration) = &simple_type.enumeration else {
            continue;
        };
        let _ = writeln!(
            html,
            "<h2>Enumeration {}</h2>\n<table>\n<tr><th>value</th><th>name</th><th>description</th></tr>",
            escape(&simple_type.name)
        );
        for item in &enumeration.items {
            let _ = writeln!(
                html,
                "<tr><td>{}</td><td>{}</td><td>{}</td></tr>",
                item.value,
                escape(&item.name),
                escape(item.description.as_deref().unwrap_or(""))
            );
        }
        html.push_str("</table>\n");
    }
}

fn render_variables(html: &mut String, md: &ModelDescription) {
    html.push_str(
        "<h2 id=\"variables\">Variables</h2>\n<table>\n<tr><th>name</th><th>causality</th><th>variability</th>\
         <th>type</th><th>start</th><th>unit</th><th>description</th></tr>\n",
    );
    let variables = &md.model_variables.variables;
    for causality in CAUSALITY_ORDER {
        for variable in variables
            .iter()
            .filter(|v| v.causality_or_default() == causality)
        {
            let (type_name, start, unit) = type_start_unit(md, variable);
            let _ = writeln!(
                html,
                "<tr><td><code>{}</code></td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
                escape(&variable.name),
                causality.name(),
                variable.variability_or_default().name(),
                escape(&type_name),
                escape(&start),
                escape(&unit),
                escape(variable.description.as_deref().unwrap_or("")),
            );
        }
    }
    html.push_str("</table>\n");
}

/// (type, start value, unit) of a variable as shown to a reader; empty where not applicable.
fn type_start_unit(md: &ModelDescription, v: &ScalarVariable) -> (String, String, String) {
    let type_name = match (&v.enumeration, v.kind()) {
        (Some(enumeration), _) => format!("Enumeration {}", enumeration.declared_type),
        (None, Some(kind)) => format!("{kind:?}"),
        (None, None) => "?".to_owned(),
    };
    let start = match v.start() {
        Some(StartValue::Real(x)) => x.to_string(),
        Some(StartValue::Integer(x) | StartValue::Enumeration(x)) => x.to_string(),
        Some(StartValue::Boolean(x)) => x.to_string(),
        Some(StartValue::String(x)) => x,
        None => String::new(),
    };
    let unit = md.unit_of(v).unwrap_or_default().to_owned();
    (type_name, start, unit)
}

fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    const XML: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="2.0" modelName="Lander &amp; Co" guid="{abc}"
    description="a &lt;test&gt; model">
  <CoSimulation modelIdentifier="Lander"/>
  <ModelVariables>
    <ScalarVariable name="out" valueReference="2" causality="output" description="speed">
      <Real unit="m/s"/>
    </ScalarVariable>
    <ScalarVariable name="k" valueReference="1" causality="parameter" variability="fixed">
      <Real start="2.5" unit="N/m"/>
    </ScalarVariable>
    <ScalarVariable name="n" valueReference="3">
      <Integer start="4"/>
    </ScalarVariable>
  </ModelVariables>
  <ModelStructure/>
</fmiModelDescription>"#;

    fn page() -> String {
        render(&ModelDescription::from_xml(XML).unwrap())
    }

    /// Two states (`x`, then `v`, declared in the other order) and one event indicator.
    const ME_XML: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="2.0" modelName="Ball" guid="{b}" numberOfEventIndicators="1">
  <ModelExchange modelIdentifier="Ball"/>
  <CoSimulation modelIdentifier="Ball"/>
  <ModelVariables>
    <ScalarVariable name="v" valueReference="1"><Real unit="m/s"/></ScalarVariable>
    <ScalarVariable name="x" valueReference="2"><Real unit="m"/></ScalarVariable>
    <ScalarVariable name="der(x)" valueReference="3"><Real derivative="2"/></ScalarVariable>
    <ScalarVariable name="der(v)" valueReference="4"><Real derivative="1"/></ScalarVariable>
    <ScalarVariable name="h" valueReference="5" description="Event indicator of impact"><Real/></ScalarVariable>
  </ModelVariables>
  <ModelStructure>
    <Derivatives><Unknown index="3"/><Unknown index="4"/></Derivatives>
  </ModelStructure>
</fmiModelDescription>"#;

    #[test]
    fn a_model_exchange_page_lists_the_states_in_the_solver_order_and_the_event_indicators() {
        let html = render(&ModelDescription::from_xml(ME_XML).unwrap());
        assert!(html.contains("<a href=\"#model-exchange\">"), "{html}");
        let x = html
            .find("<td>1</td><td><code>x</code></td><td>m</td><td><code>der(x)</code></td><td>")
            .expect("x is state 1");
        let v = html
            .find("<td>2</td><td><code>v</code></td><td>m/s</td><td><code>der(v)</code></td><td>")
            .expect("v is state 2");
        assert!(x < v);
        assert!(html.contains("Event indicators: 1;"), "{html}");
        assert!(html.contains("by the variables <code>h</code>."), "{html}");
        assert!(html.contains("<th>Model Exchange model identifier</th><td>Ball</td>"));
        // A Co-Simulation-only page has no such section.
        assert!(!page().contains("model-exchange"));
    }

    #[test]
    fn an_fmi3_page_names_its_own_version_and_token_and_how_arrays_are_declared() {
        let md = ModelDescription::from_xml(ME_XML).unwrap();
        let html = render_fmi3(
            &md,
            &Fmi3Facts {
                instantiation_token: "{t3}".into(),
                generation_tool: Some("tool 3".into()),
            },
        );
        assert!(html.contains("<th>FMI version</th><td>3.0</td>"), "{html}");
        assert!(
            html.contains("<th>Instantiation token</th><td>{t3}</td>"),
            "{html}"
        );
        assert!(!html.contains("{b}"), "the FMI 2.0 GUID is not this FMU's");
        assert!(
            html.contains("<th>Generated by</th><td>tool 3</td>"),
            "{html}"
        );
        assert!(
            html.contains("<code>fmi3GetContinuousStates</code>"),
            "{html}"
        );
        assert!(html.contains("declares each array once"), "{html}");
        assert!(!render(&md).contains("declares each array once"));
    }

    #[test]
    fn the_page_carries_the_docs_prose_with_links_kept_inside_the_page() {
        let html = page();
        assert!(html.contains("<section id=\"interface\">"), "{html}");
        assert!(html.contains("<section id=\"paper-notes\">"), "{html}");
        // Headings, a table and a sentence of each document, rendered.
        assert!(
            html.contains("<h1>Wiring LanderGnc and LanderPlant"),
            "{html}"
        );
        assert!(html.contains("<h1>The paper as implemented</h1>"), "{html}");
        assert!(html.contains("<th>LanderGnc parameter</th>"), "{html}");
        assert!(html.contains("scalar first"), "{html}");
        assert!(
            html.contains("<code>phi_b_of_q_phi_is_phi</code>"),
            "{html}"
        );
        // A link from one document to the other points into the page, never to a file.
        assert!(html.contains("<a href=\"#interface\">"), "{html}");
        assert!(!html.contains("href=\"interface.md\""), "{html}");
        assert!(!html.contains("ERRATA.md") && !html.contains("INTERFACE.md"));
    }

    #[test]
    fn text_from_the_description_is_escaped() {
        let html = page();
        assert!(html.contains("<h1>Lander &amp; Co</h1>"), "{html}");
        assert!(html.contains("a &lt;test&gt; model"), "{html}");
        assert!(!html.contains("<test>"));
    }

    #[test]
    fn every_variable_appears_once_with_unit_and_start() {
        let html = page();
        for name in ["<code>out</code>", "<code>k</code>", "<code>n</code>"] {
            assert_eq!(html.matches(name).count(), 1, "{name} in {html}");
        }
        assert!(html.contains("<td>2.5</td><td>N/m</td>"), "{html}");
        assert!(html.contains("<td>m/s</td><td>speed</td>"), "{html}");
    }

    #[test]
    fn parameters_come_before_outputs_and_absent_causality_reads_local() {
        let html = page();
        let k = html.find("<code>k</code>").unwrap();
        let out = html.find("<code>out</code>").unwrap();
        let n = html.find("<code>n</code>").unwrap();
        assert!(k < out && out < n, "{html}");
        assert!(
            html.contains(
                "<code>n</code></td><td>local</td><td>continuous</td><td>Integer</td><td>4</td>"
            ),
            "{html}"
        );
    }
}
