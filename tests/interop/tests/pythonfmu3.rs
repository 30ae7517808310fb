//! A third-party FMI 3.0 Co-Simulation FMU: a mass on a spring and a damper driven by a
//! force, written in Python (tests/interop/python/spring_damper3/SpringDamperPy3.py) and
//! packaged by pythonfmu3 when the test runs; two instances of it, the second driven by the
//! force the first passes on, flown in the harness and in fmpy (FMI 3.0,
//! tests/interop/python/fmpy3_master.py).
//!
//! The FMU exchanges a Float64 input, Float64 scalar outputs, a Float64 array output and an
//! array parameter, an Int32 output and a Boolean output.
//!
//! Model structure: pythonfmu3 (0.3.4) lists the outputs in ModelStructure without a
//! `dependencies` attribute, which in FMI 3.0 means that every output depends on every input
//! at the same instant, and it declares no `hasEventMode`. A Gauss-Seidel master must then
//! read the driven instance's outputs right after setting its input, which FMI 3.0 allows
//! only in Event Mode: fmpy3_master.py enters it, and pythonfmu3's `fmi3UpdateDiscreteStates`
//! fails (fatal: the slave has no `update_discrete_states`); the harness, seeing no Event
//! Mode, reads those outputs before setting the inputs and warns that they come one step
//! late. Every output of this FMU is a function of its state alone, so the test declares
//! `dependencies=""` on each, as the FMU's author would if pythonfmu3 let them. Both masters
//! then keep the FMU in Step Mode: outputs read after each step, inputs set before the next.
//!
//! Environment: pythonfmu3's binary calls the Python C API without linking libpython, so the
//! harness flies it in a child process (src/bin/fly_scenario.rs) started with the venv's
//! libpython preloaded and PYTHONHOME set (tests/interop/python/embedding_env.py), and
//! PYTHONPATH naming the venv's packages: pythonfmu3 imports numpy for array variables. That
//! process ends with `_exit` to step around pythonfmu3's teardown at process exit (see the
//! bin).
//!
//! Tolerance: none. The same binary in both masters, the same calls with the same values at
//! the same communication points (t_k = k h from a step counter in both), and Python's
//! arithmetic inside the FMU either way: every recorded value must be bit-identical.
// std's transcendental functions make the spring-damper's exact solution, the reference here, outside any FMU (the
// workspace clippy.toml forbids them for the FMUs' sake).
#![allow(clippy::disallowed_methods)]
use interop_tests::compare::compare;
use interop_tests::{python, read_trajectory, scratch, write_json};
use std::path::{Path, PathBuf};
use std::process::Command;

const STOP_TIME_S: f64 = 40.0;
const STEP_SIZE_S: f64 = 0.01;
/// Instance `a`: pythonfmu3 defaults (mass 2 kg, 50 N/m, 2 N s/m) and a constant force.
const A_MASS_KG: f64 = 2.0;
const A_STIFFNESS_NPM: f64 = 50.0;
const A_DAMPING_NSPM: f64 = 2.0;
const A_FORCE_N: f64 = 10.0;
/// Instance `b`, driven by `a.spring_force`, starting displaced.
const B_STIFFNESS_NPM: f64 = 80.0;
const B_X0_M: f64 = 0.05;

/// `python -m pythonfmu3 build` into `dir`, then the model structure rewritten (see the
/// module comment).
fn build_fmu(dir: &Path) -> PathBuf {
    let fmu = python::build_fmu("pythonfmu3", "spring_damper3/SpringDamperPy3.py", dir);
    declare_outputs_independent_of_inputs(&fmu);
    fmu
}

/// Rewrites the FMU's modelDescription.xml so that every `<Output>` of ModelStructure
/// depends on no input.
fn declare_outputs_independent_of_inputs(fmu: &Path) {
    python::rewrite_model_description(fmu, |text| {
        assert!(
            text.contains(r#"fmiVersion="3.0""#)
                && text.matches("<Output ").count() == 6
                && !text.contains("dependencies=")
                && !text.contains("hasEventMode"),
            "pythonfmu3's model description changed; revisit this rewrite:\n{text}"
        );
        text.replace("<Output ", r#"<Output dependencies="" "#)
    });
}

/// The scenario: `a` held at a constant force (an unconnected input set before
/// initialization), `b` driven by the force `a` passes on; Gauss-Seidel, `a` first.
fn scenario_toml(fmu: &Path) -> String {
    let fmu = fmu.to_str().expect("a UTF-8 temporary path");
    format!(
        r#"name = "spring-damper-pythonfmu3"
start_time = 0.0
stop_time = {STOP_TIME_S:?}
step_size = {STEP_SIZE_S:?}
ordering = "gauss-seidel"

[[instance]]
name = "a"
fmu = "{fmu}"
[instance.parameters]
force = {A_FORCE_N:?}

[[instance]]
name = "b"
fmu = "{fmu}"
[instance.parameters]
mass = 1.0
stiffness = {B_STIFFNESS_NPM:?}
damping = 4.0
"state0[1]" = {B_X0_M:?}

[[connection]]
from = "a.spring_force"
to = "b.force"
"#
    )
}

/// The same system for fmpy3_master.py. Its FMU paths name FMI 2.0 twins, which it maps to
/// the `fmi3` folder beside them: the FMU is built there.
fn system_json(fmi3_fmu: &Path) -> serde_json::Value {
    let twin = fmi3_fmu
        .parent()
        .and_then(Path::parent)
        .expect("the FMU is in an fmi3 folder")
        .join(fmi3_fmu.file_name().unwrap());
    serde_json::json!({
        "start_time": 0.0,
        "stop_time": STOP_TIME_S,
        "step_size": STEP_SIZE_S,
        "instances": [
            {"name": "a", "fmu": twin, "parameters": [["force", A_FORCE_N]]},
            {"name": "b", "fmu": twin, "parameters": [
                ["mass", 1.0], ["stiffness", B_STIFFNESS_NPM], ["damping", 4.0],
                ["state0[1]", B_X0_M]]},
        ],
        "connections": [["a.spring_force", "b.force"]],
    })
}

/// What the harness's process needs to host pythonfmu3's binary: embedding_env.py's
/// LD_PRELOAD and PYTHONHOME, and PYTHONPATH for the venv's packages (numpy).
fn embedding_env() -> Vec<(String, String)> {
    let mut env = python::embedding_env();
    let output = Command::new(python::venv_python())
        .args([
            "-c",
            "import numpy, os; print(os.path.dirname(os.path.dirname(numpy.__file__)))",
        ])
        .output()
        .expect("cannot run the venv's Python");
    assert!(output.status.success(), "the venv has no numpy");
    let site_packages = String::from_utf8(output.stdout).unwrap().trim().to_owned();
    env.push(("PYTHONPATH".to_owned(), site_packages));
    env
}

fn column(trajectory: &cosim::master::Trajectory, name: &str) -> Vec<f64> {
    trajectory
        .column(name)
        .unwrap_or_else(|| panic!("no column {name}"))
}

/// The closed-form response of `a` (at rest at 0 when the constant force comes on):
/// x(t) = F/k (1 - e^(-s t) (cos(w_d t) + s/w_d sin(w_d t))),
/// v(t) = F/k w^2/w_d e^(-s t) sin(w_d t), s = c/(2m), w^2 = k/m, w_d^2 = w^2 - s^2.
fn step_response(t: f64) -> (f64, f64) {
    let omega2 = A_STIFFNESS_NPM / A_MASS_KG;
    let sigma = A_DAMPING_NSPM / (2.0 * A_MASS_KG);
    let omega_d = (omega2 - sigma * sigma).sqrt();
    let x_eq = A_FORCE_N / A_STIFFNESS_NPM;
    let decay = (-sigma * t).exp();
    let (sin, cos) = (omega_d * t).sin_cos();
    (
        x_eq * (1.0 - decay * (cos + sigma / omega_d * sin)),
        x_eq * omega2 / omega_d * decay * sin,
    )
}

/// What the FMU must have computed, whoever flew it.
fn assert_physics(trajectory: &cosim::master::Trajectory, who: &str) {
    let rows = trajectory.len();
    assert_eq!(rows, 4001, "{who}: rows");
    assert!(trajectory.values.iter().all(|x| x.is_finite()), "{who}");
    let (x, v) = (column(trajectory, "a.x"), column(trajectory, "a.v"));
    // a: the step response at every communication point (each step is the exact
    // zero-order-hold solution), to rounding
    let mut worst: f64 = 0.0;
    for (k, &t) in trajectory.times.iter().enumerate() {
        let (x_exact, v_exact) = step_response(t);
        worst = worst
            .max((x[k] - x_exact).abs())
            .max((v[k] - v_exact).abs());
    }
    println!("{who}: a's step response within {worst:.2e} of the closed form");
    assert!(worst < 1e-12, "{who}: a off its step response by {worst}");
    // the array output is [x, v]; the force passed on is k x + c v
    assert_eq!(column(trajectory, "a.state[1]"), x, "{who}");
    assert_eq!(column(trajectory, "a.state[2]"), v, "{who}");
    let spring_force: Vec<f64> = x
        .iter()
        .zip(&v)
        .map(|(x, v)| A_STIFFNESS_NPM * x + A_DAMPING_NSPM * v)
        .collect();
    assert_eq!(column(trajectory, "a.spring_force"), spring_force, "{who}");
    // Int32: one per step taken; Boolean: v > 0, false at rest at t = 0, true from the
    // first step on, then flipping at every half period pi/w_d = 0.6315 s: 1 + 63 times
    let steps: Vec<f64> = (0..rows).map(|k| k as f64).collect();
    assert_eq!(column(trajectory, "a.steps"), steps, "{who}");
    assert_eq!(column(trajectory, "b.steps"), steps, "{who}");
    let moving_up = column(trajectory, "a.moving_up");
    let expected: Vec<f64> = v.iter().map(|&v| f64::from(u8::from(v > 0.0))).collect();
    assert_eq!(moving_up, expected, "{who}");
    let flips = moving_up.windows(2).filter(|w| w[0] != w[1]).count();
    assert_eq!(flips, 1 + 63, "{who}: a's direction changes");
    // b: starts where its array parameter put it, and ends at rest where the force a
    // passes on (F, once a settles) holds its spring: F / k_b = 0.125 m
    let b_x = column(trajectory, "b.x");
    assert_eq!(b_x[0], B_X0_M, "{who}: b.x at t = 0");
    assert_eq!(column(trajectory, "b.state[1]")[0], B_X0_M, "{who}");
    let b_end = b_x[rows - 1];
    println!("{who}: b ends at x = {b_end} m");
    assert!(
        (b_end - A_FORCE_N / B_STIFFNESS_NPM).abs() < 1e-8,
        "{who}: b ends at {b_end}"
    );
}

#[test]
fn a_pythonfmu3_fmi3_fmu_flies_bit_identically_in_the_harness_and_in_fmpy() {
    // GIVEN the spring-damper packaged by pythonfmu3 and a system of two instances of it
    let dir = scratch("interop-pythonfmu3-");
    let fmi3_dir = dir.path().join("fmi3");
    std::fs::create_dir(&fmi3_dir).unwrap();
    let fmu = build_fmu(&fmi3_dir);
    let scenario = dir.path().join("spring-damper.toml");
    std::fs::write(&scenario, scenario_toml(&fmu)).unwrap();

    // WHEN the harness flies it, in a process set up to host pythonfmu3's binary ...
    let harness_csv = dir.path().join("harness.csv");
    let output = Command::new(env!("CARGO_BIN_EXE_fly_scenario"))
        .arg(&scenario)
        .arg(&harness_csv)
        .envs(embedding_env())
        .output()
        .expect("cannot run fly_scenario");
    assert!(
        output.status.success(),
        "the harness could not fly the pythonfmu3 FMU ({}):\n{}{}",
        output.status,
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
    let harness = read_trajectory(&harness_csv);
    // ... and fmpy, through FMI 3.0
    let spec = write_json(&system_json(&fmu), dir.path());
    let fmpy_csv = dir.path().join("fmpy.csv");
    python::run("fmpy3_master.py", [spec.as_os_str(), fmpy_csv.as_os_str()]);
    let fmpy = read_trajectory(&fmpy_csv);

    // THEN the FMU computed the spring-damper's motion in both masters ...
    assert_physics(&harness, "harness");
    assert_physics(&fmpy, "fmpy");
    // ... and the same numbers: every output at every communication point, bit for bit
    assert_eq!(
        fmpy.names, harness.names,
        "both record every output, in order"
    );
    assert_eq!(fmpy.times, harness.times, "communication points");
    let comparison = compare(&harness, &fmpy, 0, &harness.names);
    println!("fmpy (FMI 3.0) vs harness with the pythonfmu3 FMU:\n{comparison}");
    assert!(comparison.identical(), "{comparison}");
}
