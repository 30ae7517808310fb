//! JUnit XML, the report CI systems read: one test suite per scenario run, one test case
//! for its verdict and one per requirement.
use super::Judged;
use anyhow::Context;
use std::fmt::Write;
use std::path::Path;

/// One test case: its name, the failure message if it failed, and the text shown with it.
#[derive(Debug, Clone, PartialEq)]
pub struct Case {
    pub name: String,
    pub failure: Option<String>,
    pub detail: String,
}

/// One suite: a scenario's run.
#[derive(Debug, Clone, PartialEq)]
pub struct Suite {
    pub name: String,
    pub time_s: f64,
    pub cases: Vec<Case>,
}

fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// The XML of `suites`.
pub fn render(suites: &[Suite]) -> String {
    let tests: usize = suites.iter().map(|s| s.cases.len()).sum();
    let failures = |s: &Suite| s.cases.iter().filter(|c| c.failure.is_some()).count();
    let all_failures: usize = suites.iter().map(failures).sum();
    let mut xml = String::from("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    let _ = writeln!(
        xml,
        "<testsuites name=\"harness\" tests=\"{tests}\" failures=\"{all_failures}\">"
    );
    for s in suites {
        let _ = writeln!(
            xml,
            "  <testsuite name=\"{}\" tests=\"{}\" failures=\"{}\" errors=\"0\" time=\"{:.3}\">",
            escape(&s.name),
            s.cases.len(),
            failures(s),
            s.time_s
        );
        for c in &s.cases {
            let _ = write!(
                xml,
                "    <testcase classname=\"{}\" name=\"{}\"",
                escape(&s.name),
                escape(&c.name)
            );
            match &c.failure {
                None => {
                    let _ = writeln!(
                        xml,
                        "><system-out>{}</system-out></testcase>",
                        escape(&c.detail)
                    );
                }
                Some(message) => {
                    let _ = writeln!(
                        xml,
                        "><failure message=\"{}\">{}</failure></testcase>",
                        escape(message),
                        escape(&c.detail)
                    );
                }
            }
        }
        xml.push_str("  </testsuite>\n");
    }
    xml.push_str("</testsuites>\n");
    xml
}

/// The suite of one run: its verdict (`passed` is `Some` when it ended as expected) and
/// its requirements.
pub fn suite(
    name: &str,
    time_s: f64,
    passed: Option<String>,
    verdict: &str,
    requirements: &[Judged],
) -> Suite {
    let mut cases = vec![Case {
        name: "verdict".into(),
        failure: passed.is_none().then(|| verdict.to_owned()),
        detail: verdict.to_owned(),
    }];
    cases.extend(requirements.iter().map(|j| Case {
        name: j.name.clone(),
        failure: (!j.holds()).then(|| j.describe()),
        detail: j.describe(),
    }));
    Suite {
        name: name.to_owned(),
        time_s,
        cases,
    }
}

/// Writes the report of `suites` to `path` (its folder created).
pub fn write(path: &Path, suites: &[Suite]) -> anyhow::Result<()> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    std::fs::write(path, render(suites)).with_context(|| format!("writing {}", path.display()))
}
