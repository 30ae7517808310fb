//! Both lander FMUs through two checkers we did not write: fmpy's `validate_fmu` and
//! fmutool's `-check` (fmu-manipulation-toolbox). No error and no warning is accepted; the
//! script also requires fmutool's two "passed" lines, so a checker that stopped early fails.
use interop_tests::{fmu_path, python};

#[test]
fn fmpy_validate_and_fmutool_check_find_nothing_in_either_lander_fmu() {
    let report = python::run("checkers.py", ["LanderGnc", "LanderPlant"].map(fmu_path));
    assert!(report.contains("checkers: 2 passed, 0 failed"), "{report}");
}
