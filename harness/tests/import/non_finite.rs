//! `harness run` on an FMU whose outputs stop being numbers (the master's fixture,
//! cosim/tests/non_finite_fmu.rs): exit code 1 naming the variable, or a completed run with
//! one warning per allowed variable.
use crate::non_finite_fmu::NonFiniteFmu;
use std::process::Command;
use tempfile::TempDir;

/// `harness run` on a TOML scenario of the fixture, with `extra` top-level keys.
fn harness_run(
    fmu: &NonFiniteFmu,
    extra: &str,
    options: &[&str],
) -> (std::process::Output, TempDir) {
    let work = TempDir::new().unwrap();
    let scenario = work.path().join("nan.toml");
    std::fs::write(
        &scenario,
        format!(
            "name = \"nan\"\nstop_time = 1.0\nstep_size = 0.1\n{extra}\n\
             [[instance]]\nname = \"src\"\nfmu = \"{}\"\n",
            fmu.dir.display()
        ),
    )
    .unwrap();
    let output = Command::new(env!("CARGO_BIN_EXE_harness"))
        .arg("--fmu-dir")
        .arg(work.path())
        .args(options)
        .arg("run")
        .arg(&scenario)
        .arg("-o")
        .arg(work.path().join("out.csv"))
        .env("RUST_BACKTRACE", "0")
        .env_remove("RUST_LOG")
        .output()
        .unwrap();
    (output, work)
}

#[test]
fn the_cli_fails_a_nan_run_with_exit_code_1_and_names_it() {
    let fmu = NonFiniteFmu::build(&[]);
    let (output, _work) = harness_run(&fmu, "", &[]);
    let said = format!(
        "{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
    assert_eq!(output.status.code(), Some(1), "{said}");
    assert!(
        said.contains("'src'") && said.contains("'y'") && said.contains("t = 0.5"),
        "{said}"
    );
}

#[test]
fn the_cli_completes_an_allowed_nan_run_and_warns_once_per_variable() {
    let fmu = NonFiniteFmu::build(&[]);
    let allow = "allow_non_finite = [\"src.y\", \"src.v\"]";
    // A supervised worker (the default) completes it too.
    let (output, _work) = harness_run(&fmu, allow, &[]);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    // In process, the warnings reach the harness's logger.
    let (output, work) = harness_run(&fmu, allow, &["--in-process"]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    assert_eq!(stderr.matches("'src.y'").count(), 1, "{stderr}");
    assert_eq!(stderr.matches("'src.v[2]'").count(), 1, "{stderr}");
    let csv = std::fs::read_to_string(work.path().join("out.csv")).unwrap();
    assert_eq!(csv.lines().count(), 12, "{csv}");
}
