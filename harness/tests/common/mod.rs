//! Test fixtures: the packaged FMUs, the Oscillator and zip helpers (the importer's tests'
//! `files.rs`, included) and the harness binary.
#![allow(dead_code)] // each test file uses a different subset

#[path = "../../../fmi-import/tests/files.rs"]
mod files;
pub use files::*;

use std::process::Command;

/// The harness binary run with these arguments on the FMU directory, with no backtrace.
pub fn harness(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_harness"))
        .arg("--fmu-dir")
        .arg(fmu_dir())
        .args(args)
        .env("RUST_BACKTRACE", "0")
        .output()
        .unwrap()
}
