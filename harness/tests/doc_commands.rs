//! Every harness command line the documents show names a subcommand the harness has, with
//! options that subcommand (or the harness as a whole) takes: a renamed option or a removed
//! command fails here with the document and line, not in a reader's terminal.
use crate::common;

use std::collections::{BTreeMap, BTreeSet};
use std::process::Command;

/// The long options a `--help` text lists.
fn options(help: &str) -> BTreeSet<String> {
    help.split_whitespace()
        .filter_map(|word| {
            let option = word.strip_prefix("--")?;
            let name: String = option
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '-')
                .collect();
            (!name.is_empty()).then(|| format!("--{name}"))
        })
        .collect()
}

fn help(args: &[&str]) -> String {
    let output = Command::new(env!("CARGO_BIN_EXE_harness"))
        .args(args)
        .arg("--help")
        .output()
        .unwrap();
    assert!(output.status.success(), "harness {args:?} --help failed");
    String::from_utf8(output.stdout).unwrap()
}

/// The harness's subcommands with the options each takes (its own and the global ones).
fn interface() -> BTreeMap<String, BTreeSet<String>> {
    let top = help(&[]);
    let global = options(&top);
    let commands: Vec<String> = top
        .split("Commands:")
        .nth(1)
        .expect("a Commands: section")
        .split("Options:")
        .next()
        .unwrap()
        .lines()
        .filter_map(|line| {
            let name = line.strip_prefix("  ")?.split_whitespace().next()?;
            (!name.is_empty() && name != "help").then(|| name.to_owned())
        })
        .collect();
    commands
        .into_iter()
        .map(|command| {
            let mut taken = options(&help(&[&command]));
            taken.extend(global.iter().cloned());
            (command, taken)
        })
        .collect()
}

/// The harness command lines of a Markdown text, with their line numbers: code spans and
/// fenced lines that start with `harness ` (or `$ harness `, or `cargo run ... -p harness --`).
fn command_lines(text: &str) -> Vec<(usize, String)> {
    let mut found = Vec::new();
    let mut fenced = false;
    for (number, line) in text.lines().enumerate() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            continue;
        }
        let pieces: Vec<&str> = if fenced {
            vec![line]
        } else {
            line.split('`').skip(1).step_by(2).collect()
        };
        for piece in pieces {
            let piece = piece.trim().trim_start_matches("$ ");
            let rest = if let Some(rest) = piece.strip_prefix("harness ") {
                rest
            } else if let Some((_, rest)) = piece.split_once("-p harness -- ") {
                rest
            } else {
                continue;
            };
            found.push((number + 1, rest.split('#').next().unwrap().to_owned()));
        }
    }
    found
}

/// What is wrong with one documented command line (`rest` after `harness `), if anything.
fn problems(rest: &str, interface: &BTreeMap<String, BTreeSet<String>>) -> Vec<String> {
    let words: Vec<&str> = rest.split_whitespace().collect();
    // Global options may come before the subcommand; skip them and their values.
    let Some(command) = words.iter().find(|w| !w.starts_with('-')).copied() else {
        return Vec::new();
    };
    let Some(taken) = interface.get(command) else {
        // A word that is no subcommand: prose such as "harness is ..." or a placeholder.
        return if command.chars().all(|c| c.is_ascii_lowercase() || c == '-')
            && rest.contains(" --")
        {
            vec![format!("no subcommand `{command}`")]
        } else {
            Vec::new()
        };
    };
    words
        .iter()
        .filter(|w| w.starts_with("--") && w.len() > 2)
        .map(|w| w.split('=').next().unwrap())
        .filter(|option| !taken.contains(*option))
        .map(|option| format!("`harness {command}` takes no `{option}`"))
        .collect()
}

#[test]
fn every_documented_harness_command_and_option_exists() {
    let root = common::workspace_root();
    let interface = interface();
    assert!(interface.contains_key("run") && interface["run"].contains("--out"));
    let mut documents = vec![
        root.join("README.md"),
        root.join("ARCHITECTURE.md"),
        root.join("harness/README.md"),
    ];
    let mut docs: Vec<_> = std::fs::read_dir(root.join("docs"))
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    docs.sort();
    documents.extend(docs);
    let (mut wrong, mut checked) = (Vec::new(), 0);
    for document in documents.iter().filter(|d| d.is_file()) {
        let text = std::fs::read_to_string(document).unwrap();
        let shown = document.strip_prefix(&root).unwrap().display().to_string();
        for (line, rest) in command_lines(&text) {
            checked += 1;
            for problem in problems(&rest, &interface) {
                wrong.push(format!("{shown}:{line}: {problem}: harness {rest}"));
            }
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
    assert!(checked > 30, "only {checked} harness command lines found");
}

#[test]
fn a_renamed_option_and_a_removed_command_are_caught() {
    let interface = interface();
    assert!(problems("run paper --out x.csv", &interface).is_empty());
    assert!(problems("--in-process run paper", &interface).is_empty());
    assert_eq!(
        problems("run paper --output x.csv", &interface),
        ["`harness run` takes no `--output`"]
    );
    assert_eq!(
        problems("simulate paper --out x.csv", &interface),
        ["no subcommand `simulate`"]
    );
    let found =
        command_lines("Run `harness run paper --out a.csv` or\n```\n$ harness test dir\n```\n");
    assert_eq!(
        found,
        [
            (1, "run paper --out a.csv".to_owned()),
            (3, "test dir".to_owned())
        ]
    );
}
