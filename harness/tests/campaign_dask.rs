//! `cargo xtask campaign-dask` with 2 Dask workers on loopback leaves the files of the same
//! `harness monte-carlo` campaign run locally, manifest.csv and summary.csv byte for byte.
use crate::common;

use std::path::Path;
use std::process::Command;

const CAMPAIGN: [&str; 7] = [
    "-n",
    "3",
    "--phi-cmd-deg",
    "0,150",
    "--seed",
    "11",
    "--no-plots",
];

fn names(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

#[test]
fn a_dask_campaign_on_two_local_workers_equals_the_local_campaign() {
    let dir = tempfile::tempdir().unwrap();
    let local = dir.path().join("local");
    let dask = dir.path().join("dask");
    let harness = env!("CARGO_BIN_EXE_harness");
    let status = Command::new(harness)
        .arg("--fmu-dir")
        .arg(common::fmu_dir())
        .arg("monte-carlo")
        .args(CAMPAIGN)
        .arg("--out-dir")
        .arg(&local)
        .arg("--quiet")
        .status()
        .unwrap();
    // 3: flown, some flights outside the paper scenario's limits.
    assert!(matches!(status.code(), Some(0 | 3)), "{status}");

    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let output = Command::new(cargo)
        .current_dir(common::workspace_root())
        .env("LANDER_FMU_DIR", common::fmu_dir())
        .args([
            "run",
            "-q",
            "-p",
            "xtask",
            "--",
            "campaign-dask",
            "--workers",
            "2",
        ])
        .arg("--harness")
        .arg(harness)
        .arg("--")
        .args(CAMPAIGN)
        .arg("--out-dir")
        .arg(&dask)
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&output.stdout).into_owned()
        + &String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), status.code(), "{text}");
    assert!(text.contains("2 shards on"), "two Dask tasks: {text}");

    assert_eq!(names(&dask), names(&local));
    for file in ["manifest.csv", "summary.csv"] {
        assert!(
            std::fs::read(dask.join(file)).unwrap() == std::fs::read(local.join(file)).unwrap(),
            "{file} differs"
        );
    }
    assert!(
        !dir.path().join("dask.dask-shards").exists(),
        "shards removed"
    );
}
