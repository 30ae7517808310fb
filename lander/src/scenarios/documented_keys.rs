//! docs/scenarios.md documents every key the scenario reader accepts, and the reader accepts
//! every key it documents: each table's keys as serde lists them against the first column
//! of that table's section in the doc.
use crate::verdict::{Envelope, Spec};
use std::collections::BTreeSet;

/// The keys in the first column of the doc's tables, by section heading (`## ...`).
fn documented() -> Vec<(String, BTreeSet<String>)> {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../docs/scenarios.md");
    let text = std::fs::read_to_string(path).expect("docs/scenarios.md");
    let mut sections: Vec<(String, BTreeSet<String>)> = Vec::new();
    for line in text.lines() {
        if let Some(heading) = line.strip_prefix("## ") {
            sections.push((heading.trim().to_owned(), BTreeSet::new()));
            continue;
        }
        let Some(cell) = line
            .strip_prefix("| `")
            .and_then(|rest| rest.split_once("` |"))
        else {
            continue;
        };
        let bare = cell.0.trim_matches(|c| c == '[' || c == ']');
        // A key, or `[verdict.envelope]`; signal paths (`plant.touchdown`) and formulas are
        // other tables.
        let bracketed = cell.0.starts_with('[');
        let key = match bare.rsplit_once('.') {
            Some((_, last)) if bracketed => last,
            Some(_) => continue,
            None => bare,
        };
        if !key.is_empty() && key.chars().all(|c| c.is_ascii_lowercase() || c == '_') {
            if let Some((_, keys)) = sections.last_mut() {
                keys.insert(key.to_owned());
            }
        }
    }
    sections
}

fn section(sections: &[(String, BTreeSet<String>)], heading: &str) -> BTreeSet<String> {
    sections
        .iter()
        .find(|(h, _)| h == heading)
        .unwrap_or_else(|| panic!("docs/scenarios.md has no section '## {heading}'"))
        .1
        .clone()
}

fn set(keys: &[&[&str]]) -> BTreeSet<String> {
    keys.iter()
        .flat_map(|k| k.iter())
        .map(|k| k.to_string())
        .collect()
}

#[test]
fn every_key_the_reader_accepts_is_documented_and_every_documented_key_is_accepted() {
    let doc = documented();
    let read = cosim::system::toml_format::keys();
    let reader = |table: &str| read.iter().find(|(t, _)| *t == table).unwrap().1;
    let checks = [
        (
            "Top-level keys",
            set(&[reader(""), &["verdict", "requirement"]]),
        ),
        ("`[campaign]`", set(&[reader("campaign")])),
        (
            "`[[campaign.sweep]]`",
            set(&[reader("campaign.sweep"), reader("campaign.sweep.grid")]),
        ),
        (
            "`[[campaign.dispersion]]`",
            set(&[reader("campaign.dispersion")]),
        ),
        (
            "`[[campaign.correlation]]`",
            set(&[reader("campaign.correlation")]),
        ),
        ("`[[instance]]`", set(&[reader("instance")])),
        ("`[[connection]]`", set(&[reader("connection")])),
        ("`[limits]`", set(&[reader("limits")])),
        ("`[[event]]`", set(&[reader("event")])),
        (
            "`[verdict]`",
            set(&[
                cosim::system::fields::of::<Spec>(),
                cosim::system::fields::of::<Envelope>(),
            ]),
        ),
        ("`[[requirement]]`", set(&[cosim::requirements::keys()])),
    ];
    let mut problems = Vec::new();
    for (heading, accepted) in checks {
        assert!(!accepted.is_empty(), "no keys read for {heading}");
        let documented = section(&doc, heading);
        for key in accepted.difference(&documented) {
            problems.push(format!("{heading}: `{key}` is read but not documented"));
        }
        for key in documented.difference(&accepted) {
            problems.push(format!("{heading}: `{key}` is documented but refused"));
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}
