//! The FMI-LS-REF references every FMU carries, checked in fmpy independently of the harness
//! that wrote them (tests/interop/python/fmpy_references.py): each FMI 2.0 FMU simulated by
//! `simulate_fmu` with its shipped stimuli over its experiment, each reference signal
//! within `fmpy.cross_check.validate_signal`'s band of the shipped tolerances.
use interop_tests::{fmu_path, python};
use system_tests::shipped_fmus;

#[test]
fn fmpy_finds_every_fmus_runs_inside_its_shipped_references() {
    let fmus = shipped_fmus();
    assert!(!fmus.is_empty(), "no FMU crate ships FMI 2.0");
    let report = python::run("fmpy_references.py", fmus.iter().map(|id| fmu_path(id)));
    let all_passed = format!("fmpy_references: {} passed, 0 failed", fmus.len());
    assert!(report.contains(&all_passed), "{report}");
}
