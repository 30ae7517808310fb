//! `harness run` and `harness vars` with an FMI 3.0 FMU of every variable type and a
//! structural parameter (the importer's C stub, fmi-import/tests/fixtures/stub_fmu3.c):
//! values from `--set` set exactly or refused before the run naming where they came from,
//! arrays sized by the structural parameter set, typed columns in CSV and Arrow, texts
//! across the supervised worker.
use crate::common::harness;
use crate::stub_fmu3;
use std::io::Write;
use std::path::{Path, PathBuf};

/// The stub packed as `Stub3.fmu` in `dir`.
fn stub_fmu(dir: &Path) -> PathBuf {
    let root = stub_fmu3::build(dir);
    let path = dir.join("Stub3.fmu");
    let mut zip = zip::ZipWriter::new(std::fs::File::create(&path).unwrap());
    for relative in ["modelDescription.xml", "binaries/x86_64-linux/Stub3.so"] {
        zip.start_file(relative, zip::write::SimpleFileOptions::default())
            .unwrap();
        zip.write_all(&std::fs::read(root.join(relative)).unwrap())
            .unwrap();
    }
    zip.finish().unwrap();
    path
}

fn text(output: &std::process::Output) -> (String, String) {
    (
        String::from_utf8_lossy(&output.stdout).into_owned(),
        String::from_utf8_lossy(&output.stderr).into_owned(),
    )
}

#[test]
fn set_values_of_every_type_are_recorded_exactly_and_n_sizes_the_arrays() {
    let dir = tempfile::tempdir().unwrap();
    let fmu = stub_fmu(dir.path());
    let csv = dir.path().join("run.csv");
    let arrow = dir.path().join("run.arrow");
    for out in [&csv, &arrow] {
        let output = harness(&[
            "run",
            fmu.to_str().unwrap(),
            "--set",
            "n=3",
            "--set",
            "x[3]=1.5",
            "--set",
            "uint64_in=18446744073709551615",
            "--set",
            "int8_in=-128",
            "--set",
            "string_in=hello",
            "--set",
            "binary_in=00ff",
            "--record",
            "y,uint64_out,int8_out,int32_out,boolean_out,float32_out,big,string_out,binary_out",
            "--stop-time",
            "0.02",
            "-o",
            out.to_str().unwrap(),
        ]);
        let (stdout, stderr) = text(&output);
        assert!(output.status.success(), "{stdout}\n{stderr}");
    }
    let csv = std::fs::read_to_string(&csv).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next().unwrap(),
        "time,Stub3.y[1],Stub3.y[2],Stub3.y[3],Stub3.uint64_out,Stub3.int8_out,\
         Stub3.int32_out,Stub3.boolean_out,Stub3.float32_out,Stub3.big,Stub3.string_out,\
         Stub3.binary_out"
    );
    // After the last step: y = 2 x with x[3] set; integers as integers, the largest UInt64
    // exact; 2^64 - 1 - steps for `big`.
    let rows: Vec<&str> = lines.collect();
    let steps = rows.len() as u64 - 1;
    assert_eq!(
        rows[rows.len() - 1],
        format!(
            "0.02,0.0,0.0,3.0,{},-128,0,0,0.0,{},hello,00ff",
            u64::MAX,
            u64::MAX - steps
        ),
        "{csv}"
    );
    let (trajectory, types) = cosim::results::read_arrow_typed(&arrow).unwrap();
    let uint64 = trajectory
        .names
        .iter()
        .position(|n| n == "Stub3.uint64_out")
        .unwrap();
    assert_eq!(types[uint64], cosim::results::ColumnType::UInt64);
    let last = trajectory.row(trajectory.len() - 1);
    assert_eq!(last[uint64].to_bits(), u64::MAX);

    // pyarrow and pandas read each column in its type, the UInt64 exactly.
    let python = crate::common::workspace_root().join(".venv/bin/python");
    assert!(
        python.is_file(),
        "{} is missing: run `cargo xtask python-env`",
        python.display()
    );
    let check = r#"
import sys, pyarrow.feather as feather
table = feather.read_table(sys.argv[1])
types = {f.name: str(f.type) for f in table.schema}
print(types["Stub3.y[3]"], types["Stub3.uint64_out"], types["Stub3.int8_out"],
      types["Stub3.int32_out"], types["Stub3.boolean_out"], types["Stub3.float32_out"],
      types["Stub3.string_out"], types["Stub3.binary_out"])
frame = table.to_pandas()
print(frame["Stub3.uint64_out"].iloc[-1], frame["Stub3.binary_out"].iloc[-1].hex(),
      frame["Stub3.string_out"].iloc[-1])
"#;
    let output = std::process::Command::new(python)
        .args(["-c", check])
        .arg(&arrow)
        .output()
        .unwrap();
    let (stdout, stderr) = text(&output);
    assert!(output.status.success(), "{stderr}");
    assert_eq!(
        stdout,
        format!(
            "double uint64 int8 int32 bool float string binary\n{} 00ff hello\n",
            u64::MAX
        )
    );
}

#[test]
fn values_their_type_cannot_hold_are_refused_before_the_run_naming_the_set() {
    let dir = tempfile::tempdir().unwrap();
    let fmu = stub_fmu(dir.path());
    let out = dir.path().join("never.csv");
    let output = harness(&[
        "run",
        fmu.to_str().unwrap(),
        "--set",
        "uint8_in=300",
        "--set",
        "p16=1.5",
        "--set",
        "n=-2",
        "-o",
        out.to_str().unwrap(),
    ]);
    let (stdout, stderr) = text(&output);
    assert_eq!(output.status.code(), Some(1), "{stdout}\n{stderr}");
    for expected in [
        "instance 'Stub3': parameter 'uint8_in' is UInt8, and the value given cannot be one: \
         300 is outside the range of UInt8 [0, 255] (from --set uint8_in=300)",
        "parameter 'p16' is Int16, and the value given cannot be one: the Real 1.5 is not a \
         Int16 (from --set p16=1.5)",
        "structural parameter 'n' (UInt64) cannot be -2",
    ] {
        assert!(stderr.contains(expected), "{expected:?} not in:\n{stderr}");
    }
    assert!(!out.exists());
}

#[test]
fn vars_names_each_fmi3_type() {
    let dir = tempfile::tempdir().unwrap();
    let fmu = stub_fmu(dir.path());
    let output = harness(&["vars", fmu.to_str().unwrap()]);
    let (stdout, stderr) = text(&output);
    assert!(output.status.success(), "{stderr}");
    for line in [
        "n\tparameter\tfixed\tUInt64\t2\t",
        "p16\tparameter\tfixed\tInt16\t7\t",
        "uint64_out\toutput\tdiscrete\tUInt64\t",
        "float32_in\tinput\tcontinuous\tFloat32\t0\t",
        "binary_in\tinput\tdiscrete\tBinary\t",
        "x[2]\tinput\tcontinuous\tFloat64\t0\t",
        // Beyond 32 bits: the file's own start value.
        "offset64\tparameter\tfixed\tInt64\t-4611686018427387904\t",
    ] {
        assert!(stdout.contains(line), "{line:?} not in:\n{stdout}");
    }
}

#[test]
fn a_requirement_over_a_64_bit_or_text_column_is_refused_before_the_run() {
    let dir = tempfile::tempdir().unwrap();
    let fmu = stub_fmu(dir.path());
    let scenario = dir.path().join("stub.toml");
    std::fs::write(
        &scenario,
        format!(
            "name = \"stub\"\nstart_time = 0.0\nstop_time = 0.1\nstep_size = 0.05\n\n\
             [[instance]]\nname = \"s\"\nfmu = \"{}\"\n\n\
             [[requirement]]\nname = \"counts\"\nformula = \"always [0, 0.1] s.big >= 0\"\n\n\
             [[requirement]]\nname = \"small\"\nformula = \"always [0, 0.1] s.int8_out >= 0\"\n",
            fmu.display()
        ),
    )
    .unwrap();
    let out = dir.path().join("never.csv");
    let output = harness(&[
        "run",
        scenario.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    let (stdout, stderr) = text(&output);
    assert_eq!(output.status.code(), Some(1), "{stdout}\n{stderr}");
    assert!(
        stderr.contains("s.big is a UInt64 column, which a formula does not read"),
        "{stderr}"
    );
    assert!(!stderr.contains("int8_out"), "an Int8 is read: {stderr}");
    assert!(!out.exists());
}
