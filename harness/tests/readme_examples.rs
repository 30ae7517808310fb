//! The README's example sessions, run: each `$ harness ...` line of a shell block is flown
//! and its printed lines and exit code must be the ones the README shows, so the README
//! cannot go stale.
use crate::common;

use std::process::Command;

/// The shell blocks of the README whose first line runs the harness: (command line, the
/// lines it prints, the exit code `echo $?` shows).
fn examples(readme: &str) -> Vec<(String, Vec<String>, i32)> {
    let mut found = Vec::new();
    let mut lines = readme.lines();
    while let Some(line) = lines.next() {
        // Any fence opens a block (with or without a language); only a bare one closes it.
        if !line.trim_start().starts_with("```") {
            continue;
        }
        let block: Vec<&str> = lines.by_ref().take_while(|l| l.trim() != "```").collect();
        let Some(command) = block.first().and_then(|l| l.strip_prefix("$ harness ")) else {
            continue;
        };
        let Some(echo) = block.iter().position(|l| *l == "$ echo $?") else {
            continue;
        };
        let printed = block[1..echo].iter().map(|l| l.to_string()).collect();
        let code = block[echo + 1]
            .trim()
            .parse()
            .expect("an exit code after echo $?");
        found.push((command.to_string(), printed, code));
    }
    found
}

#[test]
fn every_harness_session_in_the_readme_prints_what_it_shows() {
    let root = common::workspace_root();
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let sessions = examples(&readme);
    assert!(
        !sessions.is_empty(),
        "no harness session found in the README"
    );
    let dir = tempfile::tempdir().unwrap();
    for (command, printed, code) in sessions {
        // The README's default output path, redirected into a scratch folder.
        let out = dir.path().join("run.csv");
        let output = Command::new(env!("CARGO_BIN_EXE_harness"))
            .current_dir(&root)
            .args(command.split_whitespace())
            .arg("-o")
            .arg(&out)
            .env("RUST_BACKTRACE", "0")
            .output()
            .unwrap();
        let stdout = String::from_utf8_lossy(&output.stdout)
            .replace(&out.display().to_string(), "target/harness/run.csv");
        let got: Vec<&str> = stdout.lines().collect();
        assert_eq!(got, printed, "`harness {command}`");
        assert_eq!(output.status.code(), Some(code), "`harness {command}`");
    }
}
