//! A third-party FMI 3.0 Co-Simulation FMU with a structural parameter and non-Float64
//! types: a counter written in Python (tests/interop/python/counter3/CounterPy3.py) and
//! packaged by pythonfmu3 when the test runs; two instances, the first with its structural
//! parameter `n` set to 3 (so its arrays `gains` and `y` have three elements, the second's
//! two), the second driven by a UInt64 and a String output of the first; flown in the
//! harness and in fmpy (FMI 3.0, tests/interop/python/fmpy3_types_master.py).
//!
//! What pythonfmu3 (0.3.4) exports, read from its source: Float64, Int32, Int64, UInt64,
//! Boolean, String and Enumeration variables, arrays with `<Dimension valueReference>`, the
//! `structuralParameter` causality and Configuration Mode (fmi3EnterConfigurationMode,
//! fmi3ExitConfigurationMode); its Float32, Int8, UInt8, Int16, UInt16, UInt32 and Binary
//! functions answer "not implemented", so those types are tested against the importer's C
//! stub instead (fmi-import/tests/fmi3_types.rs, cosim/tests/fmi3_types.rs).
//!
//! Model description: pythonfmu3 writes no `start` for a structural parameter (FMI 3.0
//! requires one for a parameter, and an array's extent cannot be known without it) and no
//! `dependencies` on the outputs (every output a function of the state alone here); the test
//! adds `start="2"` to `n` and `dependencies=""` to each output, as the FMU's author would if
//! pythonfmu3 let them. Both masters keep the FMU in Step Mode.
//!
//! Tolerance: none. The same binary in both masters, the same calls at the same
//! communication points: the two CSV files must be equal as text, which holds every Float64
//! to its last bit (shortest round-trip form in both), each Int64 and UInt64 exactly (an
//! Int64 near -2^62 and a UInt64 above 2^63, which no f64 holds) and each String.
use interop_tests::{python, scratch, write_json};
use std::path::{Path, PathBuf};
use std::process::Command;

const STOP_TIME_S: f64 = 2.0;
const STEP_SIZE_S: f64 = 0.125;

/// `python -m pythonfmu3 build` into `dir`, then the model description completed (see the
/// module comment).
fn build_fmu(dir: &Path) -> PathBuf {
    let fmu = python::build_fmu("pythonfmu3", "counter3/CounterPy3.py", dir);
    python::rewrite_model_description(&fmu, |text| {
        let structural = r#"<UInt64 name="n" valueReference="1" causality="structuralParameter" variability="fixed"/>"#;
        assert!(
            text.contains(structural)
                && text.matches("<Output ").count() == 7
                && !text.contains("dependencies="),
            "pythonfmu3's model description changed; revisit this rewrite:\n{text}"
        );
        text.replace(structural, &structural.replace("/>", r#" start="2"/>"#))
            .replace("<Output ", r#"<Output dependencies="" "#)
    });
    fmu
}

/// What both masters record, in order: `a`'s arrays have three elements, `b`'s two.
const RECORD: [&str; 11] = [
    "a.y",
    "a.count",
    "a.big",
    "a.odd",
    "a.label",
    "b.y",
    "b.count",
    "b.big",
    "b.echo_big",
    "b.echo_label",
    "b.label",
];

fn scenario_toml(fmu: &Path) -> String {
    let fmu = fmu.to_str().expect("a UTF-8 temporary path");
    let record: Vec<String> = RECORD.iter().map(|r| format!("{r:?}")).collect();
    format!(
        r#"name = "counter-pythonfmu3"
start_time = 0.0
stop_time = {STOP_TIME_S:?}
step_size = {STEP_SIZE_S:?}
ordering = "gauss-seidel"
record = [{}]

[[instance]]
name = "a"
fmu = "{fmu}"
[instance.parameters]
n = 3
u = 0.5
label_in = "unused, \"quoted\""

[[instance]]
name = "b"
fmu = "{fmu}"
[instance.parameters]
offset = 9007199254740993
u = -1.5

[[connection]]
from = "a.big"
to = "b.big_in"

[[connection]]
from = "a.label"
to = "b.label_in"
"#,
        record.join(", ")
    )
}

fn system_json(fmu: &Path) -> serde_json::Value {
    serde_json::json!({
        "start_time": 0.0,
        "stop_time": STOP_TIME_S,
        "step_size": STEP_SIZE_S,
        "instances": [
            {"name": "a", "fmu": fmu, "parameters": [
                ["n", 3], ["u", 0.5], ["label_in", "unused, \"quoted\""]]},
            {"name": "b", "fmu": fmu, "parameters": [
                ["offset", 9007199254740993i64], ["u", -1.5]]},
        ],
        "connections": [["a.big", "b.big_in"], ["a.label", "b.label_in"]],
        "record": RECORD,
    })
}

/// What the harness's process needs to host pythonfmu3's binary (as in pythonfmu3.rs).
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

#[test]
fn a_pythonfmu3_fmu_with_a_structural_parameter_and_64_bit_and_string_types_flies_identically_in_the_harness_and_in_fmpy(
) {
    // GIVEN the counter packaged by pythonfmu3 and a system of two instances of it
    let dir = scratch("interop-pythonfmu3-types-");
    let fmu = build_fmu(dir.path());
    let scenario = dir.path().join("counter.toml");
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
    // ... and fmpy, through FMI 3.0
    let spec = write_json(&system_json(&fmu), dir.path());
    let fmpy_csv = dir.path().join("fmpy.csv");
    python::run(
        "fmpy3_types_master.py",
        [spec.as_os_str(), fmpy_csv.as_os_str()],
    );
    let harness = std::fs::read_to_string(&harness_csv).unwrap();
    let fmpy = std::fs::read_to_string(&fmpy_csv).unwrap();

    // THEN the harness sized a's arrays by the n it set, and recorded what the FMU computed
    let lines: Vec<&str> = harness.lines().collect();
    assert_eq!(
        lines[0],
        "time,a.y[1],a.y[2],a.y[3],a.count,a.big,a.odd,a.label,b.y[1],b.y[2],b.count,b.big,\
         b.echo_big,b.echo_label,b.label"
    );
    let steps = (STOP_TIME_S / STEP_SIZE_S) as u64;
    assert_eq!(lines.len() as u64, steps + 2, "header and a row per point");
    // After the last step: y[i] = gains[i] u + steps taken before it; the 64-bit counters
    // exact; b echoes what a passed on at the point before.
    let last = lines[lines.len() - 1];
    let expected = format!(
        "2.0,{:?},{:?},{:?},{},{},0,n=3 step {steps},{:?},{:?},{},{},{},n=3 step {}!,n=2 step {steps}",
        0.5 + (steps - 1) as f64,
        1.0 + (steps - 1) as f64,
        1.5 + (steps - 1) as f64,
        -(1i64 << 62) + steps as i64,
        u64::MAX - steps,
        -1.5 + (steps - 1) as f64,
        -3.0 + (steps - 1) as f64,
        9_007_199_254_740_993 + steps,
        u64::MAX - steps,
        u64::MAX - (steps - 1),
        steps - 1,
    );
    assert_eq!(last, expected, "{harness}");
    // ... and fmpy recorded the same, character for character
    assert_eq!(harness, fmpy, "the harness's CSV and fmpy's differ");
}
