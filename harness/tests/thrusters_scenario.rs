//! `harness/scenarios/paper-thrusters.toml`: the paper scenario with eight thrusters and
//! navigation errors. The thrusters do fly it, the decoupled law beats the coupled one at
//! phi_cmd = 150 deg, and a Monte Carlo run draws its own navigation errors.
use crate::common;

use campaign::flight::{campaign_system, Flyer};
use campaign::{DispersionRanges, Flight};
use cosim::master::{Simulation, Trajectory};
use cosim::system::{toml_format, SystemDescription};
use lander::laws::{Law, Laws};
use std::path::{Path, PathBuf};

const SCENARIO: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/scenarios/paper-thrusters.toml"
);

fn fmu_dir() -> PathBuf {
    let dir = common::fmu_dir();
    assert!(
        dir.join("LanderNav.fmu").is_file(),
        "LanderNav.fmu is missing in {}: run `cargo xtask fmus` first",
        dir.display()
    );
    dir
}

fn fly(system: SystemDescription) -> Trajectory {
    let mut simulation = Simulation::new(system, &fmu_dir()).unwrap();
    let mut trajectory = Trajectory {
        names: simulation.column_names().to_vec(),
        ..Default::default()
    };
    simulation.run(&mut trajectory).unwrap();
    trajectory
}

fn max_horizontal_deviation_m(run: &Trajectory) -> f64 {
    let north = run.column("plant.r_nue[1]").unwrap();
    let east = run.column("plant.r_nue[3]").unwrap();
    north
        .iter()
        .zip(&east)
        .map(|(n, e)| n.hypot(*e))
        .fold(0.0, f64::max)
}

#[test]
fn thrusters_fly_the_paper_scenario_and_the_decoupled_law_deviates_least() {
    // GIVEN the scenario with each law
    let with_law = |law: Law| {
        let mut system = toml_format::read(Path::new(SCENARIO)).unwrap();
        let laws = Laws::of_instance(&system, "gnc", &common::fmu_dir()).unwrap();
        assert!(system.set_parameter("gnc", "control_law", laws.parameter(law).unwrap()));
        fly(system)
    };
    let (coupled, decoupled) = (with_law(Law::COUPLED), with_law(Law::DECOUPLED));
    // THEN the plant is driven by pulses: duties strictly between 0 and 1 occur
    let duty = decoupled.column("gnc.rcs_duty[5]").unwrap();
    assert!(
        duty.iter().any(|d| *d > 0.0 && *d < 1.0),
        "no partial pulse"
    );
    assert!(duty.contains(&0.0), "never off");
    // AND the decoupled law keeps the lander near the vertical, the coupled law does not
    // (nominal flight: 2.7 m and 93 m)
    let (c, d) = (
        max_horizontal_deviation_m(&coupled),
        max_horizontal_deviation_m(&decoupled),
    );
    assert!(d < 10.0 && c > 30.0, "coupled {c} m, decoupled {d} m");
}

#[test]
fn each_monte_carlo_run_draws_its_own_navigation_errors() {
    // GIVEN the scenario for 5 s without any dispersion: runs differ only by their seed
    let (mut system, spec) = campaign_system(SCENARIO, &[], true).unwrap();
    system.stop_time = 5.0;
    let mut flyer = Flyer::new(system, spec, &fmu_dir()).unwrap();
    let none = DispersionRanges::none();
    let mut estimate = |run_seed| {
        let flight = Flight {
            index: 0,
            run: 0,
            run_seed,
            law: Law::DECOUPLED,
            phi_cmd_deg: 150.0,
        };
        flyer.fly(&flight, &none);
        let run = flyer.trajectory();
        let truth = run.column("plant.r_nue[1]").unwrap();
        let nav = run.column("nav.r_nue[1]").unwrap();
        let error: Vec<u64> = nav
            .iter()
            .zip(&truth)
            .map(|(n, t)| (n - t).to_bits())
            .collect();
        error
    };
    // WHEN two runs fly, and the first again
    let (first, second, again) = (estimate(11 << 40), estimate(12 << 40), estimate(11 << 40));
    // THEN their navigation errors differ, and a run's are the same on a replay
    assert_ne!(first, second);
    assert_eq!(first, again);
    assert!(first.iter().any(|b| f64::from_bits(*b) != 0.0));
}
