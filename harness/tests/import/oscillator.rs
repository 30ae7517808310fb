//! An FMU that is not a lander, the export layer's Oscillator, run from a scenario file.
use crate::common::oscillator_fmu;
use tempfile::TempDir;

/// An FMU that is not a lander runs alone from a scenario file and is judged only by how
/// its run ended: exit code 0, no lander words.
#[test]
fn the_oscillator_alone_runs_from_a_scenario_and_exits_0() {
    let fmu = oscillator_fmu();
    let dir = TempDir::new().unwrap();
    let scenario = dir.path().join("oscillator.toml");
    std::fs::write(
        &scenario,
        format!(
            "name = \"oscillator\"\nstart_time = 0.0\nstop_time = 2.0\nstep_size = 0.01\n\
             [[instance]]\nname = \"osc\"\nfmu = \"{}\"\n\
             [instance.parameters]\nk = 4.0\n",
            fmu.path.display()
        ),
    )
    .unwrap();
    let out = dir.path().join("run.csv");
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_harness"))
        .arg("run")
        .arg(&scenario)
        .arg("-o")
        .arg(&out)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(0), "{stdout}{stderr}");
    assert!(
        stdout.contains("completed at t = 2.00 s (as the scenario expects)"),
        "{stdout}"
    );
    assert!(!stdout.contains("ground"), "{stdout}");
    let csv = std::fs::read_to_string(&out).unwrap();
    assert!(csv.lines().next().unwrap().contains("osc.x"), "{csv}");
    assert_eq!(csv.lines().count(), 202, "header + 201 rows");
}
