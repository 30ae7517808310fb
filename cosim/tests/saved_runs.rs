//! Saved runs: the paper loop saved at a communication point and continued by another
//! simulation records, from that point on, the uninterrupted run's rows bit for bit, in
//! FMI 2.0 and 3.0 and under either ordering; and files that cannot continue a run (damaged,
//! of other FMUs, of a Model Exchange instance) are refused before the run, naming why.
use crate::common::{fmu_dir, lander_loop};
use cosim::master::{
    Checkpoints, MasterError, RunEnd, SaveRequest, SavedError, SavedRun, Simulation, Trajectory,
};
use cosim::system::{Ordering, SystemDescription};
use std::path::Path;

/// The paper loop over 20 s, with the FMUs of FMI `version`.
fn paper_loop(version: &str, ordering: Ordering) -> SystemDescription {
    let mut system = lander_loop();
    system.stop_time = 20.0;
    system.ordering = ordering;
    if version == "3.0" {
        for instance in &mut system.instances {
            instance.fmu = Path::new("fmi3").join(&instance.fmu);
        }
    }
    system
}

fn fly(system: SystemDescription, checkpoints: Checkpoints) -> (Trajectory, RunEnd, Option<f64>) {
    let mut simulation = Simulation::new(system, &fmu_dir()).unwrap();
    simulation
        .set_checkpoints(checkpoints)
        .unwrap_or_else(|e| panic!("{e}"));
    let mut trajectory = Trajectory {
        names: simulation.column_names().to_vec(),
        ..Default::default()
    };
    let end = simulation
        .run(&mut trajectory)
        .unwrap_or_else(|e| panic!("{e}"));
    (trajectory, end, simulation.saved_at())
}

fn bits(values: &[f64]) -> Vec<u64> {
    values.iter().map(|v| v.to_bits()).collect()
}

fn save(path: &Path, at: Option<f64>) -> Checkpoints {
    Checkpoints {
        resume: None,
        save: Some(SaveRequest {
            path: path.to_owned(),
            at,
        }),
    }
}

fn resume(path: &Path) -> Checkpoints {
    Checkpoints {
        resume: Some(SavedRun::read(path).unwrap_or_else(|e| panic!("{e}"))),
        save: None,
    }
}

#[test]
fn a_continued_paper_loop_records_the_uninterrupted_rows_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    for version in ["2.0", "3.0"] {
        for ordering in [Ordering::GaussSeidel, Ordering::Jacobi] {
            let case = format!("FMI {version}, {ordering:?}");
            let file = dir.path().join("paper.state");
            // GIVEN an uninterrupted run that saves itself at t = 7.5 s on its way
            let (whole, whole_end, saved_at) =
                fly(paper_loop(version, ordering), save(&file, Some(7.5)));
            assert_eq!(saved_at, Some(7.5), "{case}");
            // WHEN another simulation continues from the file
            let (continued, end, _) = fly(paper_loop(version, ordering), resume(&file));
            // THEN its rows are the uninterrupted run's from 7.5 s on, bit for bit
            let from = whole.times.iter().position(|&t| t == 7.5).unwrap();
            assert_eq!(continued.times[0], 7.5, "{case}");
            assert_eq!(bits(&continued.times), bits(&whole.times[from..]), "{case}");
            let width = whole.names.len();
            assert_eq!(
                bits(&continued.values),
                bits(&whole.values[from * width..]),
                "{case}"
            );
            assert_eq!(end, whole_end, "{case}");
        }
    }
}

#[test]
fn a_run_saved_at_its_end_continues_into_a_shorter_or_equal_one_only_where_the_fmus_allow() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("end.state");
    let mut short = paper_loop("2.0", Ordering::GaussSeidel);
    short.stop_time = 5.0;
    let (whole, _, saved_at) = fly(short.clone(), save(&file, None));
    assert_eq!(saved_at, Some(5.0));
    // Continued to its own stop time: the last row again, the same.
    let (continued, _, _) = fly(short.clone(), resume(&file));
    assert_eq!(continued.times, [5.0]);
    let width = whole.names.len();
    assert_eq!(
        bits(&continued.values),
        bits(&whole.values[whole.values.len() - width..])
    );
    // Beyond it: the FMUs were told the stop time 5 s, so that is refused before the run.
    let mut longer = short;
    longer.stop_time = 10.0;
    let error = refused(longer, &file);
    assert!(error.contains("stop time"), "{error}");
}

/// The error of continuing `system` from `file`, which must come before the run.
fn refused(system: SystemDescription, file: &Path) -> String {
    let mut simulation = Simulation::new(system, &fmu_dir()).unwrap();
    match SavedRun::read(file) {
        Err(error) => error.to_string(),
        Ok(saved) => match simulation.set_checkpoints(Checkpoints {
            resume: Some(saved),
            save: None,
        }) {
            Err(error @ MasterError::Checkpoint { .. }) => error.to_string(),
            Err(other) => panic!("wrong error: {other}"),
            Ok(()) => panic!("a saved run that cannot continue this system was accepted"),
        },
    }
}

#[test]
fn a_saved_run_of_other_fmus_or_another_system_is_refused_naming_what_differs() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("fmi2.state");
    let mut system = paper_loop("2.0", Ordering::GaussSeidel);
    system.stop_time = 1.0;
    fly(system.clone(), save(&file, Some(0.5)));

    let mut fmi3 = paper_loop("3.0", Ordering::GaussSeidel);
    fmi3.stop_time = 1.0;
    let error = refused(fmi3, &file);
    assert!(error.contains("instance 'gnc'"), "{error}");
    assert!(
        error.contains("FMI 2.0") && error.contains("FMI 3.0"),
        "{error}"
    );

    let mut renamed = system.clone();
    renamed.name = "another".into();
    let error = refused(renamed, &file);
    assert!(error.contains("system 'lander-loop'"), "{error}");

    let mut jacobi = system.clone();
    jacobi.ordering = Ordering::Jacobi;
    let error = refused(jacobi, &file);
    assert!(error.contains("gauss-seidel ordering"), "{error}");

    let mut recorded = system;
    recorded.record = Some(vec!["plant.r_nue".into()]);
    let error = refused(recorded, &file);
    assert!(error.contains("--record"), "{error}");
}

#[test]
fn a_damaged_or_foreign_file_is_refused_naming_the_file_and_the_fault() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("damaged.state");
    let mut system = paper_loop("2.0", Ordering::GaussSeidel);
    system.stop_time = 1.0;
    fly(system.clone(), save(&file, Some(0.5)));
    let mut bytes = std::fs::read(&file).unwrap();
    let middle = bytes.len() / 2;
    bytes[middle] ^= 1;
    std::fs::write(&file, &bytes).unwrap();
    let error = refused(system.clone(), &file);
    assert!(error.contains("damaged.state"), "{error}");
    assert!(error.contains("checksum"), "{error}");

    std::fs::write(&file, &bytes[..bytes.len() - 3]).unwrap();
    assert!(refused(system.clone(), &file).contains("truncated"));

    std::fs::write(&file, "time,plant.r_nue[2]\n0,800\n").unwrap();
    let error = refused(system.clone(), &file);
    assert!(error.contains("not a saved run"), "{error}");

    let missing = dir.path().join("missing.state");
    let error = SavedRun::read(&missing).unwrap_err();
    assert!(matches!(error, SavedError::Read { .. }));
    assert!(error.to_string().contains("missing.state"), "{error}");
}

#[test]
fn model_exchange_instances_and_save_points_off_the_grid_are_refused_before_the_run() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("never.state");
    let mut system = paper_loop("2.0", Ordering::GaussSeidel);
    system.instance_mut("plant").unwrap().model_exchange =
        Some(cosim::master::SolverSettings::default());
    let mut simulation = Simulation::new(system, &fmu_dir()).unwrap();
    let error = simulation
        .set_checkpoints(save(&file, None))
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("instance 'plant' runs as Model Exchange"),
        "{error}"
    );

    let mut simulation =
        Simulation::new(paper_loop("2.0", Ordering::GaussSeidel), &fmu_dir()).unwrap();
    let error = simulation
        .set_checkpoints(save(&file, Some(7.505)))
        .unwrap_err()
        .to_string();
    assert!(error.contains("not a communication point"), "{error}");
    let error = simulation
        .set_checkpoints(save(&file, Some(25.0)))
        .unwrap_err()
        .to_string();
    assert!(error.contains("after this run's stop time"), "{error}");
    assert!(!file.exists());
}

#[test]
fn a_continued_run_saves_again_and_its_continuation_is_still_the_uninterrupted_run() {
    let dir = tempfile::tempdir().unwrap();
    let (first, second) = (
        dir.path().join("first.state"),
        dir.path().join("second.state"),
    );
    let system = paper_loop("3.0", Ordering::GaussSeidel);
    let (whole, _, _) = fly(system.clone(), save(&first, Some(5.0)));
    let mut again = resume(&first);
    again.save = save(&second, Some(12.0)).save;
    let (_, _, saved_at) = fly(system.clone(), again);
    assert_eq!(saved_at, Some(12.0));
    let (last, _, _) = fly(system.clone(), resume(&second));
    let from = whole.times.iter().position(|&t| t == 12.0).unwrap();
    let width = whole.names.len();
    assert_eq!(bits(&last.values), bits(&whole.values[from * width..]));
    // A save point before the point a run continues from is none of its points.
    let mut early = resume(&first);
    early.save = save(&second, Some(2.0)).save;
    let mut simulation = Simulation::new(system, &fmu_dir()).unwrap();
    let error = simulation.set_checkpoints(early).unwrap_err().to_string();
    assert!(
        error.contains("before the first communication point of this run, t = 5"),
        "{error}"
    );
}

/// Engine faults on the paper loop around a save point at 7.5 s: two before it on the same
/// variable (the later must win in the continued run too), one due at it (7.495 s applies at
/// the point 7.5 s, after the save), one after it.
const FAULTS: [(&str, f64, f64); 4] = [
    ("first", 3.0, 0.95),
    ("second", 5.004, 0.97),
    ("at-the-save-point", 7.495, 0.96),
    ("after", 12.0, 0.9),
];

fn with_faults(version: &str, faults: &[(&str, f64, f64)]) -> SystemDescription {
    let mut system = paper_loop(version, Ordering::GaussSeidel);
    system.stop_time = 15.0;
    system.events = crate::common::engine_faults(faults);
    system
}

#[test]
fn events_before_at_and_after_the_save_point_give_the_uninterrupted_run_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    for version in ["2.0", "3.0"] {
        let file = dir.path().join(format!("faults-{version}.state"));
        // GIVEN a run with the four faults, saved at 7.5 s on its way
        let (whole, _, saved_at) = fly(with_faults(version, &FAULTS), save(&file, Some(7.5)));
        assert_eq!(saved_at, Some(7.5));
        // WHEN another simulation of the same scenario continues from the file
        let (continued, _, _) = fly(with_faults(version, &FAULTS), resume(&file));
        // THEN its rows are the uninterrupted run's from 7.5 s on, bit for bit: the faults
        // before the point are in the FMU states, not applied again; the one due at the point
        // and the one after are applied once, where the uninterrupted run applied them
        let from = whole.times.iter().position(|&t| t == 7.5).unwrap();
        let width = whole.names.len();
        assert_eq!(
            bits(&continued.times),
            bits(&whole.times[from..]),
            "{version}"
        );
        assert_eq!(
            bits(&continued.values),
            bits(&whole.values[from * width..]),
            "FMI {version}"
        );
        // AND the faults changed the flight (what the comparison above tells apart): without
        // the last two the rows after the point differ
        let (unfaulted, _, _) = fly(with_faults(version, &FAULTS[..2]), Checkpoints::default());
        let thrust = whole.column_index("plant.thrust_actual").unwrap();
        let next = from + 1;
        assert_ne!(
            unfaulted.values[next * width + thrust],
            whole.values[next * width + thrust],
            "FMI {version}: the fault at the save point must change the step from it"
        );
    }
}

#[test]
fn a_continuation_whose_events_before_the_save_point_differ_is_refused_naming_them() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("faults.state");
    fly(with_faults("2.0", &FAULTS), save(&file, Some(7.5)));
    // An event before the point moved, given another value, left out or added: the FMU states
    // hold what the saved run applied, so the continued run would silently differ.
    let mut moved = FAULTS;
    moved[0].1 = 4.0;
    let mut revalued = FAULTS;
    revalued[1].2 = 0.5;
    let mut added = FAULTS.to_vec();
    added.insert(0, ("early", 1.0, 0.99));
    for (case, faults) in [
        ("moved", moved.to_vec()),
        ("revalued", revalued.to_vec()),
        ("left out", FAULTS[1..].to_vec()),
        ("added", added),
    ] {
        let error = refused(with_faults("2.0", &faults), &file);
        assert!(
            error.contains("events") && error.contains("before t = 7.5 s"),
            "{case}: {error}"
        );
    }
    // Those due at or after the point are the continued run's own: another value or time
    // there is a run branching from the saved point, accepted.
    let mut branched = FAULTS;
    branched[2].2 = 0.5;
    branched[3].1 = 13.0;
    let mut simulation = Simulation::new(with_faults("2.0", &branched), &fmu_dir()).unwrap();
    simulation
        .set_checkpoints(resume(&file))
        .unwrap_or_else(|e| panic!("{e}"));
}

#[test]
fn an_event_due_at_the_start_of_a_shortened_last_step_is_applied_once_in_a_continuation() {
    // GIVEN a run to 10.005 s, its last step 5 ms from 10 s, saved at 10 s, and a fault at
    // 9.993 s: due at the point 10 s (the first at or after it), so not yet in the saved state
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("last-step.state");
    let mut system = with_faults("2.0", &[("in-the-last-step", 9.993, 0.5)]);
    system.stop_time = 10.005;
    let (whole, _, saved_at) = fly(system.clone(), save(&file, Some(10.0)));
    assert_eq!(saved_at, Some(10.0));
    // WHEN continued
    let (continued, _, _) = fly(system, resume(&file));
    // THEN the continued rows are the uninterrupted ones: the fault applied at 10 s
    let width = whole.names.len();
    assert_eq!(continued.times, [10.0, 10.005]);
    assert_eq!(
        bits(&continued.values),
        bits(&whole.values[whole.values.len() - 2 * width..])
    );
    let thrust = whole.column("plant.thrust_actual").unwrap();
    let command = whole.column("gnc.thrust_cmd").unwrap();
    let last = thrust.len() - 1;
    assert!((thrust[last] / command[last] - 0.5).abs() < 1e-12);
}
