//! The shipped Model Exchange landing against the shipped Co-Simulation landing.
use cosim::master::{RunEnd, Simulation, Trajectory};
use cosim::system::SystemDescription;
use std::path::Path;

/// Flies `system`, its relative FMU paths in `fmu_dir`: every recorded row and how it ended,
/// and the simulation (for its Model Exchange event counts).
fn fly_in(system: SystemDescription, fmu_dir: &Path) -> (Trajectory, RunEnd, Simulation) {
    let mut simulation = Simulation::new(system, fmu_dir).unwrap();
    let mut trajectory = Trajectory {
        names: simulation.column_names().to_vec(),
        ..Default::default()
    };
    let end = simulation.run(&mut trajectory).unwrap();
    (trajectory, end, simulation)
}

#[test]
fn the_shipped_model_exchange_landing_touches_down_where_the_co_simulation_landing_does() {
    // GIVEN the shipped landing, and its twin with the plant as Model Exchange
    let fmu_dir = crate::common::fmu_dir();
    let run = |name: &str| {
        let (trajectory, end, _) = fly_in(lander::scenarios::load(name).unwrap(), &fmu_dir);
        (trajectory, end)
    };
    let (cs, cs_end) = run("landing");
    let (me, me_end) = run("landing-model-exchange");
    let touchdown = |end: &RunEnd| match end {
        RunEnd::Terminated { instance, time } if instance == "plant" => *time,
        other => panic!("not the plant's touchdown: {other:?}"),
    };
    // THEN both touch down at the same instant, to the solver's event tolerance (measured:
    // 4e-11 s apart, altitudes within 1.0e-10 m on the way down)
    let (t_cs, t_me) = (touchdown(&cs_end), touchdown(&me_end));
    assert!((t_cs - t_me).abs() < 1e-8, "{t_cs} vs {t_me}");
    assert_eq!(cs.times.len(), me.times.len());
    let (a, b) = (
        cs.column("plant.r_nue[2]").unwrap(),
        me.column("plant.r_nue[2]").unwrap(),
    );
    let worst = a
        .iter()
        .zip(&b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    assert!(worst < 1e-8, "altitudes differ by {worst} m");
    assert!(
        worst > 0.0,
        "the Model Exchange plant must not be the Co-Simulation plant"
    );
    // AND the last row is taken after the event update that ended the run: it carries the
    // touchdown the plant latched in that update, which the row before does not.
    let flag = me.column("plant.touchdown").unwrap();
    assert_eq!(flag[flag.len() - 1], 1.0, "the touchdown row");
    assert_eq!(flag[flag.len() - 2], 0.0, "the row before the event");
}
