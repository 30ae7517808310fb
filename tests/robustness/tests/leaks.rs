//! Leaks: instantiate/initialize/step/free cycles under valgrind memcheck with zero
//! definitely-lost bytes and no memory error, and resident memory flat over the cycles.
//! The 10,000-cycle version is the `cycles` binary (see its documentation).
use robustness_tests::cycles::cycle;
use robustness_tests::instance::Fmu;
use robustness_tests::package::Lander;
use robustness_tests::reference::Wiring;
use robustness_tests::rss::vm_rss_kib;
use std::process::Command;

/// Under valgrind (about 50 times slower) per FMU.
const VALGRIND_CYCLES: &str = "300";

#[test]
fn cycles_under_valgrind_lose_no_memory_and_make_no_memory_error() {
    for lander in Lander::all() {
        let output = Command::new("valgrind")
            .args([
                "--leak-check=full",
                "--errors-for-leak-kinds=definite",
                "--error-exitcode=99",
                env!("CARGO_BIN_EXE_cycles"),
                "--cycles",
                VALGRIND_CYCLES,
                "--fmu",
                lander.model_identifier(),
            ])
            .output()
            .expect("valgrind must be installed (apt-get install valgrind; .ci/run does)");
        let report = String::from_utf8_lossy(&output.stderr);
        assert!(
            output.status.success(),
            "{}: valgrind failed:\n{report}",
            lander.model_identifier()
        );
        assert!(
            report.contains("definitely lost: 0 bytes")
                || report.contains("All heap blocks were freed"),
            "{report}"
        );
        assert!(report.contains("ERROR SUMMARY: 0 errors"), "{report}");
    }
}

#[test]
fn resident_memory_is_flat_over_the_cycles() {
    const CYCLES: usize = 3000;
    for lander in Lander::all() {
        let fmu = Fmu::load(lander).expect("packaged FMU");
        let wiring = Wiring::of(&fmu);
        let mut rss = Vec::new();
        for k in 0..CYCLES {
            cycle(&fmu, &wiring, k).unwrap_or_else(|e| panic!("{e}"));
            if (k + 1) % (CYCLES / 10) == 0 {
                rss.push(vm_rss_kib().expect("VmRSS in /proc/self/status"));
            }
        }
        // After the first tenth (allocator warm-up), no growth beyond allocator noise: a leak
        // of even 64 bytes per cycle would add 170 KiB here.
        let growth_kib = rss[9] as i64 - rss[0] as i64;
        assert!(
            growth_kib <= 64,
            "{}: VmRSS {rss:?} KiB",
            lander.model_identifier()
        );
    }
}
