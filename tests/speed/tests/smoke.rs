//! The bench binary in its quick mode (a 5 s flight, one pass, 4 Monte Carlo runs), so the
//! measurement code stays working between real runs. It needs what `cargo xtask test`
//! prepares first: the packaged FMUs and the Python venv.
use std::process::Command;

/// Rows of the printed table by id: the cells after the id.
fn rows(table: &str) -> Vec<(String, Vec<String>)> {
    table
        .lines()
        .filter(|line| line.starts_with("| ") && !line.starts_with("| #") && !line.contains("---"))
        .map(|line| {
            let cells: Vec<String> = line
                .trim_matches('|')
                .split(" | ")
                .map(|cell| cell.trim().to_owned())
                .collect();
            (cells[0].clone(), cells[1..].to_vec())
        })
        .collect()
}

/// The number at the start of a cell such as "1.23 µs" or "250x".
fn leading_number(cell: &str) -> f64 {
    let digits: String = cell
        .chars()
        .take_while(|c| c.is_ascii_digit() || *c == '.')
        .collect();
    digits
        .parse()
        .unwrap_or_else(|_| panic!("no number at the start of {cell:?}"))
}

#[test]
fn quick_run_prints_every_row_with_a_positive_median() {
    // GIVEN the packaged FMUs
    let fmu_dir = interop_tests::fmu_dir();
    // WHEN the bench runs in quick mode
    let output = Command::new(env!("CARGO_BIN_EXE_speed-bench"))
        .arg("--quick")
        .arg("--fmu-dir")
        .arg(&fmu_dir)
        .output()
        .expect("cannot start speed-bench");
    let stdout = String::from_utf8_lossy(&output.stdout);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        output.status.success(),
        "speed-bench --quick failed ({}):\n{stdout}\n{stderr}",
        output.status
    );
    println!("{stdout}");

    // THEN every measurement has its row, in order, with a positive, finite median
    let rows = rows(&stdout);
    let ids: Vec<&str> = rows.iter().map(|(id, _)| id.as_str()).collect();
    assert_eq!(
        ids,
        ["1", "1b", "2", "3", "3s", "4", "4s", "5", "6", "6b", "6c"]
    );
    for (id, cells) in &rows {
        let median = leading_number(&cells[1]);
        assert!(median.is_finite() && median > 0.0, "row {id}: {cells:?}");
    }
    // AND the header says where the figures were taken
    assert!(stdout.contains("load average"), "{stdout}");
}

#[test]
fn a_missing_fmu_folder_is_refused_naming_the_command_that_makes_it() {
    let empty = tempfile::tempdir().unwrap();
    let output = Command::new(env!("CARGO_BIN_EXE_speed-bench"))
        .arg("--quick")
        .arg("--fmu-dir")
        .arg(empty.path())
        .output()
        .expect("cannot start speed-bench");
    assert!(!output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("cargo xtask fmus"), "{stderr}");
}

/// The instruction counts on a short flight: every call order of both FMI versions gets a
/// row and the run's own cross-checks (plain = read-then-step, FMI 2.0 = FMI 3.0, bit for
/// bit) pass. (A test build's plain loop is unoptimised, so the ratios mean nothing here;
/// `cargo xtask bench` runs the release build.)
#[test]
fn call_orders_count_prints_every_order_of_both_versions() {
    let fmu_dir = interop_tests::fmu_dir();
    let output = Command::new(env!("CARGO_BIN_EXE_call_orders"))
        .arg("--fmu-dir")
        .arg(&fmu_dir)
        .args(["--steps", "100", "count"])
        .output()
        .expect("cannot start call_orders");
    let stdout = String::from_utf8_lossy(&output.stdout);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        output.status.success(),
        "call_orders count failed ({}):\n{stdout}\n{stderr}",
        output.status
    );
    println!("{stdout}");
    let (orders, variants) = stdout
        .split_once("native C master")
        .unwrap_or_else(|| panic!("no C master table:\n{stdout}"));
    let rows: Vec<_> = rows(orders).into_iter().skip(1).collect(); // the header
    let versions: Vec<&str> = rows.iter().map(|(fmi, _)| fmi.as_str()).collect();
    // The C floor, the plain Rust loop, then three call orders of each version.
    assert_eq!(
        versions,
        ["none", "none", "2.0", "2.0", "2.0", "3.0", "3.0", "3.0"]
    );
    assert!(rows[0].1[0].contains("plain C"), "{stdout}");
    let ratios: Vec<f64> = rows.iter().map(|(_, c)| leading_number(&c[2])).collect();
    assert_eq!(ratios[0], 1.0);
    assert!(
        ratios.iter().all(|&r| r.is_finite() && r > 0.0),
        "{ratios:?}"
    );
    assert!(
        stdout.contains("unoptimised") == cfg!(debug_assertions),
        "{stdout}"
    );
    // The C master: 6 list variants of 3 orders of 2 versions, then the worst of each; the
    // four list orders of one call order cost the same to the instruction.
    let variant_rows: Vec<_> = self::rows(variants)
        .into_iter()
        .filter(|(fmi, _)| fmi != "FMI")
        .collect();
    assert_eq!(variant_rows.len(), 36 + 6, "{variants}");
    for order in variant_rows[..36].chunks(6) {
        let count = |row: &(String, Vec<String>)| row.1[2].clone();
        assert!(
            order[..4].iter().all(|row| count(row) == count(&order[0])),
            "{order:?}"
        );
    }
}
