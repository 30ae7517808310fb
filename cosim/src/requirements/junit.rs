//! JUnit XML, the report CI systems read: one test suite per scenario run, one test case
//! for its verdict and one per requirement. The layout is the one Jenkins and GitLab read
//! (the Ant schema, `junit-10.xsd`): `tests`, `failures` and `errors` totals on
//! `<testsuites>` and on each `<testsuite>`; a `time` on each `<testcase>`; in a test case
//! an `<error>` (it could not be run) or a `<failure>` (it ran and failed) before its
//! `<system-out>`; in a suite the test cases before its `<system-err>`.
use super::Judged;
use anyhow::Context;
use std::fmt::Write;
use std::path::Path;

/// How a test case ended.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Outcome {
    Passed,
    /// It ran and failed, with the message a CI system shows in its list.
    Failed(String),
    /// It could not be run, with the message.
    Error(String),
}

/// One test case: its name, its time, how it ended and the text shown with it.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Case {
    pub name: String,
    pub time_s: f64,
    pub outcome: Outcome,
    pub detail: String,
}

/// One suite: a scenario's run.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Suite {
    pub name: String,
    pub time_s: f64,
    pub cases: Vec<Case>,
    /// What the run wrote to its error stream (the FMUs' warnings, say), if the caller has
    /// it.
    pub system_err: Option<String>,
    /// The run's result file, by its name beside the verdicts file, when it wrote one: where
    /// a report finds the requirements' signals.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub results: Option<String>,
    /// Each requirement's formula, by the name of its case.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub formulas: Vec<NamedFormula>,
    /// The FMUs the run loaded, as their descriptions say.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub fmus: Vec<FmuFacts>,
}

#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct NamedFormula {
    pub name: String,
    pub formula: String,
}

/// What a report shows of one instance's FMU.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct FmuFacts {
    pub instance: String,
    pub fmu: String,
    pub model_name: String,
    pub fmi_version: String,
    #[serde(default)]
    pub model_version: Option<String>,
    #[serde(default)]
    pub generation_tool: Option<String>,
    #[serde(default)]
    pub generation_date: Option<String>,
}

impl Suite {
    fn failures(&self) -> usize {
        self.count(|o| matches!(o, Outcome::Failed(_)))
    }

    fn errors(&self) -> usize {
        self.count(|o| matches!(o, Outcome::Error(_)))
    }

    fn count(&self, which: impl Fn(&Outcome) -> bool) -> usize {
        self.cases.iter().filter(|c| which(&c.outcome)).count()
    }
}

/// The file beside a `harness test` folder's results that keeps its suites for
/// `harness report`, which reads them back without parsing the JUnit XML.
pub const VERDICTS_FILE: &str = "verdicts.toml";

#[derive(serde::Serialize, serde::Deserialize)]
struct Verdicts {
    suite: Vec<Suite>,
}

/// Writes `suites` as TOML to `path`.
pub fn write_verdicts(path: &Path, suites: &[Suite]) -> anyhow::Result<()> {
    let text = toml::to_string(&Verdicts {
        suite: suites.to_vec(),
    })?;
    std::fs::write(path, text).with_context(|| format!("writing {}", path.display()))
}

/// The suites [`write_verdicts`] wrote.
pub fn read_verdicts(path: &Path) -> anyhow::Result<Vec<Suite>> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    let verdicts: Verdicts =
        toml::from_str(&text).with_context(|| format!("reading {}", path.display()))?;
    Ok(verdicts.suite)
}

/// `text` as XML character data or a double-quoted attribute value. XML 1.0 allows no
/// control character but tab, line feed and carriage return, not even as a reference: the
/// others (a terminal colour code in an FMU's log) become U+FFFD, or the whole file would
/// not parse. In an attribute a line break is kept as a reference, which a parser would
/// otherwise turn into a space.
fn escape(text: &str, attribute: bool) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\n' if attribute => out.push_str("&#10;"),
            '\r' => out.push_str("&#13;"),
            '\t' | '\n' => out.push(c),
            '\u{FFFE}' | '\u{FFFF}' => out.push('\u{FFFD}'),
            c if u32::from(c) < 0x20 => out.push('\u{FFFD}'),
            c => out.push(c),
        }
    }
    out
}

/// The XML of `suites`.
pub fn render(suites: &[Suite]) -> String {
    let tests: usize = suites.iter().map(|s| s.cases.len()).sum();
    let failures: usize = suites.iter().map(Suite::failures).sum();
    let errors: usize = suites.iter().map(Suite::errors).sum();
    let time_s: f64 = suites.iter().map(|s| s.time_s).sum();
    let mut xml = String::from("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    let _ = writeln!(
        xml,
        "<testsuites name=\"harness\" tests=\"{tests}\" failures=\"{failures}\" \
         errors=\"{errors}\" time=\"{time_s:.3}\">"
    );
    for s in suites {
        let name = escape(&s.name, true);
        let _ = writeln!(
            xml,
            "  <testsuite name=\"{name}\" tests=\"{}\" failures=\"{}\" errors=\"{}\" \
             skipped=\"0\" time=\"{:.3}\">",
            s.cases.len(),
            s.failures(),
            s.errors(),
            s.time_s
        );
        for c in &s.cases {
            let _ = write!(
                xml,
                "    <testcase classname=\"{name}\" name=\"{}\" time=\"{:.3}\">",
                escape(&c.name, true),
                c.time_s
            );
            let detail = escape(&c.detail, false);
            let _ = match &c.outcome {
                Outcome::Passed => write!(xml, "<system-out>{detail}</system-out>"),
                Outcome::Failed(message) => write!(
                    xml,
                    "<failure message=\"{}\">{detail}</failure>",
                    escape(message, true)
                ),
                Outcome::Error(message) => write!(
                    xml,
                    "<error message=\"{}\">{detail}</error>",
                    escape(message, true)
                ),
            };
            xml.push_str("</testcase>\n");
        }
        if let Some(text) = &s.system_err {
            let _ = writeln!(xml, "    <system-err>{}</system-err>", escape(text, false));
        }
        xml.push_str("  </testsuite>\n");
    }
    xml.push_str("</testsuites>\n");
    xml
}

/// The suite of one run: its verdict (`passed` is `Some` when it ended as expected), which
/// takes the run's time, and its requirements, judged on the recorded rows afterwards.
pub fn suite(
    name: &str,
    time_s: f64,
    passed: Option<String>,
    verdict: &str,
    requirements: &[Judged],
) -> Suite {
    let mut cases = vec![Case {
        name: "verdict".into(),
        time_s,
        outcome: match passed {
            Some(_) => Outcome::Passed,
            None => Outcome::Failed(verdict.to_owned()),
        },
        detail: verdict.to_owned(),
    }];
    cases.extend(requirements.iter().map(|j| Case {
        name: j.name.clone(),
        time_s: 0.0,
        outcome: if j.holds() {
            Outcome::Passed
        } else {
            Outcome::Failed(j.describe())
        },
        detail: j.describe(),
    }));
    Suite {
        name: name.to_owned(),
        time_s,
        cases,
        system_err: None,
        results: None,
        formulas: requirements
            .iter()
            .map(|j| NamedFormula {
                name: j.name.clone(),
                formula: j.text.clone(),
            })
            .collect(),
        fmus: Vec::new(),
    }
}

/// The suite of a scenario that could not be run (`message` says why) after `time_s`: one
/// `run` case in error.
pub fn error_suite(name: &str, time_s: f64, message: &str) -> Suite {
    Suite {
        name: name.to_owned(),
        time_s,
        cases: vec![Case {
            name: "run".into(),
            time_s,
            outcome: Outcome::Error(message.to_owned()),
            detail: message.to_owned(),
        }],
        system_err: None,
        results: None,
        formulas: Vec::new(),
        fmus: Vec::new(),
    }
}

/// Writes the report of `suites` to `path` (its folder created).
pub fn write(path: &Path, suites: &[Suite]) -> anyhow::Result<()> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    std::fs::write(path, render(suites)).with_context(|| format!("writing {}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::super::robustness::{Robustness, Truth};
    use super::super::EarlyEnd;
    use super::*;
    use serde::Deserialize;

    /// What a CI system reads of the report.
    #[derive(Deserialize)]
    struct TestSuites {
        #[serde(rename = "@tests")]
        tests: usize,
        #[serde(rename = "@failures")]
        failures: usize,
        #[serde(rename = "@errors")]
        errors: usize,
        testsuite: Vec<TestSuite>,
    }

    #[derive(Deserialize)]
    struct TestSuite {
        #[serde(rename = "@name")]
        name: String,
        #[serde(rename = "@tests")]
        tests: usize,
        #[serde(rename = "@failures")]
        failures: usize,
        #[serde(rename = "@errors")]
        errors: usize,
        #[serde(rename = "@time")]
        time: f64,
        testcase: Vec<TestCase>,
        #[serde(rename = "system-err")]
        system_err: Option<String>,
    }

    #[derive(Deserialize)]
    struct TestCase {
        #[serde(rename = "@name")]
        name: String,
        #[serde(rename = "@time")]
        time: f64,
        failure: Option<Message>,
        error: Option<Message>,
    }

    #[derive(Deserialize)]
    struct Message {
        #[serde(rename = "@message")]
        message: String,
        #[serde(rename = "#text", default)]
        text: String,
    }

    fn judged(name: &str, truth: Truth, value: f64) -> Judged {
        Judged {
            name: name.into(),
            text: "always [0, 10] m.y < 1".into(),
            robustness: Robustness {
                value,
                at_s: 2.0,
                truth,
            },
            recorded_s: (0.0, 10.0),
            early_end: EarlyEnd::Inconclusive,
            undefined: None,
        }
    }

    #[test]
    fn the_report_counts_failures_and_errors_apart_with_times_and_the_error_stream() {
        let mut flown = suite(
            "landing",
            12.5,
            None,
            "HARD LANDING <by 3 m/s> & more",
            &[
                judged("holds", Truth::Holds, 1.0),
                judged("at its limit", Truth::Violated, 0.0),
                judged(
                    "cut short",
                    Truth::Inconclusive {
                        from_s: 0.0,
                        to_s: 20.0,
                    },
                    0.5,
                ),
            ],
        );
        flown.system_err = Some("plant: warning \u{1b}[33mslow\u{1b}[0m\nline two".into());
        let broken = error_suite("c-broken", 0.25, "could not be run: no \"system\"\nat all");
        let xml = render(&[flown, broken]);
        let report: TestSuites = serde_xml_rs::from_str(&xml).unwrap();
        assert_eq!(
            (report.tests, report.failures, report.errors),
            (5, 3, 1),
            "{xml}"
        );
        let flown = &report.testsuite[0];
        assert_eq!(
            (
                flown.name.as_str(),
                flown.tests,
                flown.failures,
                flown.errors
            ),
            ("landing", 4, 3, 0)
        );
        assert_eq!(flown.time, 12.5);
        let names: Vec<&str> = flown.testcase.iter().map(|c| c.name.as_str()).collect();
        assert_eq!(names, ["verdict", "holds", "at its limit", "cut short"]);
        assert_eq!(flown.testcase[0].time, 12.5);
        assert_eq!(
            flown.testcase[0].failure.as_ref().unwrap().message,
            "HARD LANDING <by 3 m/s> & more"
        );
        assert!(flown.testcase[1].failure.is_none() && flown.testcase[1].error.is_none());
        assert!(flown.testcase[2]
            .failure
            .as_ref()
            .is_some_and(|f| f.message.contains("exactly at its limit")));
        assert!(flown.testcase[3].failure.as_ref().is_some_and(|f| f
            .message
            .contains("INCONCLUSIVE (window [0, 20] s, run ended at 10 s")));
        assert_eq!(
            flown.system_err.as_deref(),
            Some("plant: warning \u{fffd}[33mslow\u{fffd}[0m\nline two")
        );

        let broken = &report.testsuite[1];
        assert_eq!((broken.tests, broken.failures, broken.errors), (1, 0, 1));
        assert!(broken.system_err.is_none());
        let case = &broken.testcase[0];
        assert_eq!((case.name.as_str(), case.time), ("run", 0.25));
        assert!(case.failure.is_none());
        let error = case.error.as_ref().expect("an error, not a failure");
        // The line break survives in the attribute.
        assert_eq!(error.message, "could not be run: no \"system\"\nat all");
        assert_eq!(error.text, "could not be run: no \"system\"\nat all");
    }
}
