//! Generated files kept under version control (e.g. `modelDescription.xml`) must match what
//! the code generates now.
use std::path::Path;

/// Panics unless the file at `path` holds exactly `generated`, telling how to regenerate it.
pub fn assert_file_matches(path: impl AsRef<Path>, generated: &str, regenerate: &str) {
    let path = path.as_ref();
    let checked_in = std::fs::read_to_string(path).unwrap_or_else(|e| {
        panic!(
            "cannot read {}: {e}; generate it with `{regenerate}`",
            path.display()
        )
    });
    if checked_in != generated {
        let line = checked_in
            .lines()
            .zip(generated.lines())
            .position(|(a, b)| a != b)
            .unwrap_or_else(|| checked_in.lines().count().min(generated.lines().count()));
        panic!(
            "{} is stale (first difference at line {}): regenerate with `{regenerate}`",
            path.display(),
            line + 1
        );
    }
}
