//! The one renderer of an SSD, SSP 1.0 or 2.0: elements, connectors, inline parameter sets,
//! connections, the system's OMSimulator annotation, `DefaultExperiment` with our master
//! annotation. What differs by version comes in a [`Body`] ([`super::ssp`] makes SSP 1.0's,
//! [`super::ssp2`] SSP 2.0's); why the file looks as it does for other tools is said in
//! [`super::ssp`].
use super::{Ordering, SystemDescription};
use std::fmt::Write as _;

pub const ANNOTATION_TYPE: &str = "org.lander-fmi.master";
/// The name of every component's parameter set in the SSDs we write (Ecos's convention).
pub const PARAMETER_SET: &str = "initialValues";
const OMS_ANNOTATION_TYPE: &str = "org.openmodelica";
const NS_OMS: &str =
    "https://raw.githubusercontent.com/OpenModelica/OMSimulator/master/schema/oms.xsd";
const NS_SSC: &str = "http://ssp-standard.org/SSP1/SystemStructureCommon";
const NS_SSD: &str = "http://ssp-standard.org/SSP1/SystemStructureDescription";
const NS_SSV: &str = "http://ssp-standard.org/SSP1/SystemStructureParameterValues";

/// What an SSD version writes of its own; the rest of the file is the same in 1.0 and 2.0.
pub(super) struct Body {
    /// The SSD's and every parameter set's `version`.
    pub version: &'static str,
    pub connectors: Vec<WrittenConnector>,
    /// Per instance, in instance order.
    pub parameters: Vec<Vec<Written>>,
    pub connections: Vec<(String, String)>,
}

pub(super) struct WrittenConnector {
    pub instance: String,
    pub name: String,
    pub kind: &'static str,
    /// The `ssc:` element.
    pub type_name: &'static str,
    /// `ssc:Dimension` sizes; none for a scalar.
    pub dimensions: Vec<u64>,
}

/// A parameter value: the `ssv:` element, its `value` (unescaped; a row-major list for an
/// array) and the array's `ssc:Dimension` sizes.
pub(super) struct Written {
    pub name: String,
    pub type_name: &'static str,
    pub value: String,
    pub dimensions: Vec<u64>,
}

fn dimensions(sizes: &[u64]) -> String {
    sizes
        .iter()
        .map(|n| format!(r#"<ssc:Dimension size="{n}"/>"#))
        .collect()
}

pub(super) fn render(system: &SystemDescription, body: &Body) -> String {
    let version = body.version;
    let mut x = String::new();
    let _ = writeln!(x, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        x,
        r#"<ssd:SystemStructureDescription xmlns:ssc="{NS_SSC}" xmlns:ssd="{NS_SSD}" xmlns:ssv="{NS_SSV}" xmlns:oms="{NS_OMS}" version="{version}" name="{}">"#,
        esc(&system.name)
    );
    let _ = writeln!(x, r#"  <ssd:System name="{}">"#, esc(&system.name));
    let _ = writeln!(x, "    <ssd:Elements>");
    for (instance, parameters) in system.instances.iter().zip(&body.parameters) {
        let file = instance
            .fmu
            .file_name()
            .map(|f| f.to_string_lossy().into_owned())
            .unwrap_or_default();
        let _ = writeln!(
            x,
            r#"      <ssd:Component name="{}" type="application/x-fmu-sharedlibrary" source="resources/{}">"#,
            esc(&instance.name),
            esc(&file)
        );
        let own: Vec<_> = body
            .connectors
            .iter()
            .filter(|c| c.instance == instance.name)
            .collect();
        if !own.is_empty() {
            let _ = writeln!(x, "        <ssd:Connectors>");
            for c in own {
                let _ = writeln!(
                    x,
                    r#"          <ssd:Connector name="{}" kind="{}"><ssc:{}/>{}</ssd:Connector>"#,
                    esc(&c.name),
                    c.kind,
                    c.type_name,
                    dimensions(&c.dimensions)
                );
            }
            let _ = writeln!(x, "        </ssd:Connectors>");
        }
        if !parameters.is_empty() {
            let _ = writeln!(x, "        <ssd:ParameterBindings>");
            let _ = writeln!(x, "          <ssd:ParameterBinding>");
            let _ = writeln!(x, "            <ssd:ParameterValues>");
            let _ = writeln!(
                x,
                r#"              <ssv:ParameterSet version="{version}" name="{PARAMETER_SET}">"#
            );
            let _ = writeln!(x, "                <ssv:Parameters>");
            for p in parameters {
                let _ = writeln!(
                    x,
                    r#"                  <ssv:Parameter name="{}"><ssv:{} value="{}"/>{}</ssv:Parameter>"#,
                    esc(&p.name),
                    p.type_name,
                    esc(&p.value),
                    dimensions(&p.dimensions)
                );
            }
            let _ = writeln!(x, "                </ssv:Parameters>");
            let _ = writeln!(x, "              </ssv:ParameterSet>");
            let _ = writeln!(x, "            </ssd:ParameterValues>");
            let _ = writeln!(x, "          </ssd:ParameterBinding>");
            let _ = writeln!(x, "        </ssd:ParameterBindings>");
        }
        let _ = writeln!(x, "      </ssd:Component>");
    }
    let _ = writeln!(x, "    </ssd:Elements>");
    if !body.connections.is_empty() {
        let _ = writeln!(x, "    <ssd:Connections>");
        for (from, to) in &body.connections {
            let (Some((se, sc)), Some((ee, ec))) = (super::split_path(from), super::split_path(to))
            else {
                continue;
            };
            let _ = writeln!(
                x,
                r#"      <ssd:Connection startElement="{}" startConnector="{}" endElement="{}" endConnector="{}"/>"#,
                esc(se),
                esc(sc),
                esc(ee),
                esc(ec)
            );
        }
        let _ = writeln!(x, "    </ssd:Connections>");
    }
    let _ = writeln!(x, "    <ssd:Annotations>");
    let _ = writeln!(
        x,
        r#"      <ssc:Annotation type="{OMS_ANNOTATION_TYPE}"><oms:Annotations><oms:SimulationInformation><oms:FixedStepMaster description="oms-ma" stepSize="{:?}"/></oms:SimulationInformation></oms:Annotations></ssc:Annotation>"#,
        system.step_size
    );
    let _ = writeln!(x, "    </ssd:Annotations>");
    let _ = writeln!(x, "  </ssd:System>");
    let ordering = match system.ordering {
        Ordering::GaussSeidel => "gauss-seidel",
        Ordering::Jacobi => "jacobi",
    };
    let _ = writeln!(
        x,
        r#"  <ssd:DefaultExperiment startTime="{:?}" stopTime="{:?}">"#,
        system.start_time, system.stop_time
    );
    let _ = writeln!(x, "    <ssd:Annotations>");
    let _ = writeln!(
        x,
        r#"      <ssc:Annotation type="{ANNOTATION_TYPE}"><Master stepSize="{:?}" ordering="{ordering}"/></ssc:Annotation>"#,
        system.step_size
    );
    let _ = writeln!(x, "    </ssd:Annotations>");
    let _ = writeln!(x, "  </ssd:DefaultExperiment>");
    let _ = writeln!(x, "</ssd:SystemStructureDescription>");
    x
}

fn esc(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for ch in s.chars() {
        match ch {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c => out.push(c),
        }
    }
    out
}
