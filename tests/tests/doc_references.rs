//! What the documentation names exists: every path, crate and `cargo xtask` command that
//! README.md, ARCHITECTURE.md, docs/*.md and the crate READMEs name in code spans or links.
//! A file moved, a crate renamed or a task removed fails here, naming the document, the line
//! and the reference, instead of leaving a reader at a dead end. (The harness's commands and
//! options are checked against its own `--help` by harness/tests/doc_commands.rs.)
//!
//! CHANGELOG.md is history: it names what was, and is not read.
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use system_tests::workspace_root;

/// The documents a user or contributor reads, relative to the workspace root.
fn documents(root: &Path) -> Vec<PathBuf> {
    let mut found = vec![root.join("README.md"), root.join("ARCHITECTURE.md")];
    let mut sorted = |dir: PathBuf, keep: &dyn Fn(&Path) -> bool| {
        let Ok(entries) = std::fs::read_dir(&dir) else {
            return;
        };
        let mut paths: Vec<PathBuf> = entries.flatten().map(|e| e.path()).collect();
        paths.sort();
        found.extend(paths.into_iter().filter(|p| keep(p)));
    };
    sorted(root.join("docs"), &|p| {
        p.extension().is_some_and(|e| e == "md")
    });
    // Every crate's and test crate's README (one level and two levels down).
    for parent in [root.to_path_buf(), root.join("tests")] {
        sorted(parent, &|p| p.join("README.md").is_file());
    }
    found
        .into_iter()
        .map(|p| if p.is_dir() { p.join("README.md") } else { p })
        .collect()
}

/// The code spans (`...`) and link targets `](...)` of a Markdown text, with their line
/// numbers; fenced blocks are left out (they hold sessions, whose paths are the user's).
fn references(text: &str) -> Vec<(usize, String)> {
    let mut found = Vec::new();
    let mut fenced = false;
    for (number, line) in text.lines().enumerate() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            continue;
        }
        if fenced {
            continue;
        }
        let mut spans = line.split('`');
        spans.next();
        // Every other piece between backticks is a code span.
        while let Some(span) = spans.next() {
            found.push((number + 1, span.to_owned()));
            spans.next();
        }
        let mut rest = line;
        while let Some(at) = rest.find("](") {
            rest = &rest[at + 2..];
            if let Some(end) = rest.find(')') {
                found.push((number + 1, rest[..end].to_owned()));
                rest = &rest[end..];
            }
        }
    }
    found
}

/// `reference` read as a path of this repository (`fmu-gnc/src/lib.rs`, `docs/speed.md#x`,
/// `../README.md`, `src/loader/`), or None when it is not one: a URL, an anchor, a command,
/// a placeholder (`DIR/report.html`), a build output under `target/`, a path on the user's
/// machine.
fn as_path(reference: &str) -> Option<&str> {
    let path = reference.split('#').next()?.trim_end_matches('/');
    let is_path_text = !path.is_empty()
        && path
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "_-./*".contains(c))
        && (path.contains('/') || path.ends_with(".md") || path.ends_with(".py"));
    let outside = ["target/", ".venv/", "/", "~", "http"]
        .iter()
        .any(|p| path.starts_with(p))
        || path.contains("://");
    (is_path_text && !outside).then_some(path)
}

/// Whether `path`, named in a document in `dir`, exists: relative to the document or to the
/// workspace root, a `*` matching any one name. Ok(None) when its first component exists
/// neither beside the document nor at the root (a placeholder such as `OUT_DIR/x`).
fn resolves(path: &str, dir: &Path, root: &Path) -> Option<bool> {
    let first = path.split('/').next().unwrap_or(path);
    let bases: Vec<&Path> = [dir, root]
        .into_iter()
        .filter(|base| first == ".." || base.join(first).exists())
        .collect();
    if bases.is_empty() {
        return None;
    }
    Some(bases.iter().any(|base| exists_with_glob(&base.join(path))))
}

fn exists_with_glob(path: &Path) -> bool {
    let text = path.to_string_lossy();
    let Some(star) = text.find('*') else {
        return path.exists();
    };
    let (head, tail) = text.split_at(star);
    let (dir, prefix) = head.rsplit_once('/').unwrap_or((".", head));
    let tail = &tail[1..];
    let (suffix, rest) = tail.split_once('/').unwrap_or((tail, ""));
    let Ok(entries) = std::fs::read_dir(dir) else {
        return false;
    };
    entries.flatten().any(|e| {
        let name = e.file_name().to_string_lossy().into_owned();
        name.starts_with(prefix)
            && name.ends_with(suffix)
            && (rest.is_empty() || exists_with_glob(&e.path().join(rest)))
    })
}

/// The workspace's package names and member directories.
fn workspace_crates(root: &Path) -> BTreeSet<String> {
    let manifest: toml::Table = std::fs::read_to_string(root.join("Cargo.toml"))
        .unwrap()
        .parse()
        .unwrap();
    let members = manifest["workspace"]["members"].as_array().unwrap();
    let mut names = BTreeSet::new();
    for member in members {
        let member = member.as_str().unwrap();
        let dirs: Vec<PathBuf> = if let Some(prefix) = member.strip_suffix('*') {
            let (parent, start) = prefix.rsplit_once('/').unwrap_or(("", prefix));
            std::fs::read_dir(root.join(parent))
                .unwrap()
                .flatten()
                .map(|e| e.path())
                .filter(|p| {
                    p.file_name()
                        .is_some_and(|n| n.to_string_lossy().starts_with(start))
                        && p.join("Cargo.toml").is_file()
                })
                .collect()
        } else {
            vec![root.join(member)]
        };
        for dir in dirs {
            names.insert(dir.file_name().unwrap().to_string_lossy().into_owned());
            let package: toml::Table = std::fs::read_to_string(dir.join("Cargo.toml"))
                .unwrap()
                .parse()
                .unwrap();
            if let Some(name) = package
                .get("package")
                .and_then(|p| p.get("name"))
                .and_then(|n| n.as_str())
            {
                names.insert(name.to_owned());
            }
        }
    }
    names
}

/// Each workspace package's integration-test targets: its `[[test]]` names and, where cargo
/// finds them itself (`autotests`, on by default), its `tests/*.rs` and `tests/*/main.rs`.
fn test_targets(root: &Path) -> BTreeMap<String, BTreeSet<String>> {
    let mut targets = BTreeMap::new();
    for member in fmu_metadata::workspace_members(root).unwrap_or_else(|e| panic!("{e}")) {
        let dir = root.join(member);
        let manifest: toml::Table = std::fs::read_to_string(dir.join("Cargo.toml"))
            .unwrap()
            .parse()
            .unwrap();
        let Some(package) = manifest.get("package") else {
            continue;
        };
        let name = package["name"].as_str().unwrap().to_owned();
        let mut names: BTreeSet<String> = manifest
            .get("test")
            .and_then(|t| t.as_array())
            .into_iter()
            .flatten()
            .filter_map(|t| t.get("name")?.as_str().map(str::to_owned))
            .collect();
        let automatic = package.get("autotests").and_then(|a| a.as_bool()) != Some(false);
        if let (true, Ok(entries)) = (automatic, std::fs::read_dir(dir.join("tests"))) {
            for path in entries.flatten().map(|e| e.path()) {
                if path.extension().is_some_and(|e| e == "rs") || path.join("main.rs").is_file() {
                    names.insert(path.file_stem().unwrap().to_string_lossy().into_owned());
                }
            }
        }
        targets.insert(name, names);
    }
    targets
}

/// What is wrong with a `cargo test -p PACKAGE --test TARGET ...` line, if anything.
fn test_command_problems(
    command: &str,
    targets: &BTreeMap<String, BTreeSet<String>>,
) -> Vec<String> {
    let words: Vec<&str> = command.split_whitespace().collect();
    let after = |flag: &str| -> Vec<&str> {
        words
            .windows(2)
            .filter(|w| w[0] == flag)
            .map(|w| w[1])
            .collect()
    };
    let mut problems = Vec::new();
    for package in after("-p") {
        let Some(known) = targets.get(package) else {
            problems.push(format!("no package `{package}`"));
            continue;
        };
        for target in after("--test") {
            if !known.contains(target) {
                problems.push(format!("`{package}` has no test target `{target}`"));
            }
        }
    }
    problems
}

/// Crates and tools from outside the workspace that the documents name.
const FOREIGN: &[&str] = &[
    "cargo-fuzz",
    "cargo-web",
    "fmi-sys",
    "rust-web-src",
    "rustc-web",
    "serde-xml-rs",
    "fmi-rs",
    "rust-fmi",
    "fmi-standard",
    "gcc-mingw-w64-x86-64",
    "gcc-aarch64-linux-gnu",
    "qemu-user",
    "qemu-user-static",
    "libc6-dev-arm64-cross",
    "x86_64-pc-windows-gnu",
    "aarch64-unknown-linux-gnu",
    "x86_64-unknown-linux-gnu",
    "line-tables-only",
];

/// A code span that names a crate the way the workspace's do (`fmi-import`, `fmu-gnc`):
/// lowercase words joined by hyphens, one of them an FMI or project word.
fn looks_like_a_crate(span: &str) -> bool {
    let words: Vec<&str> = span.split('-').collect();
    words.len() >= 2
        && words.iter().all(|w| {
            !w.is_empty()
                && w.chars()
                    .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit())
        })
        && words.iter().any(|w| {
            [
                "fmi", "fmi2", "fmi3", "fmu", "cosim", "ode", "lander", "model", "tests",
            ]
            .contains(w)
        })
}

/// A shipped scenario's name (`landing-model-exchange`), which reads like a crate's.
fn is_scenario(name: &str, root: &Path) -> bool {
    exists_with_glob(&root.join(format!("*/scenarios/{name}.toml")))
}

/// `cargo xtask` subcommands: the variants of xtask's `enum Command`, as clap names them.
fn xtask_commands(root: &Path) -> BTreeSet<String> {
    let source = std::fs::read_to_string(root.join("xtask/src/main.rs")).unwrap();
    let body = source
        .split("enum Command {")
        .nth(1)
        .expect("xtask's enum Command")
        .split("\n}")
        .next()
        .unwrap();
    body.lines()
        .filter_map(|line| {
            let name = line.strip_prefix("    ")?;
            let first = name.chars().next()?;
            if !first.is_ascii_uppercase() {
                return None;
            }
            let ident: String = name
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric())
                .collect();
            let mut kebab = String::new();
            for (k, c) in ident.chars().enumerate() {
                if c.is_ascii_uppercase() && k > 0 {
                    kebab.push('-');
                }
                kebab.push(c.to_ascii_lowercase());
            }
            Some(kebab)
        })
        .collect()
}

#[test]
fn every_path_crate_and_task_the_documents_name_exists() {
    let root = workspace_root();
    let crates = workspace_crates(&root);
    let tasks = xtask_commands(&root);
    let targets = test_targets(&root);
    assert!(
        tasks.contains("fmus") && tasks.contains("test"),
        "{tasks:?}"
    );
    let mut dead = Vec::new();
    let mut checked = 0;
    for document in documents(&root) {
        let text = std::fs::read_to_string(&document).unwrap();
        let dir = document.parent().unwrap();
        let shown = document.strip_prefix(&root).unwrap().display().to_string();
        for (line, reference) in references(&text) {
            if let Some(path) = as_path(&reference) {
                match resolves(path, dir, &root) {
                    Some(true) => checked += 1,
                    Some(false) => dead.push(format!("{shown}:{line}: no such path `{path}`")),
                    None => {}
                }
            } else if looks_like_a_crate(&reference) && !is_scenario(&reference, &root) {
                checked += 1;
                if !crates.contains(&reference) && !FOREIGN.contains(&reference.as_str()) {
                    dead.push(format!("{shown}:{line}: no crate `{reference}`"));
                }
            }
            for command in reference.split("cargo test ").skip(1) {
                checked += 1;
                for problem in test_command_problems(command, &targets) {
                    dead.push(format!("{shown}:{line}: {problem}"));
                }
            }
            for task in reference.split("cargo xtask ").skip(1) {
                let task = task.split_whitespace().next().unwrap_or("");
                checked += 1;
                if !tasks.contains(task) {
                    dead.push(format!("{shown}:{line}: no task `cargo xtask {task}`"));
                }
            }
        }
    }
    assert!(
        dead.is_empty(),
        "{} dead references (of {checked} checked):\n{}",
        dead.len(),
        dead.join("\n")
    );
    // The documents do name many: a parser that finds none would pass vacuously.
    assert!(checked > 200, "only {checked} references found");
}

#[test]
fn a_moved_file_an_unknown_crate_and_a_removed_task_are_caught() {
    let root = workspace_root();
    let dir = tempfile::tempdir().unwrap();
    let text =
        "See `harness/src/loader/mod.rs`, the crate `fmi-loader` and `cargo xtask release`.\n\
                ```\n$ ls `not/checked`\n```\n[ok](README.md) `fmu-gnc/src/*.rs`\n";
    let found = references(text);
    let paths: Vec<_> = found.iter().filter_map(|(_, r)| as_path(r)).collect();
    assert_eq!(
        paths,
        ["harness/src/loader/mod.rs", "fmu-gnc/src/*.rs", "README.md"]
    );
    assert_eq!(resolves(paths[0], dir.path(), &root), Some(false));
    assert_eq!(resolves(paths[1], dir.path(), &root), Some(true));
    assert_eq!(resolves(paths[2], dir.path(), &root), Some(true));
    assert_eq!(resolves("OUT_DIR/x.csv", dir.path(), &root), None);
    assert!(looks_like_a_crate("fmi-loader"));
    assert!(!workspace_crates(&root).contains("fmi-loader"));
    assert!(!looks_like_a_crate("early-end") && !looks_like_a_crate("--in-process"));
    assert!(is_scenario("landing-model-exchange", &root) && !is_scenario("fmi-loader", &root));
    assert!(!xtask_commands(&root).contains("release"));
    let targets = test_targets(&root);
    assert!(test_command_problems("-p harness --test main x::", &targets).is_empty());
    assert_eq!(
        test_command_problems("-p harness --test golden_trajectory", &targets),
        ["`harness` has no test target `golden_trajectory`"]
    );
}
