//! C ABI conformance of the packaged FMUs, checked the way a C master sees them.
//!
//! 1. `nm -D --defined-only` on the library of each packaged FMU, FMI 2.0 and FMI 3.0, lists
//!    exactly what its `[package.metadata.fmu]` promises (one library serves both
//!    standards): the 34 `fmi2*` functions of FMI 2.0 Co-Simulation, plus the 10 of Model
//!    Exchange when FMI 2.0 offers it, plus the 75 `fmi3*` functions when FMI 3.0 is
//!    shipped; nothing missing, nothing of ours leaking.
//! 2. cbindgen writes a C header of the functions the export macro generates (from the
//!    macro-expanded plant crate, whose export adds Model Exchange to the macro's
//!    Co-Simulation functions that every FMU uses), and
//!    `tests/c/abi_check.c` is compiled against it *and* the official FMI 2.0 and 3.0
//!    headers with `-std=c99 -Wall -Wextra -Werror -pedantic`: a signature that differs
//!    from the standard's `fmi2XxxTYPE` or `fmi3XxxTYPE` is a conflicting redeclaration,
//!    i.e. a compile error.
//! 3. The compiled program dlopens each packaged library, binds all 34 functions through
//!    their typedefs and runs a short simulation with its checks (see abi_check.c).
use crate::exports;

use exports::{dynamic_symbols, expected_exports, official_headers};
use fmi_abi::unpack::Unpacked;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::Command;
use system_tests::{
    fmi3_binary_path, fmi3_fmu_path, fmu_crates, shipped_fmus, target_dir, workspace_root, Fmi,
    UnpackedFmu,
};

/// Communication steps of the C program's simulation: enough for a state round trip in
/// the second half, short enough to stay far from any lander touchdown.
const C_CHECK_STEPS: u32 = 20;

#[test]
fn each_packaged_library_exports_exactly_what_its_metadata_promises() {
    let mut checked = 0;
    for fmu in fmu_crates() {
        let id = &fmu.model_identifier;
        let expected = expected_exports(&fmu);
        if fmu.ships(Fmi::V2) {
            let unpacked = UnpackedFmu::open(id);
            let exported = dynamic_symbols("nm", &unpacked.library());
            assert_eq!(exported, expected, "dynamic symbols of the FMI 2.0 {id}");
            checked += 1;
        }
        if fmu.ships(Fmi::V3) {
            let path = fmi3_fmu_path(id);
            let unpacked = Unpacked::open(&path).unwrap_or_else(|e| panic!("{e}"));
            let exported = dynamic_symbols("nm", &fmi3_binary_path(unpacked.root(), id));
            assert_eq!(exported, expected, "dynamic symbols of the FMI 3.0 {id}");
            checked += 1;
        }
    }
    assert!(checked > 0, "the metadata lists no packaged FMU");
}

#[test]
fn c_master_binds_every_function_through_the_official_typedefs_and_simulates() {
    let work = tempfile::tempdir().unwrap();
    let header = work.path().join("fmi2_exports.h");
    // A crate whose metadata ships everything (the plant): its export is the Co-Simulation
    // one plus Model Exchange in both versions, so the header declares every function and
    // each is checked against the official typedefs.
    let fullest = fmu_crates()
        .into_iter()
        .find(|f| f.ships_model_exchange(Fmi::V2) && f.ships(Fmi::V3))
        .expect("no FMU crate ships FMI 2.0 Model Exchange and FMI 3.0");
    generate_exports_header(&fullest.package, &header);
    let declared = declared_functions(&std::fs::read_to_string(&header).unwrap());
    assert_eq!(
        declared,
        expected_exports(&fullest),
        "functions declared in the cbindgen header of {}",
        fullest.package
    );

    let program = work.path().join("abi_check");
    compile_abi_check(work.path(), &program);

    for fmu in shipped_fmus() {
        let unpacked = UnpackedFmu::open(&fmu);
        let description = &unpacked.description;
        let step_size = description
            .default_experiment
            .as_ref()
            .and_then(|e| e.step_size)
            .unwrap_or(1e-2);
        let real_outputs: Vec<String> = description
            .outputs()
            .filter(|v| v.real.is_some())
            .map(|v| v.value_reference.to_string())
            .collect();
        // An FMU that declares directional derivatives answers an empty request with OK;
        // one that does not refuses every request.
        let provides_derivatives = description
            .co_simulation
            .as_ref()
            .and_then(|cs| cs.provides_directional_derivative)
            .unwrap_or(false);
        let output = Command::new(&program)
            .env(
                "ABI_CHECK_PROVIDES_DIRECTIONAL_DERIVATIVE",
                if provides_derivatives { "1" } else { "0" },
            )
            .arg(unpacked.library())
            .arg(&description.guid)
            .arg(unpacked.resource_uri())
            .arg(step_size.to_string())
            .arg(C_CHECK_STEPS.to_string())
            .args(&real_outputs)
            .output()
            .expect("cannot run the compiled abi_check");
        let stdout = String::from_utf8_lossy(&output.stdout);
        println!("{}:\n{stdout}", fmu);
        assert!(
            output.status.success() && stdout.contains(", 0 failed"),
            "abi_check failed on {} ({}):\n{stdout}{}",
            fmu,
            output.status,
            String::from_utf8_lossy(&output.stderr)
        );
    }
}

/// Writes the cbindgen header of `package`'s exported functions. The `fmi2*` symbols are
/// generated by the `export_fmi2!` macro, which cbindgen only sees in the expanded crate.
fn generate_exports_header(package: &str, header: &Path) {
    let expanded = header.with_extension("expanded.rs");
    std::fs::write(&expanded, expand_crate(package)).unwrap();
    let config_path = workspace_root().join("tests/c/cbindgen.toml");
    let config = cbindgen::Config::from_file(&config_path)
        .unwrap_or_else(|e| panic!("{}: {e}", config_path.display()));
    cbindgen::Builder::new()
        .with_config(config)
        .with_src(&expanded)
        .generate()
        .unwrap_or_else(|e| panic!("cbindgen on the expanded {package}: {e}"))
        .write_to_file(header);
}

/// The macro-expanded source of a library crate (`rustc -Zunpretty=expanded`).
fn expand_crate(package: &str) -> String {
    let output = Command::new(env!("CARGO"))
        .current_dir(workspace_root())
        .args([
            "rustc",
            "--quiet",
            "--lib",
            "--profile",
            "check",
            "-p",
            package,
        ])
        // A folder of its own: the outer `cargo test` holds the lock of the usual one.
        .arg("--target-dir")
        .arg(target_dir().join("abi-check"))
        .args(["--", "-Zunpretty=expanded"])
        // -Zunpretty is unstable; RUSTC_BOOTSTRAP lets the stable toolchain run it, as
        // cbindgen's own `parse.expand` requires a nightly compiler for.
        .env("RUSTC_BOOTSTRAP", "1")
        .output()
        .expect("cannot run cargo");
    assert!(
        output.status.success(),
        "expanding {package} failed:\n{}",
        String::from_utf8_lossy(&output.stderr)
    );
    String::from_utf8(output.stdout).expect("expanded source is UTF-8")
}

/// Names of the functions a C header declares (an identifier directly before `(`).
fn declared_functions(header: &str) -> BTreeSet<String> {
    header
        .split('(')
        .filter_map(|before| {
            let name_start = before
                .rfind(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
                .map_or(0, |i| i + 1);
            let name = &before[name_start..];
            (name.starts_with("fmi2") || name.starts_with("fmi3")).then(|| name.to_owned())
        })
        .collect()
}

fn compile_abi_check(include_dir: &Path, program: &Path) {
    let source = workspace_root().join("tests/c/abi_check.c");
    let output = Command::new(std::env::var_os("CC").unwrap_or_else(|| "cc".into()))
        .args(["-std=c99", "-Wall", "-Wextra", "-Werror", "-pedantic"])
        .arg("-I")
        .arg(official_fmi2_headers())
        .arg("-I")
        .arg(official_headers("fmi-standard3"))
        .arg("-I")
        .arg(include_dir)
        .arg(&source)
        .arg("-o")
        .arg(program)
        .args(["-ldl", "-lm"])
        .output()
        .expect("cannot run the C compiler");
    assert!(
        output.status.success(),
        "abi_check.c does not compile against the official headers and ours:\n{}",
        String::from_utf8_lossy(&output.stderr)
    );
}

/// `fmi-standard2/headers` of the fmi-sys crate in the cargo registry (a dev-dependency of
/// this crate, so cargo has downloaded it), found through `cargo metadata`.
fn official_fmi2_headers() -> PathBuf {
    official_headers("fmi-standard2")
}

#[test]
fn declared_functions_reads_names_before_parentheses_only() {
    let header = "fmi2Status fmi2DoStep(fmi2Component c,\n    fmi2Real t);\n\
                  const char *fmi2GetVersion(void);\nvoid other(int x);\n";
    let expected: BTreeSet<String> = ["fmi2DoStep", "fmi2GetVersion"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    assert_eq!(declared_functions(header), expected);
}
