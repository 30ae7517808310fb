//! The numbers of the documents' prose that a command produces, each followed by a comment
//! naming it (invisible in the rendered Markdown):
//!
//! - `70.1<!-- from: harness paper full-fidelity, the row "LABEL", value 1, to 0.1 -->`: the
//!   first value of the printed row LABEL (one per law for `harness paper`: coupled,
//!   decoupled, reduced), rounded to 0.1 (without `to`: as printed);
//! - `7<!-- from: harness monte-carlo scenario=paper n=30 seed=1; summary.csv: ITEM; coupled,
//!   150 deg -->`: a campaign's cell, ITEM as a campaign block's (`results_cells.rs`), in
//!   the cell that follows (`LAW, PHI deg`), optionally `; to 0.1`.
//!
//! A Markdown comment inside a paragraph may not hold `--`, so an option is written
//! `key=value` and read as `--key value` (`-k value` for a one-letter key): `n=30 seed=1
//! set=gnc.x=0.5` is `-n 30 --seed 1 --set gnc.x=0.5`.
use super::cells::{self, Item};
use super::{campaign_results, paper_summary, row_values};

pub const OPEN: &str = "<!-- from: ";
const CLOSE: &str = " -->";

/// Where a number comes from.
#[derive(Debug, Clone, PartialEq)]
pub enum Source {
    /// Value `index` (from 0) of the printed row `label` of `command`.
    Printed {
        command: String,
        label: String,
        index: usize,
    },
    /// A campaign block's item in one cell.
    Campaign {
        command: String,
        item: Item,
        cell: String,
    },
    /// The first number minus the second (`A minus B`).
    Difference(Box<Source>, Box<Source>),
}

impl Source {
    /// The campaigns it reads: (command, item).
    pub fn campaigns(&self) -> Vec<(&str, &Item)> {
        match self {
            Source::Printed { .. } => Vec::new(),
            Source::Campaign { command, item, .. } => vec![(command.as_str(), item)],
            Source::Difference(a, b) => [a.campaigns(), b.campaigns()].concat(),
        }
    }
}

/// A number of the prose with its source: on line `line` (from 1), `number` ending where
/// the comment starts.
#[derive(Debug, Clone, PartialEq)]
pub struct Inline {
    pub line: usize,
    pub number: String,
    pub comment: String,
    pub source: Source,
    /// The rounding step (`to 0.1`).
    pub step: Option<String>,
}

/// Every number with a `from:` comment in `text`.
pub fn find(text: &str) -> Result<Vec<Inline>, String> {
    let mut found = Vec::new();
    for (index, line) in text.lines().enumerate() {
        let mut rest = line;
        let mut before = String::new();
        while let Some(at) = rest.find(OPEN) {
            before.push_str(&rest[..at]);
            let after = &rest[at + OPEN.len()..];
            let end = after
                .find(CLOSE)
                .ok_or_else(|| format!("line {}: a `from:` comment is not closed", index + 1))?;
            let comment = &after[..end];
            if comment.contains("--") {
                return Err(format!(
                    "line {}: `{comment}` holds `--`, which ends no Markdown comment: write \
                     `key=value` for `--key value`",
                    index + 1
                ));
            }
            let number: String = before
                .chars()
                .rev()
                .take_while(|c| c.is_ascii_digit() || *c == '.' || *c == '-')
                .collect::<Vec<_>>()
                .into_iter()
                .rev()
                .collect();
            // A number, or an interval `low-high`.
            if number.is_empty() || number.split('-').all(str::is_empty) {
                return Err(format!(
                    "line {}: no number before `{OPEN}{comment}{CLOSE}`",
                    index + 1
                ));
            }
            let (source, step) = parse(comment).map_err(|e| format!("line {}: {e}", index + 1))?;
            found.push(Inline {
                line: index + 1,
                number,
                comment: comment.to_owned(),
                source,
                step,
            });
            before.push_str(&rest[at..at + OPEN.len() + end + CLOSE.len()]);
            rest = &after[end + CLOSE.len()..];
        }
    }
    Ok(found)
}

/// A command of a comment with its `key=value` words as the options they stand for.
fn expand(command: &str) -> String {
    command
        .split_whitespace()
        .map(|word| match word.split_once('=') {
            Some((key, value))
                if !key.is_empty()
                    && key.chars().all(|c| c.is_ascii_alphanumeric() || c == '-') =>
            {
                let dashes = if key.len() == 1 { "-" } else { "--" };
                format!("{dashes}{key} {value}")
            }
            _ => word.to_owned(),
        })
        .collect::<Vec<_>>()
        .join(" ")
}

fn parse(comment: &str) -> Result<(Source, Option<String>), String> {
    if let Some((a, b)) = comment.split_once(" minus ") {
        let ((a, _), (b, step)) = (parse(a)?, parse(b)?);
        return Ok((Source::Difference(Box::new(a), Box::new(b)), step));
    }
    if let Some((command, spec)) = comment.split_once("; summary.csv: ") {
        let mut parts = spec.split("; ");
        let item = cells::parse_item(parts.next().unwrap_or_default())?;
        let cell = parts
            .next()
            .ok_or_else(|| format!("`{comment}`: expected `; LAW, PHI deg` after the item"))?;
        let step = parts
            .next()
            .map(|s| s.strip_prefix("to ").unwrap_or(s).to_owned());
        return Ok((
            Source::Campaign {
                command: expand(command),
                item,
                cell: cell.trim().to_owned(),
            },
            step,
        ));
    }
    let (command, rest) = comment
        .split_once(", the row \"")
        .ok_or_else(|| format!("`{comment}`: expected `COMMAND, the row \"LABEL\"`"))?;
    let (label, options) = rest
        .split_once('"')
        .ok_or_else(|| format!("`{comment}`: the label is not closed"))?;
    let (mut index, mut step) = (0, None);
    for option in options.split(", ").map(str::trim).filter(|o| !o.is_empty()) {
        if let Some(k) = option.strip_prefix("value ") {
            index = k
                .parse::<usize>()
                .ok()
                .and_then(|k| k.checked_sub(1))
                .ok_or_else(|| format!("`{comment}`: `{option}` is no value number"))?;
        } else if let Some(s) = option.strip_prefix("to ") {
            step = Some(s.to_owned());
        } else {
            return Err(format!("`{comment}`: unknown `{option}`"));
        }
    }
    if !command.starts_with("harness ") {
        return Err(format!("`{comment}`: `{command}` is no harness command"));
    }
    Ok((
        Source::Printed {
            command: expand(command),
            label: label.to_owned(),
            index,
        },
        step,
    ))
}

/// `value` rounded to the decimals of `step` (`0.1`: one, `1`: none).
fn rounded(value: &str, step: Option<&str>) -> Result<String, String> {
    let Some(step) = step else {
        return Ok(value.to_owned());
    };
    let x: f64 = value
        .trim_start_matches('+')
        .parse()
        .map_err(|_| format!("`{value}` is no number to round"))?;
    let decimals = step.split_once('.').map_or(0, |(_, d)| d.len());
    Ok(format!("{x:.decimals$}"))
}

/// The number's text now, from its command.
pub fn render(inline: &Inline) -> Result<String, String> {
    // An interval's unit follows the comment in the prose: `11.6-39.4<!-- ... --> %`.
    let text = text(&inline.source)?;
    rounded(text.trim_end_matches(" %"), inline.step.as_deref())
}

/// A source's value as its command prints it (a difference: to full precision).
fn text(source: &Source) -> Result<String, String> {
    match source {
        Source::Printed {
            command,
            label,
            index,
        } => {
            let values = row_values(&paper_summary(command), label, command);
            let value = values.get(*index).ok_or_else(|| {
                format!("`{command}` prints {} values in \"{label}\"", values.len())
            })?;
            Ok(value.clone())
        }
        Source::Campaign {
            command,
            item,
            cell,
        } => {
            let campaign = campaign_results(command);
            let (law, phi) = cells::row_cell(std::slice::from_ref(cell), &campaign.laws());
            cells::evaluate(item, &campaign, law.as_deref(), phi)
                .map_err(|e| format!("`{command}`, {cell}: {e}"))
        }
        Source::Difference(a, b) => {
            let number = |s: &Source| -> Result<f64, String> {
                let t = text(s)?;
                t.trim_start_matches('+')
                    .parse()
                    .map_err(|_| format!("`{t}` is no number to subtract"))
            };
            Ok((number(a)? - number(b)?).to_string())
        }
    }
}

/// `text` with the numbers of `inlines` replaced by `now` (in order).
pub fn replace(text: &str, inlines: &[Inline], now: &[String]) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_owned).collect();
    for (inline, new) in inlines.iter().zip(now) {
        let line = &mut lines[inline.line - 1];
        let tagged = format!("{}{OPEN}{}{CLOSE}", inline.number, inline.comment);
        *line = line.replacen(&tagged, &format!("{new}{OPEN}{}{CLOSE}", inline.comment), 1);
    }
    let mut joined = lines.join("\n");
    if text.ends_with('\n') {
        joined.push('\n');
    }
    joined
}

#[test]
fn prose_numbers_are_found_with_their_sources() {
    let text = "deviates 70.1<!-- from: harness paper full-fidelity, the row \"max horizontal \
        deviation, descent (m)\", value 1, to 0.1 --> m coupled\nlands hard in \
        7<!-- from: harness monte-carlo scenario=paper n=30 seed=1 set=gnc.x=0.5; summary.csv: \
        failed_verdicts; coupled, 150 deg --> of 30\n";
    let found = find(text).unwrap();
    assert_eq!(found.len(), 2);
    assert_eq!(found[0].number, "70.1");
    assert_eq!(
        found[0].source,
        Source::Printed {
            command: "harness paper full-fidelity".into(),
            label: "max horizontal deviation, descent (m)".into(),
            index: 0
        }
    );
    assert_eq!(found[0].step.as_deref(), Some("0.1"));
    assert_eq!((found[1].line, found[1].number.as_str()), (2, "7"));
    assert!(
        matches!(&found[1].source, Source::Campaign { command, cell, .. }
        if cell == "coupled, 150 deg"
            && command == "harness monte-carlo --scenario paper -n 30 --seed 1 --set gnc.x=0.5")
    );
    let replaced = replace(text, &found, &["70.3".into(), "6".into()]);
    assert!(replaced.starts_with("deviates 70.3<!-- from: harness paper"));
    assert!(replaced.contains("hard in 6<!-- from: harness monte-carlo"));
    assert_eq!(rounded("10.880", Some("0.1")).unwrap(), "10.9");
    assert_eq!(rounded("-5.916202e1", Some("1")).unwrap(), "-59");
    assert!(find("the<!-- from: harness paper paper, the row \"x\" -->").is_err());
    assert!(find("1<!-- from: harness paper paper, the row \"x\", at 3 -->").is_err());
    assert!(find("1<!-- from: harness paper paper --set a=1, the row \"x\" -->").is_err());
    let difference = find(
        "by 30.1<!-- from: harness paper a, the row \"x\", value 1 minus harness paper b, \
         the row \"x\", value 2, to 0.1 --> m",
    )
    .unwrap();
    assert!(matches!(&difference[0].source, Source::Difference(a, b)
        if matches!(**a, Source::Printed { index: 0, .. })
            && matches!(**b, Source::Printed { index: 1, .. })));
    assert_eq!(difference[0].step.as_deref(), Some("0.1"));
}
