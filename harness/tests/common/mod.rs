//! Test fixtures: the packaged FMUs, the Oscillator and zip helpers (the importer's tests'
//! `files.rs`, included) and the harness binary.
#![allow(dead_code)] // each test file uses a different subset

#[path = "../../../fmi-import/tests/files.rs"]
mod files;
pub use files::*;

use std::path::{Path, PathBuf};
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

/// The Oscillator campaign example (docs/examples/oscillator-campaign.toml) as an SSD in
/// `dir`: `osc.ssd`, its FMU named by file name alone, and the sidecar `osc.campaign.toml`
/// with the example's `[campaign]` table and requirements. The SSD's path.
pub fn oscillator_campaign_ssd(dir: &Path) -> PathBuf {
    let text =
        std::fs::read_to_string(workspace_root().join("docs/examples/oscillator-campaign.toml"))
            .unwrap();
    let ssd = dir.join("osc.ssd");
    std::fs::write(
        &ssd,
        r#"<?xml version="1.0" encoding="UTF-8"?>
<ssd:SystemStructureDescription xmlns:ssd="http://ssp-standard.org/SSP1/SystemStructureDescription" version="1.0" name="osc">
  <ssd:System name="osc">
    <ssd:Elements>
      <ssd:Component name="osc" type="application/x-fmu-sharedlibrary" source="Oscillator.fmu"/>
    </ssd:Elements>
  </ssd:System>
  <ssd:DefaultExperiment startTime="0" stopTime="20"/>
</ssd:SystemStructureDescription>
"#,
    )
    .unwrap();
    std::fs::write(
        dir.join("osc.campaign.toml"),
        &text[text.find("[campaign]").unwrap()..],
    )
    .unwrap();
    ssd
}
