//! A campaign records at every step only what its metrics read and takes the verdict's
//! touchdown columns once, at the end of each flight. These tests check that this lean path
//! gives what recording every output gives: the final values equal the last recorded row,
//! and every manifest row of a landing campaign (touchdowns, so the final-only columns
//! matter) equals a replay that records everything, bit for bit.
use crate::common;

use campaign::dispersion::DispersionRanges;
use campaign::{replay, runner};
use campaign::{CampaignSpec, Shard};
use cosim::master::{Simulation, Trajectory};
use lander::laws::Law;
use lander::scenarios;

#[test]
fn final_values_equal_the_last_recorded_row_for_every_exchange_type() {
    let mut system = scenarios::load("paper").unwrap();
    system.stop_time = 3.0;
    system.record = None;
    let mut simulation = Simulation::new(system, &common::fmu_dir()).unwrap();
    // Real (an array), Boolean and Integer outputs of both instances.
    let names: Vec<String> = [
        "plant.r_nue",
        "plant.propellant_exhausted",
        "gnc.guidance_phase",
    ]
    .map(String::from)
    .to_vec();
    simulation.set_final_columns(&names).unwrap();
    assert!(simulation.final_values().iter().all(|v| v.is_nan()));
    let mut trajectory = Trajectory {
        names: simulation.column_names().to_vec(),
        ..Default::default()
    };
    simulation.run(&mut trajectory).unwrap();
    let finals = simulation.final_column_names();
    assert_eq!(
        finals,
        [
            "plant.r_nue[1]",
            "plant.r_nue[2]",
            "plant.r_nue[3]",
            "plant.propellant_exhausted",
            "gnc.guidance_phase"
        ]
    );
    let last = trajectory.row(trajectory.len() - 1);
    for (name, value) in finals.iter().zip(simulation.final_values()) {
        let j = trajectory.column_index(name).unwrap();
        assert_eq!(value.to_bits(), last[j].to_bits(), "{name}");
    }
    // The altitude moved, so these are the end's values, not the start's.
    assert_ne!(simulation.final_values()[1], 800.0);
}

#[test]
fn an_unknown_final_column_is_named() {
    let system = scenarios::load("paper").unwrap();
    let mut simulation = Simulation::new(system, &common::fmu_dir()).unwrap();
    let error = simulation
        .set_final_columns(&["plant.touchdown_altitude".to_owned()])
        .unwrap_err()
        .to_string();
    assert!(error.contains("touchdown_altitude"), "{error}");
}

#[test]
fn a_landing_campaign_equals_its_replays_that_record_every_output() {
    let spec = CampaignSpec {
        scenario: "landing".into(),
        seed: 7,
        phi_cmd_deg: vec![150.0],
        laws: vec![Law::DECOUPLED, Law::new("reduced")],
        runs_per_point: 1,
        dispersions: DispersionRanges::default(),
        sets: Vec::new(),
    };
    let out = tempfile::tempdir().unwrap();
    let options = runner::RunOptions {
        fmu_dir: common::fmu_dir(),
        out_dir: out.path().to_owned(),
        workers: 1,
        shard: Shard::WHOLE,
        progress: false,
    };
    runner::run(&spec, &options).unwrap();
    for index in 0..spec.flight_count() {
        let replayed = replay::from_manifest(out.path(), index, &common::fmu_dir()).unwrap();
        let metrics = &replayed.recorded.metrics;
        // The touchdown metrics come from the final-only columns: they must be there.
        assert!(
            metrics.touchdown_vertical_speed_mps.is_finite()
                && metrics.touchdown_body_rate_radps.is_finite(),
            "flight {index} did not touch down: {metrics:?}"
        );
        assert!(
            replayed.matches(),
            "flight {index}: campaign {:?} vs replay {:?}",
            replayed.recorded,
            replayed.replayed
        );
    }
}
