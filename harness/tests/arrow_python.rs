//! An Arrow IPC result file is what Python users get: the paper scenario run through the
//! CLI twice, to CSV and to .arrow, then read by pandas, polars and pyarrow (the venv of
//! `cargo xtask python-env`), which must find the CSV's values bit for bit; and read back
//! here, equal to the CSV bit for bit.
use crate::common;

use cosim::results::{read_arrow, read_csv};
use std::path::Path;
use std::process::Command;

fn run_paper(out: &Path, extra: &[&str]) {
    let output = Command::new(env!("CARGO_BIN_EXE_harness"))
        .arg("--fmu-dir")
        .arg(common::fmu_dir())
        .args(["run", "paper", "--out"])
        .arg(out)
        .args(extra)
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "harness run failed: {}",
        String::from_utf8_lossy(&output.stderr)
    );
}

fn bits(values: &[f64]) -> Vec<u64> {
    values.iter().map(|x| x.to_bits()).collect()
}

#[test]
fn the_paper_run_as_arrow_equals_its_csv_in_rust_pandas_polars_and_pyarrow() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("paper.csv");
    let arrow = dir.path().join("paper.arrow");
    // By extension, and by --format with a name that says nothing.
    let forced = dir.path().join("paper.bin");
    run_paper(&csv, &[]);
    run_paper(&arrow, &[]);
    run_paper(&forced, &["--format", "arrow"]);
    assert_eq!(
        std::fs::read(&arrow).unwrap(),
        std::fs::read(&forced).unwrap(),
        "--format arrow and the .arrow extension wrote different files"
    );
    assert!(
        std::fs::read(&arrow).unwrap().starts_with(b"ARROW1"),
        "not an Arrow IPC file"
    );

    let from_csv = read_csv(&csv).unwrap();
    let from_arrow = read_arrow(&arrow).unwrap();
    assert_eq!(from_arrow.names, from_csv.names);
    assert_eq!(from_arrow.len(), 17_201);
    assert_eq!(bits(&from_arrow.times), bits(&from_csv.times));
    assert_eq!(bits(&from_arrow.values), bits(&from_csv.values));

    let python = common::workspace_root().join(".venv/bin/python");
    assert!(
        python.is_file(),
        "{} is missing: run `cargo xtask python-env` (or `cargo xtask test`, which does)",
        python.display()
    );
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/python/read_results.py");
    let output = Command::new(python)
        .arg(script)
        .arg(&csv)
        .arg(&arrow)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "read_results.py failed:\n{stdout}\n{}",
        String::from_utf8_lossy(&output.stderr)
    );
    for reader in ["pandas", "polars", "pyarrow"] {
        assert!(
            stdout.contains(reader),
            "{reader} did not report:\n{stdout}"
        );
    }
}
