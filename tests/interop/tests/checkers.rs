//! Every FMU the workspace packages as FMI 2.0 (each crate's `[package.metadata.fmu]`)
//! through two checkers we did not write: fmpy's `validate_fmu` and fmutool's `-check`
//! (fmu-manipulation-toolbox). No error and no warning is accepted; the script also requires
//! fmutool's two "passed" lines, so a checker that stopped early fails.
use interop_tests::{fmu_path, python};
use system_tests::shipped_fmus;

#[test]
fn fmpy_validate_and_fmutool_check_find_nothing_in_any_fmu() {
    let fmus = shipped_fmus();
    assert!(!fmus.is_empty(), "no FMU crate ships FMI 2.0");
    let report = python::run("checkers.py", fmus.iter().map(|id| fmu_path(id)));
    let all_passed = format!("checkers: {} passed, 0 failed", fmus.len());
    assert!(report.contains(&all_passed), "{report}");
}
