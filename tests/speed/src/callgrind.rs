//! Instruction counts from valgrind's callgrind: a child process runs one measured function
//! under `--toggle-collect`, so start-up, loading and instantiation are not counted, and the
//! output file gives the total and the number of calls of every function.
use anyhow::{bail, ensure, Context, Result};
use std::collections::HashMap;
use std::path::Path;
use std::process::Command;

/// What callgrind counted while the measured function was on the stack.
#[derive(Debug, Clone, Default)]
pub struct Counts {
    /// Instructions executed (event Ir).
    pub instructions: u64,
    /// Calls per function name (demangled, as callgrind writes them).
    pub calls: HashMap<String, u64>,
}

impl Counts {
    /// Calls of every function whose name contains `needle`.
    pub fn calls_of(&self, needle: &str) -> u64 {
        self.calls
            .iter()
            .filter(|(name, _)| name.contains(needle))
            .map(|(_, n)| n)
            .sum()
    }
}

/// Whether valgrind can be run.
pub fn available() -> bool {
    Command::new("valgrind")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success())
}

/// Runs `program args` under callgrind, counting only inside functions matching `collect`
/// (a callgrind pattern such as `*measured_flight*`).
pub fn count(program: &Path, args: &[String], collect: &str, out_dir: &Path) -> Result<Counts> {
    count_into(program, args, collect, &out_dir.join("callgrind.out"))
}

/// [`count`], with callgrind's file written to `out_file` (kept for `callgrind_annotate`).
pub fn count_into(
    program: &Path,
    args: &[String],
    collect: &str,
    out_file: &Path,
) -> Result<Counts> {
    let output = Command::new("valgrind")
        .arg("--tool=callgrind")
        .arg(format!("--callgrind-out-file={}", out_file.display()))
        .arg(format!("--toggle-collect={collect}"))
        .arg("--collect-atstart=no")
        .arg(program)
        .args(args)
        .output()
        .context("running valgrind (Debian package valgrind)")?;
    ensure!(
        output.status.success(),
        "{} under callgrind failed: {}\n{}",
        program.display(),
        output.status,
        String::from_utf8_lossy(&output.stderr)
    );
    let text = std::fs::read_to_string(out_file)
        .with_context(|| format!("reading {}", out_file.display()))?;
    parse(&text)
}

/// Parses a callgrind output file: the `summary:`/`totals:` line and the `calls=` lines
/// under each `cfn=` (names are compressed as `(id) name` on first use, `(id)` after).
pub fn parse(text: &str) -> Result<Counts> {
    let mut counts = Counts::default();
    let mut names: HashMap<String, String> = HashMap::new();
    let mut callee: Option<String> = None;
    let mut total = None;
    for line in text.lines() {
        if let Some(rest) = line
            .strip_prefix("summary:")
            .or_else(|| line.strip_prefix("totals:"))
        {
            let first = rest.split_whitespace().next().unwrap_or("");
            total = Some(first.parse::<u64>().context("the instruction total")?);
        } else if let Some(rest) = line.strip_prefix("cfn=") {
            callee = Some(resolve(&mut names, rest));
        } else if let Some(rest) = line.strip_prefix("fn=") {
            resolve(&mut names, rest);
            callee = None;
        } else if let Some(rest) = line.strip_prefix("calls=") {
            let n: u64 = rest
                .split_whitespace()
                .next()
                .unwrap_or("")
                .parse()
                .context("a calls= line")?;
            if let Some(name) = callee.take() {
                *counts.calls.entry(name).or_default() += n;
            }
        }
    }
    match total {
        Some(t) => counts.instructions = t,
        None => bail!("no summary or totals line in the callgrind output"),
    }
    Ok(counts)
}

/// `(id) name` defines a compressed name, `(id)` uses it, a bare name is itself.
fn resolve(names: &mut HashMap<String, String>, spec: &str) -> String {
    let spec = spec.trim();
    let Some(rest) = spec.strip_prefix('(') else {
        return spec.to_string();
    };
    let Some((id, name)) = rest.split_once(')') else {
        return spec.to_string();
    };
    let name = name.trim();
    if name.is_empty() {
        names.get(id).cloned().unwrap_or_else(|| spec.to_string())
    } else {
        names.insert(id.to_string(), name.to_string());
        name.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn compressed_names_and_calls_are_summed_per_callee() {
        let text = "events: Ir\n\
            fn=(1) main\n\
            cfn=(2) lib::gnc_sample\n\
            calls=3 0x10\n\
            5 100\n\
            cfn=(3) other\n\
            calls=1 0x20\n\
            fn=(4) caller\n\
            cfn=(2)\n\
            calls=4 0x10\n\
            summary: 12345\n";
        let counts = parse(text).unwrap();
        assert_eq!(counts.instructions, 12345);
        assert_eq!(counts.calls_of("gnc_sample"), 7);
        assert_eq!(counts.calls_of("other"), 1);
        assert_eq!(counts.calls_of("absent"), 0);
    }

    #[test]
    fn a_file_without_totals_is_an_error() {
        assert!(parse("events: Ir\nfn=(1) main\n").is_err());
    }
}
