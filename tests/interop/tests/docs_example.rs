//! The closed-loop examples users are pointed to (docs/examples/closed_loop.py in FMI 2.0 and
//! closed_loop_fmi3.py in FMI 3.0 with Event Mode, fmpy, written from docs/interface.md) fly
//! the paper scenario bit for bit as `harness run paper` does.
use cosim::master::Conventions;
use interop_tests::{fmu_dir, python, read_trajectory, run_harness, scenario, scratch};
use std::process::Command;

#[test]
fn the_documented_fmpy_loop_equals_the_harness_paper_run_bit_for_bit() {
    the_example_equals_the_harness_paper_run("closed_loop.py", &fmu_dir());
}

#[test]
fn the_documented_fmi3_fmpy_loop_equals_the_harness_paper_run_bit_for_bit() {
    the_example_equals_the_harness_paper_run("closed_loop_fmi3.py", &fmu_dir().join("fmi3"));
}

fn the_example_equals_the_harness_paper_run(script: &str, fmus: &std::path::Path) {
    // GIVEN the example run as a user would, on the packaged FMUs
    let dir = scratch("docs-example-");
    let csv = dir.path().join("closed_loop.csv");
    let example = interop_tests::workspace_root()
        .join("docs/examples")
        .join(script);
    let output = Command::new(python::venv_python())
        .arg(&example)
        .arg(fmus.join("LanderGnc.fmu"))
        .arg(fmus.join("LanderPlant.fmu"))
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
    // AND every column it records equals the harness's paper run (FMI 2.0), row for row
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

/// docs/examples/own_vehicle.py on `gnc` with `mistake` and `extra` options: the lines
/// LanderGnc logged.
fn own_vehicle(gnc: &std::path::Path, mistake: &str, seconds: f64, extra: &[&str]) -> Vec<String> {
    let example = interop_tests::workspace_root().join("docs/examples/own_vehicle.py");
    let output = Command::new(python::venv_python())
        .arg(&example)
        .arg(gnc)
        .args(["--mistake", mistake, "--seconds", &seconds.to_string()])
        .args(extra)
        .output()
        .expect("cannot run the example");
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&output.stderr)
    );
    stdout
        .lines()
        .filter(|line| line.starts_with("gnc ["))
        .map(str::to_owned)
        .collect()
}

/// The time a message says it was raised at (`"fmi2DoStep: t = 1 s: ..."`).
fn raised_at(message: &str) -> f64 {
    let after = message.split("t = ").nth(1).expect("a time");
    after.split(' ').next().unwrap().parse().expect("a number")
}

/// The example's rigid body (its own physics, thrust along its body +z, wired through the
/// constant rotation of docs/interface.md) with each wiring mistake a user makes: LanderGnc
/// names it, as a warning, within 2 s of simulated time, and logs no message twice; wired
/// right, it logs nothing over 40 s, nor with products of inertia of 300 kg m2 that the GNC,
/// given the tensor's diagonal, does not know of (docs/interface.md).
fn own_vehicle_mistakes_are_named(gnc: &std::path::Path) {
    let correct = own_vehicle(gnc, "none", 40.0, &[]);
    assert!(correct.is_empty(), "{correct:#?}");
    let products = own_vehicle(gnc, "none", 40.0, &["--products", "300"]);
    assert!(products.is_empty(), "{products:#?}");
    for (mistake, says) in [
        ("scalar-last", "the quaternion looks scalar-last"),
        ("conjugate", "the quaternion looks like its conjugate"),
        ("deg-per-s", "body rates look like deg/s"),
        ("enu", "position and velocity look like ENU"),
        (
            "earth-gravity",
            "implies gravity 1.620 m/s2, not gravity = 9.81",
        ),
        ("inertia-1000x", "the plant's inertia looks"),
        ("thrust-max-default", "is above thrust_max = 1600 N"),
    ] {
        let messages = own_vehicle(gnc, mistake, 3.0, &[]);
        let found = messages
            .iter()
            .find(|m| m.contains(says))
            .unwrap_or_else(|| panic!("{mistake}: nothing says {says:?}: {messages:#?}"));
        assert!(found.starts_with("gnc [WARNING]"), "{found}");
        assert!(raised_at(found) <= 2.0, "{mistake}: {found}");
        let mut unique = messages.clone();
        unique.sort();
        unique.dedup();
        assert_eq!(unique.len(), messages.len(), "{messages:#?}");
    }
}

#[test]
fn own_vehicle_example_fmi2_names_each_wiring_mistake() {
    own_vehicle_mistakes_are_named(&fmu_dir().join("LanderGnc.fmu"));
}

#[test]
fn own_vehicle_example_fmi3_names_each_wiring_mistake() {
    own_vehicle_mistakes_are_named(&fmu_dir().join("fmi3/LanderGnc.fmu"));
}
