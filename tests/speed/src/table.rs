//! The markdown table the run prints, and the machine it ran on.
// std's transcendental functions make the table's number formatting here, outside any FMU (the
// workspace clippy.toml forbids them for the FMUs' sake).
#![allow(clippy::disallowed_methods)]
use crate::stats::Summary;

/// One measured figure.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    pub id: &'static str,
    /// What ran, in a few words.
    pub what: String,
    /// Median with its unit.
    pub median: String,
    /// p10 - p90 with its unit, or a dash for a single sample.
    pub spread: String,
    /// What a sample is and how many there were.
    pub samples: String,
    /// Derived figures and the checks that make the figure mean what it says.
    pub notes: String,
}

impl Row {
    /// A row whose figures are `summary` multiplied by `scale`, printed in `unit`.
    pub fn timed(
        id: &'static str,
        what: impl Into<String>,
        summary: Summary,
        scale: f64,
        unit: &str,
        samples: impl Into<String>,
        notes: impl Into<String>,
    ) -> Self {
        let s = summary.scaled(scale);
        Self {
            id,
            what: what.into(),
            median: format!("{} {unit}", figure(s.median)),
            spread: if s.count > 1 {
                format!("{} – {} {unit}", figure(s.p10), figure(s.p90))
            } else {
                "–".into()
            },
            samples: samples.into(),
            notes: notes.into(),
        }
    }
}

const HEADER: [&str; 6] = [
    "#",
    "Measured",
    "Median",
    "Spread (p10 – p90)",
    "Samples",
    "Notes",
];

/// A GitHub-flavoured markdown table of `rows`.
pub fn markdown(rows: &[Row]) -> String {
    let mut out = String::new();
    let mut line = |cells: &[&str]| {
        out.push('|');
        for cell in cells {
            out.push(' ');
            out.push_str(&cell.replace('|', "\\|"));
            out.push_str(" |");
        }
        out.push('\n');
    };
    line(&HEADER);
    line(&["---"; HEADER.len()]);
    for row in rows {
        line(&[
            row.id,
            &row.what,
            &row.median,
            &row.spread,
            &row.samples,
            &row.notes,
        ]);
    }
    out
}

/// Three significant figures at most: 1234 -> "1234", 12.34 -> "12.3", 1.234 -> "1.23",
/// 0.01234 -> "0.0123"; below 0.001 in exponent form, 0.0001234 -> "1.23e-4".
pub fn figure(x: f64) -> String {
    if !x.is_finite() {
        return format!("{x}");
    }
    let magnitude = x.abs();
    if magnitude >= 100.0 || magnitude == 0.0 {
        format!("{x:.0}")
    } else if magnitude < 1e-3 {
        format!("{x:.2e}")
    } else {
        let decimals = 2 - magnitude.log10().floor() as i32;
        format!("{x:.*}", decimals as usize)
    }
}

/// Where the figures were taken: a shared machine's load changes them, so it is printed
/// with them.
#[derive(Debug, Clone)]
pub struct Machine {
    pub cpu: String,
    pub cores: usize,
}

impl Machine {
    pub fn describe() -> Self {
        let cpu = std::fs::read_to_string("/proc/cpuinfo")
            .ok()
            .and_then(|info| {
                info.lines()
                    .find(|l| l.starts_with("model name"))
                    .and_then(|l| l.split_once(':'))
                    .map(|(_, name)| name.trim().to_owned())
            })
            .unwrap_or_else(|| "unknown CPU".into());
        let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
        Self { cpu, cores }
    }
}

/// "1 flight", "3 flights".
pub fn count(n: usize, noun: &str) -> String {
    if n == 1 {
        format!("1 {noun}")
    } else {
        format!("{n} {noun}s")
    }
}

/// The 1, 5 and 15 minute load averages, as the kernel reports them.
pub fn load_average() -> Option<String> {
    let text = std::fs::read_to_string("/proc/loadavg").ok()?;
    let fields: Vec<&str> = text.split_whitespace().take(3).collect();
    (fields.len() == 3).then(|| fields.join(" / "))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn figures_keep_three_significant_digits() {
        assert_eq!(figure(1234.4), "1234");
        assert_eq!(figure(123.4), "123");
        assert_eq!(figure(12.34), "12.3");
        assert_eq!(figure(1.234), "1.23");
        assert_eq!(figure(0.01234), "0.0123");
        assert_eq!(figure(0.0001234), "1.23e-4");
        assert_eq!(figure(1.15e-10), "1.15e-10");
        assert_eq!(figure(0.0), "0");
        assert_eq!(figure(f64::NAN), "NaN");
    }

    #[test]
    fn counts_are_singular_for_one_only() {
        assert_eq!(count(1, "flight"), "1 flight");
        assert_eq!(count(0, "flight"), "0 flights");
        assert_eq!(count(20, "flight"), "20 flights");
    }

    #[test]
    fn a_timed_row_scales_into_its_unit_and_shows_the_spread() {
        let summary = Summary::of(&[1e-6, 2e-6, 3e-6]).unwrap();
        let row = Row::timed("1", "step", summary, 1e6, "µs", "3", "");
        assert_eq!(row.median, "2.00 µs");
        assert_eq!(row.spread, "1.20 – 2.80 µs");
    }

    #[test]
    fn a_single_sample_has_no_spread() {
        let row = Row::timed(
            "4",
            "campaign",
            Summary::of(&[12.5]).unwrap(),
            1.0,
            "s",
            "1",
            "",
        );
        assert_eq!(row.median, "12.5 s");
        assert_eq!(row.spread, "–");
    }

    #[test]
    fn markdown_has_a_header_a_rule_and_one_line_per_row_with_pipes_escaped() {
        let row = Row {
            id: "2",
            what: "a | b".into(),
            median: "1 s".into(),
            spread: "–".into(),
            samples: "1".into(),
            notes: String::new(),
        };
        let table = markdown(&[row.clone(), row]);
        let lines: Vec<&str> = table.lines().collect();
        assert_eq!(lines.len(), 4);
        assert!(lines[1].starts_with("| --- | --- |"));
        // 6 cells: 7 unescaped pipes per line.
        for line in &lines {
            let unescaped = line.replace("\\|", "");
            assert_eq!(unescaped.matches('|').count(), 7, "{line}");
        }
        assert!(lines[2].contains("a \\| b"));
    }
}
