//! The closed-loop example users are pointed to (docs/examples/closed_loop.py, fmpy, written
//! from docs/interface.md) flies the paper scenario bit for bit as `harness run paper` does.
use cosim::master::Conventions;
use interop_tests::{fmu_dir, python, read_trajectory, run_harness, scenario, scratch};
use std::process::Command;

#[test]
fn the_documented_fmpy_loop_equals_the_harness_paper_run_bit_for_bit() {
    // GIVEN the example run as a user would, on the packaged FMUs
    let dir = scratch("docs-example-");
    let csv = dir.path().join("closed_loop.csv");
    let example = interop_tests::workspace_root().join("docs/examples/closed_loop.py");
    let output = Command::new(python::venv_python())
        .arg(&example)
        .arg(fmu_dir().join("LanderGnc.fmu"))
        .arg(fmu_dir().join("LanderPlant.fmu"))
        .arg(&csv)
        .output()
        .expect("cannot run the example");
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&output.stderr)
    );
    // THEN it prints the hover it reaches
    assert!(
        stdout.contains("t = 172.00 s: altitude 150.000 m, 0.000 m from the vertical"),
        "{stdout}"
    );
    // AND every column it records equals the harness's paper run, row for row
    let example = read_trajectory(&csv);
    let harness = run_harness(scenario("paper"), Conventions::default());
    assert_eq!(example.times, harness.times);
    assert_eq!(example.len(), 17_201);
    for name in &example.names {
        let ours = example.column(name).unwrap();
        let reference = harness
            .column(name)
            .unwrap_or_else(|| panic!("the harness records no {name}"));
        assert!(ours == reference, "{name} differs from the harness's");
    }
    assert_eq!(example.names.len(), 18);
}
