//! The closed loops fly the same bits on every platform: the `--all-platforms` FMUs, flown by
//! one C master (tests/c/closed_loop_master.c) compiled for x86_64 Linux (run natively),
//! aarch64 Linux (under qemu-aarch64) and x86_64 Windows (under Wine), print every output of
//! every FMU at every communication point as IEEE-754 bits, and the prints must be equal line
//! by line. Three of the harness's scenarios, connected as the harness connects them:
//!
//! - `paper`: LanderGnc and LanderPlant, the paper's flight (no touchdown);
//! - `paper-thrusters`: LanderNav between them with navigation errors, eight thrusters;
//! - `landing`: the paper's descent followed by a terminal descent to touchdown, so that the
//!   touchdown step (FMI 2.0: fmi2Discard + fmi2Terminated; FMI 3.0: terminateSimulation)
//!   and the frozen touchdown outputs are compared too.
//!
//! each in FMI 2.0 (linux64, win64) and FMI 3.0 (x86_64-linux, aarch64-linux,
//! x86_64-windows), and FMI 3.0 against FMI 2.0 on x86_64 Linux. Not in the default suite: it needs the cross toolchains, qemu and Wine.
//!
//!     cargo xtask fmus --all-platforms
//!     cargo test -p system-tests --test main same_bits:: -- --ignored --nocapture
//!
//! A missing FMU or tool fails the test with the command that provides it.
use crate::cross;

use cross::{differences, first_difference, fly, Plan, Platform, Run};
use system_tests::Fmi;

const SCENARIOS: [&str; 3] = ["paper", "paper-thrusters", "landing"];

/// Flies `plan` on every platform of `version` at once (two cores: the emulated ones are
/// the slow ones).
fn fly_everywhere(plan: &Plan, name: &str) -> Vec<Run> {
    let platforms: Vec<Platform> = Platform::ALL
        .into_iter()
        .filter(|p| p.folder(plan.version).is_some())
        .collect();
    for &p in &platforms {
        cross::prepare(p);
    }
    std::thread::scope(|s| {
        let handles: Vec<_> = platforms
            .iter()
            .map(|&p| s.spawn(move || fly(p, plan, name)))
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    })
}

#[test]
#[ignore = "needs `cargo xtask fmus --all-platforms`, qemu-user and Wine"]
fn the_closed_loops_fly_the_same_bits_on_every_platform() {
    let mut failures = Vec::new();
    for scenario in SCENARIOS {
        // The x86_64 Linux run of each version: the two versions of one model fly the same
        // bits too (both step by the master's h; only the binding differs).
        let mut by_version: Vec<Run> = Vec::new();
        for version in Fmi::ALL {
            let plan = Plan::scenario(scenario, version);
            let name = format!("{scenario}-{version:?}").to_lowercase();
            let runs = fly_everywhere(&plan, &name);
            for run in &runs {
                run.assert_clean(&name);
            }
            let reference = &runs[0];
            assert_eq!(reference.platform, Platform::LinuxX86_64);
            let points = reference
                .lines()
                .filter(|l| l.starts_with(|c: char| c.is_ascii_digit()))
                .count()
                / plan.units.len();
            let end = reference.lines().rev().nth(1).unwrap_or("");
            eprintln!(
                "{name}: {points} communication points, {end}; {}",
                runs.iter()
                    .map(|r| format!("{} {:.1} s", r.platform.name(), r.seconds))
                    .collect::<Vec<_>>()
                    .join(", ")
            );
            for other in &runs[1..] {
                if let Some(first) = first_difference(reference, other) {
                    let all = differences(reference, other);
                    failures.push(format!(
                        "{name}: {first}\n  {} variables differ:\n    {}\n  run again: {}",
                        all.len(),
                        all.join("\n    "),
                        other.command
                    ));
                }
            }
            by_version.extend(runs.into_iter().next());
        }
        // Every value at every point; not the time of a touchdown row, which the master
        // takes from the step's end in FMI 2.0 (fmi2Discard) and from lastSuccessfulTime in
        // FMI 3.0 (earlyReturn).
        if let [fmi2, fmi3] = by_version.as_slice() {
            let all = differences(fmi2, fmi3);
            if !all.is_empty() {
                failures.push(format!(
                    "{scenario}: FMI 3.0 against FMI 2.0, {} variables differ:\n    {}",
                    all.len(),
                    all.join("\n    ")
                ));
            }
        }
    }
    assert!(
        failures.is_empty(),
        "{} of the flights differ between platforms:\n{}",
        failures.len(),
        failures.join("\n")
    );
}
