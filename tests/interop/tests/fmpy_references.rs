//! The FMI-LS-REF references every FMU carries, checked in fmpy independently of the harness
//! that wrote them (tests/interop/python/fmpy_references.py): each FMU simulated with its
//! shipped stimuli over its experiment (`simulate_fmu` for FMI 2.0, the same loop over
//! `FMU3Slave` for FMI 3.0), each reference signal within
//! `fmpy.cross_check.validate_signal`'s band of the shipped tolerances.
use interop_tests::{fmu_path, python};
use system_tests::{fmi3_fmu_path, fmi3_fmus, shipped_fmus};

#[test]
fn fmpy_finds_every_fmus_runs_inside_its_shipped_references() {
    let fmi2 = shipped_fmus();
    let fmi3 = fmi3_fmus();
    assert!(!fmi2.is_empty() && !fmi3.is_empty(), "{fmi2:?} {fmi3:?}");
    let paths = fmi2
        .iter()
        .map(|id| fmu_path(id))
        .chain(fmi3.iter().map(|id| fmi3_fmu_path(id)));
    let report = python::run("fmpy_references.py", paths);
    let all_passed = format!(
        "fmpy_references: {} passed, 0 failed",
        fmi2.len() + fmi3.len()
    );
    assert!(report.contains(&all_passed), "{report}");
}
