//! Model Exchange import: LanderPlant driven through its Model Exchange interface by the
//! master's adaptive solver (`ode-solver`), against the analytic free fall and against the
//! same plant as Co-Simulation in the closed loop of the paper scenario.
use crate::common::{fmu_dir, lander_loop, unzip_to, zip_dir};
use cosim::master::{RunEnd, Simulation, Trajectory};
use cosim::system::{toml_format, SystemDescription};
use std::path::Path;

const G_MOON: f64 = 1.62;

fn free_fall(fmu: &Path, extra: &str) -> SystemDescription {
    let text = format!(
        r#"
name = "free-fall"
stop_time = 40.0
step_size = 0.1

[[instance]]
name = "plant"
fmu = "{}"
{extra}

record = ["plant.r_nue[2]", "plant.v_nue[2]"]
"#,
        fmu.display()
    );
    // `record` must be a top-level key: put it before the instance table.
    let (head, instance) = text.split_once("[[instance]]").unwrap();
    let (instance, record) = instance.split_once("record").unwrap();
    let text = format!("{head}record{record}\n[[instance]]{instance}");
    toml_format::parse(&text, Path::new("free-fall.toml")).unwrap()
}

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

/// An error and its sources, joined as `{:#}` prints them.
fn chain(error: &dyn std::error::Error) -> String {
    std::iter::successors(Some(error), |e| e.source())
        .map(|e| e.to_string())
        .collect::<Vec<_>>()
        .join(": ")
}

/// The free fall from an absolute FMU path.
fn fly(system: SystemDescription) -> (Trajectory, RunEnd) {
    let (trajectory, end, simulation) = fly_in(system, Path::new("/"));
    // The free fall has one event: the touchdown, found by the plant's event indicator.
    let events = simulation.model_exchange_events();
    assert_eq!(events.len(), 1);
    assert_eq!(
        events[0],
        (
            "plant",
            cosim::master::EventCounts {
                state: 1,
                time: 0,
                step: 0
            }
        )
    );
    (trajectory, end)
}

/// The free-fall figures: 800 - 0.81 t^2 m at every recorded row before touchdown, to 1e-6 m,
/// and the touchdown at sqrt(800 / 0.81) s, to 1e-6 s.
fn assert_free_fall(trajectory: &Trajectory, end: &RunEnd, what: &str) {
    let t_touchdown = (800.0 / (0.5 * G_MOON)).sqrt();
    assert!((t_touchdown - 31.426968053).abs() < 1e-9);
    let RunEnd::Terminated { instance, time } = end else {
        panic!("{what}: the run ended with {end:?}, not the plant's touchdown");
    };
    assert_eq!(instance, "plant");
    assert!(
        (time - t_touchdown).abs() < 1e-6,
        "{what}: touchdown at {time} s, analytic {t_touchdown} s"
    );
    let altitude = trajectory.column("plant.r_nue[2]").unwrap();
    let mut worst = 0.0f64;
    for (t, h) in trajectory.times.iter().zip(&altitude) {
        if *t < t_touchdown - 1e-6 {
            worst = worst.max((h - (800.0 - 0.5 * G_MOON * t * t)).abs());
        }
    }
    assert!(
        worst < 1e-6,
        "{what}: altitude off the parabola by {worst:e} m"
    );
    assert_eq!(
        trajectory.times.len(),
        316,
        "{what}: rows to t = 31.4 and the touchdown row"
    );
    println!(
        "{what}: touchdown at {time:.12} s ({:+e} s), altitude error {worst:e} m",
        time - t_touchdown
    );
}

#[test]
fn the_fmi3_plants_free_fall_as_model_exchange_follows_the_parabola() {
    // GIVEN the FMI 3.0 plant alone, as Model Exchange
    let fmu = fmu_dir().join("fmi3/LanderPlant.fmu");
    let (trajectory, end) = fly(free_fall(&fmu, "interface = \"model-exchange\""));
    // THEN the same figures as FMI 2.0
    assert_free_fall(&trajectory, &end, "FMI 3.0");
}

#[test]
fn the_plants_free_fall_as_model_exchange_follows_the_parabola_with_either_solver() {
    let fmu = fmu_dir().join("LanderPlant.fmu");
    // BDF is of order 5 at most with error estimates per step, so it needs a tighter
    // tolerance than Tsitouras 5(4) for the same figures (at the defaults, 1e-8 and 1e-10,
    // its touchdown is 5.6e-7 s early and its altitude up to 2.8e-5 m off).
    for (solver, tolerances) in [
        ("tsit45", ""),
        (
            "bdf",
            "relative_tolerance = 1e-10\nabsolute_tolerance = 1e-10",
        ),
    ] {
        // GIVEN the plant alone, engines off at 800 m, selected as Model Exchange
        let system = free_fall(
            &fmu,
            &format!("interface = \"model-exchange\"\nsolver = \"{solver}\"\n{tolerances}"),
        );
        // WHEN the master integrates it between the 0.1 s communication points
        let (trajectory, end) = fly(system);
        // THEN the figures of the analytic free fall hold
        assert_free_fall(&trajectory, &end, solver);
    }
}

/// The FMU with its `<CoSimulation>` element removed from the description.
fn model_exchange_only(fmu: &str, dir: &Path) -> std::path::PathBuf {
    let unpacked = dir.join("unpacked");
    unzip_to(&fmu_dir().join(fmu), &unpacked);
    let description_path = unpacked.join("modelDescription.xml");
    let description = std::fs::read_to_string(&description_path).unwrap();
    let start = description.find("<CoSimulation").unwrap();
    // FMI 2.0 writes an empty element, FMI 3.0 may write one with content.
    let end = match description[start..].find("</CoSimulation>") {
        Some(close) => start + close + "</CoSimulation>".len(),
        None => start + description[start..].find("/>").unwrap() + 2,
    };
    let me_only = format!("{}{}", &description[..start], &description[end..]);
    assert!(!me_only.contains("<CoSimulation") && me_only.contains("<ModelExchange"));
    std::fs::write(&description_path, me_only).unwrap();
    let out = dir.join("LanderPlantME.fmu");
    zip_dir(&unpacked, &out);
    out
}

#[test]
fn an_fmi3_model_exchange_only_fmu_runs_with_the_solver() {
    let dir = tempfile::tempdir().unwrap();
    let fmu = model_exchange_only("fmi3/LanderPlant.fmu", dir.path());
    let (trajectory, end) = fly(free_fall(&fmu, "interface = \"model-exchange\""));
    assert_free_fall(&trajectory, &end, "FMI 3.0 Model Exchange only");
    // Naming no interface, it runs through the only one it declares.
    let (trajectory, end) = fly(free_fall(&fmu, ""));
    assert_free_fall(&trajectory, &end, "FMI 3.0 Model Exchange only, unnamed");
    let error = Simulation::new(
        free_fall(&fmu, "interface = \"co-simulation\""),
        Path::new("/"),
    )
    .err()
    .expect("an FMI 3.0 Model Exchange only FMU cannot be a Co-Simulation instance");
    let chain = chain(&error);
    assert!(chain.contains("no <CoSimulation> element"), "{chain}");
}

#[test]
fn a_model_exchange_only_fmu_runs_with_the_solver_unasked_and_is_refused_as_co_simulation() {
    // GIVEN LanderPlant with its <CoSimulation> element removed
    let dir = tempfile::tempdir().unwrap();
    let fmu = model_exchange_only("LanderPlant.fmu", dir.path());

    // WHEN it runs as Model Exchange, THEN the free-fall figures hold
    let (trajectory, end) = fly(free_fall(&fmu, "interface = \"model-exchange\""));
    assert_free_fall(&trajectory, &end, "Model Exchange only");

    // AND naming no interface, it runs through the only one it declares
    let (unnamed, end) = fly(free_fall(&fmu, ""));
    assert_free_fall(&unnamed, &end, "Model Exchange only, unnamed");

    // AND named Co-Simulation it is refused at instantiation, saying why
    let error = Simulation::new(
        free_fall(&fmu, "interface = \"co-simulation\""),
        Path::new("/"),
    )
    .err()
    .expect("a Model Exchange only FMU cannot be a Co-Simulation instance");
    let chain = chain(&error);
    assert!(chain.contains("no <CoSimulation> element"), "{chain}");
}

#[test]
fn solver_settings_without_model_exchange_and_unknown_solvers_are_refused_together() {
    let fmu = fmu_dir().join("LanderPlant.fmu");
    let text = format!(
        "name = \"x\"\nstop_time = 1.0\n[[instance]]\nname = \"plant\"\nfmu = \"{}\"\nsolver = \
         \"bdf\"\n[[instance]]\nname = \"other\"\nfmu = \"{}\"\ninterface = \
         \"model-exchange\"\nsolver = \"euler\"\nrelative_tolerance = -1.0\n",
        fmu.display(),
        fmu.display()
    );
    let error = toml_format::parse(&text, Path::new("bad.toml"))
        .unwrap_err()
        .to_string();
    for expected in [
        "instance 'plant': solver is a Model Exchange setting",
        "solver = \"euler\" is neither",
        "relative_tolerance = -1 must be a positive number",
    ] {
        assert!(error.contains(expected), "{error}");
    }
}

#[test]
fn the_paper_loop_with_the_plant_as_model_exchange_matches_the_co_simulation_loop() {
    paper_loop_model_exchange_against_co_simulation(false);
}

#[test]
fn the_fmi3_paper_loop_with_the_plant_as_model_exchange_matches_the_co_simulation_loop() {
    paper_loop_model_exchange_against_co_simulation(true);
}

fn paper_loop_model_exchange_against_co_simulation(fmi3: bool) {
    // GIVEN the paper scenario, once as shipped and once with the plant as Model Exchange
    let mut shipped = lander_loop();
    if fmi3 {
        for instance in &mut shipped.instances {
            instance.fmu = Path::new("fmi3").join(&instance.fmu);
        }
    }
    let mut model_exchange = shipped.clone();
    model_exchange.instance_mut("plant").unwrap().model_exchange =
        Some(cosim::master::SolverSettings::default());
    let fmu_dir = fmu_dir();
    let run = |system: SystemDescription| {
        let (trajectory, end, _) = fly_in(system, &fmu_dir);
        (trajectory, end)
    };
    let (cs, cs_end) = run(shipped);
    let (me, me_end) = run(model_exchange);
    // THEN both reach the stop time on the same grid
    assert_eq!(cs_end, me_end);
    assert_eq!(cs.times, me.times);
    // AND the trajectories agree within the tolerance stated in docs/model-exchange.md:
    // the Co-Simulation plant integrates with fixed-step RK4 inside each 0.01 s step, the
    // Model Exchange plant with Tsitouras 5(4) at a relative tolerance of 1e-8.
    let mut worst_position = 0.0f64;
    let mut worst_velocity = 0.0f64;
    for axis in 1..=3 {
        let r = format!("plant.r_nue[{axis}]");
        let v = format!("plant.v_nue[{axis}]");
        for (a, b) in cs.column(&r).unwrap().iter().zip(me.column(&r).unwrap()) {
            worst_position = worst_position.max((a - b).abs());
        }
        for (a, b) in cs.column(&v).unwrap().iter().zip(me.column(&v).unwrap()) {
            worst_velocity = worst_velocity.max((a - b).abs());
        }
    }
    println!(
        "paper loop (FMI 3.0: {fmi3}), CS vs ME plant: position {worst_position:e} m, \
         velocity {worst_velocity:e} m/s"
    );
    assert!(
        worst_position < 1e-3,
        "position differs by {worst_position} m"
    );
    assert!(
        worst_velocity < 1e-4,
        "velocity differs by {worst_velocity} m/s"
    );
    assert!(
        worst_position > 0.0,
        "the Model Exchange plant must not be the CS plant"
    );
}
