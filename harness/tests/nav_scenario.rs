//! The three-FMU loop plant -> LanderNav -> GNC (`harness/scenarios/paper-nav.toml`): with
//! every navigation error off it flies the two-FMU paper scenario bit for bit, the SSD
//! written from it flies the same, and an error switched on does reach the GNC.
use crate::common;

use cosim::master::{RunEnd, Simulation, Trajectory};
use cosim::system::{toml_format, ParamValue, SystemDescription};
use lander::scenarios;
use std::path::{Path, PathBuf};

fn nav_scenario() -> SystemDescription {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/paper-nav.toml");
    toml_format::read(&path).unwrap()
}

/// `target/fmu` holding the two landers (checked by `common::fmu_dir`) and LanderNav.
fn fmu_dir() -> PathBuf {
    let dir = common::fmu_dir();
    assert!(
        dir.join("LanderNav.fmu").is_file(),
        "{} is missing: run `cargo xtask fmus` first",
        dir.join("LanderNav.fmu").display()
    );
    dir
}

fn fly(system: SystemDescription) -> (RunEnd, Trajectory) {
    let mut simulation = Simulation::new(system, &fmu_dir()).unwrap();
    let mut trajectory = Trajectory {
        names: simulation.column_names().to_vec(),
        ..Default::default()
    };
    let end = simulation.run(&mut trajectory).unwrap();
    (end, trajectory)
}

fn bits(column: &[f64]) -> Vec<u64> {
    column.iter().map(|v| v.to_bits()).collect()
}

/// Every column of `two` (the GNC's and the plant's outputs) is in `three` with the same
/// bits at every communication point; returns how many columns were compared.
fn assert_same_columns(two: &Trajectory, three: &Trajectory) -> usize {
    assert_eq!(bits(&two.times), bits(&three.times), "communication points");
    for name in &two.names {
        let expected = two.column(name).unwrap();
        let got = three
            .column(name)
            .unwrap_or_else(|| panic!("{name} is not recorded in the three-FMU run"));
        if let Some(k) = (0..expected.len()).find(|&k| expected[k].to_bits() != got[k].to_bits()) {
            panic!(
                "{name} differs at t = {}: {} (two FMUs) vs {} (three FMUs)",
                two.times[k], expected[k], got[k]
            );
        }
    }
    two.names.len()
}

#[test]
fn with_every_error_off_the_three_fmu_loop_flies_the_two_fmu_loop_bit_for_bit() {
    // GIVEN the paper scenario with and without LanderNav (defaults: every error off)
    let (end_two, two) = fly(scenarios::load("paper").unwrap());
    let (end_three, three) = fly(nav_scenario());
    // THEN the runs end alike and every GNC and plant output is bit-identical at every step
    assert_eq!(end_two, end_three);
    let compared = assert_same_columns(&two, &three);
    assert!(compared > 40, "{compared} columns");
    assert!(two.times.len() > 17_000, "{} points", two.times.len());
    assert!(
        two.names.iter().any(|n| n.starts_with("gnc."))
            && two.names.iter().any(|n| n.starts_with("plant.")),
        "{:?}",
        two.names
    );
    // AND what the GNC read is the plant's state itself
    for signal in ["r_nue[2]", "q_body_to_nue[4]", "omega_body[2]", "mass"] {
        let plant = three.column(&format!("plant.{signal}")).unwrap();
        let nav = three.column(&format!("nav.{signal}")).unwrap();
        assert_eq!(bits(&plant), bits(&nav), "{signal}");
    }
}

#[test]
fn a_navigation_error_switched_on_reaches_the_gnc() {
    // GIVEN 20 s of each loop, the three-FMU one with 1 mm of position noise
    let short = |mut system: SystemDescription| {
        system.stop_time = 20.0;
        system
    };
    let (_, two) = fly(short(scenarios::load("paper").unwrap()));
    let mut noisy = short(nav_scenario());
    assert!(noisy.set_parameter("nav", "r_nue_noise_sigma", ParamValue::Real(1e-3)));
    let (_, three) = fly(noisy);
    // THEN the estimate differs from the truth and the GNC's command from the two-FMU one
    let truth = three.column("plant.r_nue[2]").unwrap();
    let estimate = three.column("nav.r_nue[2]").unwrap();
    let offsets: Vec<f64> = truth.iter().zip(&estimate).map(|(t, e)| e - t).collect();
    assert!(offsets.iter().all(|d| d.abs() < 0.01), "within 10 sigma");
    assert!(offsets.iter().filter(|d| **d != 0.0).count() > offsets.len() / 2);
    let thrust_two = two.column("gnc.thrust_cmd").unwrap();
    let thrust_three = three.column("gnc.thrust_cmd").unwrap();
    assert_ne!(bits(&thrust_two), bits(&thrust_three));
}

#[test]
fn the_ssd_written_from_the_toml_flies_the_same_three_fmu_loop() {
    // GIVEN the SSD of paper-nav.toml, as the SSP writer makes it
    let system = nav_scenario();
    let ssd = scenarios::ssd_for(&system, &fmu_dir()).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("paper-nav.ssd");
    std::fs::write(&path, ssd).unwrap();
    // WHEN both fly 20 s
    let short = |mut system: SystemDescription| {
        system.stop_time = 20.0;
        system
    };
    let (_, from_toml) = fly(short(system));
    let (_, from_ssd) = fly(short(scenarios::load(path.to_str().unwrap()).unwrap()));
    // THEN they are the same run, bit for bit, nav included
    assert_eq!(from_toml.names, from_ssd.names);
    assert!(from_toml.names.iter().any(|n| n.starts_with("nav.")));
    assert_same_columns(&from_toml, &from_ssd);
}

#[test]
fn under_jacobi_ordering_the_estimate_is_one_step_late() {
    // GIVEN the three-FMU loop exchanged Jacobi-style (every input from the outputs read
    // after the previous step)
    let mut system = nav_scenario();
    system.stop_time = 5.0;
    system.ordering = cosim::system::Ordering::Jacobi;
    let (_, run) = fly(system);
    // THEN what LanderNav shows at t_k+1 is the plant's state at t_k (up to the last
    // point, which the master records after one more exchange)
    let plant = run.column("plant.r_nue[2]").unwrap();
    let nav = run.column("nav.r_nue[2]").unwrap();
    let n = plant.len() - 1;
    assert_eq!(bits(&nav[1..n]), bits(&plant[..n - 1]));
    assert_ne!(bits(&nav[1..n]), bits(&plant[1..n]), "the lander moves");
}
