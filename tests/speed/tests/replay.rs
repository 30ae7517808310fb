//! The replay checks that make rows 1 and 2 mean "the paper flight": they pass on the
//! recorded flight and fail when the inputs differ from it by a single step or a single bit.
use fmi_import::Fmu;
use speed_bench::record::PaperRecord;
use speed_bench::replay::{gnc_cycles, plant_cycles, plant_steps};

/// The first 3 s of the paper flight, in hover: small, slow changes, the hardest case for
/// telling one step from the next.
fn short_flight() -> PaperRecord {
    PaperRecord::fly(&interop_tests::fmu_dir(), Some(3.0)).expect("the paper flight")
}

fn load(name: &str) -> Fmu {
    Fmu::load(interop_tests::fmu_path(name)).expect("a packaged FMU")
}

#[test]
fn the_plant_retraces_the_flight_under_its_recorded_commands_and_only_under_them() {
    // GIVEN a recorded flight and LanderPlant
    let record = short_flight();
    let plant = load("LanderPlant");

    // WHEN the recorded commands are replayed
    let (means, agreement) = plant_cycles(&plant, &record, record.steps(), 100).unwrap();
    // THEN every output is the recorded one, one batch mean per 100 steps
    assert!(agreement.bit_identical);
    assert_eq!(agreement.max_position_error_m, 0.0);
    assert_eq!(means.len(), record.steps().div_ceil(100));
    assert!(means.iter().all(|t| t.is_finite() && *t > 0.0));

    // WHEN one thrust command is one ULP larger
    let mut nudged = record.clone();
    let k = record.steps() / 2;
    nudged.commands[k][0] = f64::from_bits(nudged.commands[k][0].to_bits() + 1);
    let (_, agreement) = plant_cycles(&plant, &nudged, nudged.steps(), 100).unwrap();
    // THEN the replay no longer counts as the recorded flight
    assert!(!agreement.bit_identical);
    assert!(agreement.max_position_error_m < 1e-6);
}

#[test]
fn the_controller_reproduces_the_recorded_commands_only_with_the_exchange_s_timing() {
    // GIVEN a recorded flight and LanderGnc
    let record = short_flight();
    let gnc = load("LanderGnc");

    // WHEN it is replayed as the harness exchanged it: THEN the commands match
    let means = gnc_cycles(&gnc, &record, record.steps(), 100).unwrap();
    assert_eq!(means.len(), record.steps().div_ceil(100));

    // WHEN each step sees the plant one step later than the harness gave it
    let mut early = record.clone();
    early.navigation.remove(0);
    early.navigation.push(*record.navigation.last().unwrap());
    // THEN the replay is refused as another flight
    let error = gnc_cycles(&gnc, &early, early.steps(), 100).unwrap_err();
    assert!(
        error.to_string().contains("does not reproduce"),
        "{error:#}"
    );
}

#[test]
fn step_only_batches_cover_every_step_and_keep_to_the_flight() {
    // GIVEN a recorded flight and LanderPlant
    let record = short_flight();
    let plant = load("LanderPlant");
    // WHEN 95 steps are timed call by call in batches of 10
    let (means, agreement) = plant_steps(&plant, &record, 95, 10).unwrap();
    // THEN 9 full batches and one of 5, along the recorded flight
    assert_eq!(means.len(), 10);
    assert!(agreement.bit_identical);
    assert!(plant_steps(&plant, &record, 95, 0).is_err());
}
