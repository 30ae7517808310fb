//! Every lander FMU through two checkers we did not write: fmpy's `validate_fmu` and
//! fmutool's `-check` (fmu-manipulation-toolbox). No error and no warning is accepted; the
//! script also requires fmutool's two "passed" lines, so a checker that stopped early fails.
use interop_tests::{fmu_path, python};

#[test]
fn fmpy_validate_and_fmutool_check_find_nothing_in_any_lander_fmu() {
    let fmus = [
        "LanderGnc",
        "LanderPlant",
        "LanderNav",
        "LanderSensors",
        "LanderFilter",
    ];
    let report = python::run("checkers.py", fmus.map(fmu_path));
    assert!(report.contains("checkers: 5 passed, 0 failed"), "{report}");
}
