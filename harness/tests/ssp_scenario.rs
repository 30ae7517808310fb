//! The paper scenario ships as TOML and as SSP `SystemStructure.ssd`; the SSD is generated from
//! the TOML (never hand-edited) and both fly the same trajectory. Regenerate after changing the
//! TOML with `UPDATE_SSD=1 cargo test -p harness --test main ssp_scenario::`.
use crate::common;

use cosim::master::{Simulation, Trajectory};
use lander::scenarios;
use std::path::PathBuf;

fn scenarios_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("scenarios")
}

#[test]
fn the_checked_in_ssd_is_generated_from_the_toml() {
    let system = scenarios::load("paper").unwrap();
    let generated = scenarios::ssd_for(&system, &common::fmu_dir()).unwrap();
    let path = scenarios_dir().join("paper.ssd");
    if std::env::var_os("UPDATE_SSD").is_some() {
        std::fs::write(&path, &generated).unwrap();
    }
    let checked_in = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        checked_in == generated,
        "{} drifted from paper.toml: regenerate with UPDATE_SSD=1",
        path.display()
    );
}

#[test]
fn the_ssd_and_the_toml_fly_the_same_trajectory() {
    let fly = |scenario: &str| {
        let mut system = scenarios::load(scenario).unwrap();
        system.stop_time = 20.0;
        let mut simulation = Simulation::new(system, &common::fmu_dir()).unwrap();
        let mut trajectory = Trajectory {
            names: simulation.column_names().to_vec(),
            ..Default::default()
        };
        simulation.run(&mut trajectory).unwrap();
        trajectory
    };
    let from_toml = fly("paper");
    let from_ssd = fly(scenarios_dir().join("paper.ssd").to_str().unwrap());
    assert_eq!(from_toml.names, from_ssd.names);
    assert_eq!(from_toml.times, from_ssd.times);
    let bits = |t: &Trajectory| t.values.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    assert!(bits(&from_toml) == bits(&from_ssd), "trajectories differ");
}
