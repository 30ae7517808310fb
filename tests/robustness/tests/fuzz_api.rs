//! The short deterministic API fuzzing run of `cargo test` (the long one is the `fuzz-api`
//! binary). Needs the packaged FMUs (`cargo xtask fmus`).
use robustness_tests::fuzz::{self, Watchdog};
use robustness_tests::instance::Fmu;
use robustness_tests::package::Lander;
use std::time::Duration;

/// Per FMU; a debug build of the driver makes about 1,500 calls per second.
const CALLS: u64 = 12_000;

fn fuzz(lander: Lander, seed: u64) {
    let fmu = Fmu::load(lander).expect("packaged FMU");
    let dog = Watchdog::start(Duration::from_secs(20));
    let stats = fuzz::run(&fmu, CALLS, seed, &dog, |_| {}).unwrap_or_else(|e| panic!("{e}"));
    // The generator must reach the interesting places, or the run proves little.
    let [ok, _, discard, error, _] = stats.statuses;
    assert!(stats.fuzz_calls >= CALLS);
    assert!(ok > CALLS / 10, "too few successful calls: {stats:?}");
    assert!(error > CALLS / 10, "too few refusals: {stats:?}");
    assert!(stats.predicted_refusals > CALLS / 20, "{stats:?}");
    assert!(discard > 0, "no discarded status query or step: {stats:?}");
    assert!(
        stats.crafted_accepted > 0,
        "no crafted state got past the checks: {stats:?}"
    );
}

#[test]
fn lander_gnc_survives_random_call_sequences() {
    fuzz(Lander::Gnc, 7);
}

#[test]
fn lander_plant_survives_random_call_sequences() {
    fuzz(Lander::Plant, 7);
}

#[test]
fn lander_nav_survives_random_call_sequences() {
    fuzz(Lander::Nav, 7);
}

#[test]
fn lander_sensors_survives_random_call_sequences() {
    fuzz(Lander::Sensors, 7);
}

#[test]
fn lander_filter_survives_random_call_sequences() {
    fuzz(Lander::Filter, 7);
}
