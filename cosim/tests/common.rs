//! Test fixtures: the packaged lander FMUs of target/fmu and zip helpers (the importer's
//! tests' `files.rs`, included), and the lander's closed loop as a system.

#[path = "../../fmi-import/tests/files.rs"]
mod files;
pub use files::*;

use cosim::system::{toml_format, SystemDescription};
use std::fs;
use std::path::Path;

/// The lander's closed loop (tests/fixtures/lander_loop.toml), its FMUs named relative to
/// [`fmu_dir`].
pub fn lander_loop() -> SystemDescription {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/lander_loop.toml");
    let text = fs::read_to_string(&path).unwrap();
    toml_format::parse(&text, &path).unwrap_or_else(|e| panic!("{e}"))
}

/// Scenario events that set the plant's `engine_health`: (name, time in s, health) each.
pub fn engine_faults(faults: &[(&str, f64, f64)]) -> Vec<cosim::system::Event> {
    faults
        .iter()
        .map(|&(name, time_s, health)| cosim::system::Event {
            name: name.into(),
            time_s,
            instance: "plant".into(),
            variable: "engine_health".into(),
            value: cosim::system::ParamValue::Real(health),
        })
        .collect()
}
