//! Records the commit the report (and so the harness) is built from, for the pages it writes
//! (`LANDER_COMMIT`: the full hash, or `unknown` outside a git checkout or without git).
use std::process::Command;

fn main() {
    let commit = Command::new("git")
        .args(["rev-parse", "HEAD"])
        .output()
        .ok()
        .filter(|o| o.status.success())
        .and_then(|o| String::from_utf8(o.stdout).ok())
        .map(|s| s.trim().to_owned())
        .filter(|s| s.len() == 40 && s.bytes().all(|b| b.is_ascii_hexdigit()))
        .unwrap_or_else(|| "unknown".to_owned());
    println!("cargo:rustc-env=LANDER_COMMIT={commit}");
    // A new commit (HEAD moving, or the branch it names) changes the recorded hash. Only
    // files that exist are watched: cargo reruns a build script for a missing one every time.
    let git = |arg: &str| {
        Command::new("git")
            .args(["rev-parse", arg])
            .output()
            .ok()
            .filter(|o| o.status.success())
            .and_then(|o| String::from_utf8(o.stdout).ok())
            .map(|s| std::path::PathBuf::from(s.trim()))
    };
    if let (Some(dir), Some(common)) = (git("--absolute-git-dir"), git("--git-common-dir")) {
        let common = if common.is_absolute() {
            common
        } else {
            std::env::current_dir()
                .map(|d| d.join(&common))
                .unwrap_or(common)
        };
        let head = dir.join("HEAD");
        let mut watched = vec![head.clone(), common.join("packed-refs")];
        if let Ok(text) = std::fs::read_to_string(&head) {
            if let Some(reference) = text.trim().strip_prefix("ref: ") {
                watched.push(dir.join(reference));
                watched.push(common.join(reference));
            }
        }
        for path in watched.into_iter().filter(|p| p.is_file()) {
            println!("cargo:rerun-if-changed={}", path.display());
        }
    }
    println!("cargo:rerun-if-changed=build.rs");
}
