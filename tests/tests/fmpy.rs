//! The Python checks of tests/python, run against the packaged FMUs with the interpreter of
//! the workspace venv (created with pinned versions by `cargo xtask python-env`, which
//! `cargo xtask test` runs first).
use std::path::PathBuf;
use std::process::Command;
use system_tests::{
    fmi3_fmu_path, fmi3_fmus, fmu_path, model_exchange_fmus, shipped_fmus, workspace_root, Fmi,
};

/// Every script in tests/python, each run by one test below.
const SCRIPTS: [&str; 4] = [
    "fmpy_validate.py",
    "fmpy_simulate.py",
    "fmpy_model_exchange.py",
    "fmpy_derivatives.py",
];

fn venv_python() -> PathBuf {
    let python = workspace_root().join(".venv/bin/python");
    assert!(
        python.is_file(),
        "{} is missing: run `cargo xtask python-env` (or `cargo xtask test`, which does)",
        python.display()
    );
    python
}

/// Runs a script with the path of every shipped FMU as arguments; it must exit 0.
fn run_script(script: &str) {
    let fmus = shipped_fmus();
    run_script_on_paths(script, fmus.iter().map(|id| fmu_path(id)).collect());
}

fn run_script_on_paths(script: &str, fmus: Vec<PathBuf>) {
    let script_path = workspace_root().join("tests/python").join(script);
    let output = Command::new(venv_python())
        .arg(&script_path)
        .args(&fmus)
        .output()
        .unwrap_or_else(|e| panic!("cannot run {}: {e}", script_path.display()));
    let stdout = String::from_utf8_lossy(&output.stdout);
    println!("{stdout}");
    assert!(
        output.status.success(),
        "{script} failed ({}):\n{stdout}{}",
        output.status,
        String::from_utf8_lossy(&output.stderr)
    );
}

#[test]
fn fmpy_validate_finds_no_problem_in_any_fmu() {
    run_script("fmpy_validate.py");
}

#[test]
fn fmpy_simulate_runs_every_fmu_and_the_oscillator_matches_the_closed_form() {
    run_script("fmpy_simulate.py");
}

#[test]
fn fmpy_validate_finds_no_problem_in_the_fmi3_fmus() {
    run_script_on_paths(
        "fmpy_validate.py",
        fmi3_fmus().iter().map(|id| fmi3_fmu_path(id)).collect(),
    );
}

/// FMI 2.0 and FMI 3.0: CVode through Model Exchange against the analytic free fall and
/// against the same FMU's Co-Simulation. The script's checks are the plant's physics, so it
/// names the plant; the metadata must offer ME in both versions for it.
#[test]
fn fmpy_cvode_integrates_the_model_exchange_plant_like_the_analytic_and_cs_solutions() {
    let plant = "LanderPlant";
    for version in Fmi::ALL {
        assert!(
            model_exchange_fmus(version).iter().any(|id| id == plant),
            "the metadata of {plant} does not ship {version} Model Exchange"
        );
    }
    run_script_on_paths(
        "fmpy_model_exchange.py",
        vec![fmu_path(plant), fmi3_fmu_path(plant)],
    );
}

/// FMI 2.0 and FMI 3.0 Model Exchange: fmpy's getDirectionalDerivative of the plant equals
/// central differences of its derivatives over every state and input (1e-6), FMI 3.0's
/// adjoint is the transpose, and fmpy's CVode makes no derivative call.
#[test]
fn fmpy_directional_derivatives_of_the_plant_equal_central_differences() {
    let plant = "LanderPlant";
    run_script_on_paths(
        "fmpy_derivatives.py",
        vec![fmu_path(plant), fmi3_fmu_path(plant)],
    );
}

#[test]
fn every_python_script_is_run_by_a_test() {
    let mut found: Vec<String> = std::fs::read_dir(workspace_root().join("tests/python"))
        .unwrap()
        .map(|entry| entry.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|name| name.ends_with(".py"))
        .collect();
    found.sort();
    let mut known = SCRIPTS.map(str::to_owned).to_vec();
    known.sort();
    assert_eq!(found, known, "add a test for each script in tests/python");
}
