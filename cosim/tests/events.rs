//! Scenario events: a tunable parameter of the Oscillator changed mid-run, in FMI 2.0 and
//! 3.0 Co-Simulation and FMI 3.0 Model Exchange, against the analytic trajectory; every
//! problem of a scenario's events refused at load at once, each naming event and value.
use crate::common::{fmu_dir, oscillator_fmu};
use cosim::master::{RunEnd, Simulation, Trajectory};
use cosim::system::{toml_format, SystemDescription};
use std::path::Path;

/// The event (`STIFFEN`) is due at 0.503 s: on the 0.01 s grid it applies at 0.51 s, the
/// first point at or after it, not at the nearest one.
const APPLIED_S: f64 = 0.51;

/// A free mass at x = 1 (k = 0, c = 0) until the event sets k = 4 N/m: from the point it is
/// applied on, x(t) = cos(2 (t - t_e)) exactly.
fn scenario(fmu: &Path, extra_instance: &str, events: &str) -> SystemDescription {
    let text = format!(
        r#"
name = "events"
stop_time = 2.0
step_size = 0.01
record = ["osc.x"]

[[instance]]
name = "osc"
fmu = "{}"
{extra_instance}
parameters = {{ x0 = 1.0, k = 0.0, c = 0.0, substeps = 1000 }}

{events}
"#,
        fmu.display()
    );
    toml_format::parse(&text, Path::new("events.toml")).unwrap_or_else(|e| panic!("{e}"))
}

const STIFFEN: &str = r#"
[[event]]
name = "stiffen"
time = 0.503
set = "osc.k"
value = 4.0
"#;

fn fly(system: SystemDescription) -> Trajectory {
    let mut simulation = Simulation::new(system, Path::new("/")).unwrap();
    let mut trajectory = Trajectory {
        names: simulation.column_names().to_vec(),
        ..Default::default()
    };
    assert_eq!(simulation.run(&mut trajectory).unwrap(), RunEnd::Completed);
    trajectory
}

/// x stays 1 up to and including the row of the point the event applies at (that row shows
/// the values before it), then follows the cosine from that point.
fn assert_stiffened_at_the_point(trajectory: &Trajectory, tolerance: f64) {
    let x = trajectory.column("osc.x").unwrap();
    let mut checked_after = 0;
    for (&t, &x) in trajectory.times.iter().zip(&x) {
        if t <= APPLIED_S + 1e-12 {
            assert_eq!(x, 1.0, "t = {t}: before the event x must stay 1");
        } else {
            let expected = libm::cos(2.0 * (t - APPLIED_S));
            assert!(
                (x - expected).abs() < tolerance,
                "t = {t}: x = {x}, cos(2 (t - {APPLIED_S})) = {expected}"
            );
            checked_after += 1;
        }
    }
    assert!(checked_after > 100, "{checked_after} rows after the event");
}

#[test]
fn an_event_changes_a_tunable_parameter_from_its_communication_point_in_fmi2() {
    let fmu = oscillator_fmu();
    assert_stiffened_at_the_point(&fly(scenario(&fmu.path, "", STIFFEN)), 1e-9);
}

#[test]
fn an_event_changes_a_tunable_parameter_from_its_communication_point_in_fmi3() {
    let fmu = fmu_dir().join("fmi3/Oscillator.fmu");
    assert_stiffened_at_the_point(&fly(scenario(&fmu, "", STIFFEN)), 1e-9);
}

#[test]
fn an_event_on_a_model_exchange_instance_is_set_in_event_mode_between_solver_steps() {
    let fmu = fmu_dir().join("fmi3/Oscillator.fmu");
    let system = scenario(&fmu, "interface = \"model-exchange\"", STIFFEN);
    // The parameters table must follow the interface key, not precede it: same instance.
    assert!(system.instances[0].model_exchange.is_some());
    assert_stiffened_at_the_point(&fly(system), 1e-6);
}

#[test]
fn without_the_event_the_mass_stays_put() {
    // What the tests above tell apart: the event ignored leaves x = 1 throughout.
    let fmu = oscillator_fmu();
    let x = fly(scenario(&fmu.path, "", "")).column("osc.x").unwrap();
    assert!(x.iter().all(|&x| x == 1.0));
}

#[test]
fn every_problem_of_the_events_is_refused_at_load_at_once_naming_event_and_value() {
    let fmu = oscillator_fmu();
    let events = r#"
[[event]]
name = "ghost"
time = 0.5
set = "other.k"
value = 1.0

[[event]]
name = "typo"
time = 0.5
set = "osc.kk"
value = 1.0

[[event]]
name = "fixed"
time = 0.5
set = "osc.x0"
value = 2.0

[[event]]
name = "output"
time = 0.5
set = "osc.x"
value = 2.0

[[event]]
name = "boolean"
time = 0.5
set = "osc.k"
value = true

[[event]]
name = "late"
time = 5.0
set = "osc.k"
value = 1.0

[[event]]
name = "nan"
time = 0.5
set = "osc.c"
value = nan

[[event]]
name = "negative"
time = 0.5
set = "osc.k"
value = -1.0
"#;
    let system = scenario(&fmu.path, "", events);
    let error = match Simulation::new(system, Path::new("/")) {
        Ok(_) => panic!("events with problems were accepted"),
        Err(e) => e.to_string(),
    };
    for expected in [
        "event 'ghost' (other.k = 1): unknown instance 'other'",
        "event 'typo' (osc.kk = 1)",
        "event 'fixed' (osc.x0 = 2): 'x0' is neither a tunable parameter nor an input",
        "event 'output' (osc.x = 2)",
        "event 'boolean' (osc.k = true)",
        "event 'late' (osc.k = 1): time 5 s is outside [start_time, stop_time] = [0, 2] s",
        "event 'nan' (osc.c = NaN): value NaN is not a finite number",
        "event 'negative' (osc.k = -1)",
    ] {
        assert!(
            error.contains(expected),
            "missing «{expected}» in:\n{error}"
        );
    }
}

#[test]
fn an_event_on_a_connected_input_is_refused_rather_than_overridden() {
    let fmu = oscillator_fmu();
    let text = format!(
        r#"
name = "connected"
stop_time = 1.0
[[instance]]
name = "a"
fmu = "{0}"
[[instance]]
name = "b"
fmu = "{0}"
[[connection]]
from = "a.x"
to = "b.u"
[[event]]
name = "push"
time = 0.5
set = "b.u"
value = 3.0
"#,
        fmu.path.display()
    );
    let system = toml_format::parse(&text, Path::new("connected.toml")).unwrap();
    let error = match Simulation::new(system, Path::new("/")) {
        Ok(_) => panic!("an event on a connected input was accepted"),
        Err(e) => e.to_string(),
    };
    assert!(
        error.contains("event 'push' (b.u = 3)") && error.contains("connected from 'a.x'"),
        "{error}"
    );
}

#[test]
fn an_event_in_the_last_step_or_with_a_text_value_is_refused() {
    let fmu = oscillator_fmu();
    let text = r#"
[[event]]
name = "at-stop"
time = 2.0
set = "osc.k"
value = 1.0
"#;
    let error = match Simulation::new(scenario(&fmu.path, "", text), Path::new("/")) {
        Ok(_) => panic!("an event at the stop time was accepted"),
        Err(e) => e.to_string(),
    };
    assert!(error.contains("would change nothing"), "{error}");
    let text = format!(
        r#"
name = "text"
stop_time = 1.0
[[instance]]
name = "osc"
fmu = "{}"
[[event]]
name = "label"
time = 0.5
set = "osc.label"
value = "x"
"#,
        fmu.path.display()
    );
    let error = toml_format::parse(&text, Path::new("text.toml"))
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("event 'label': value \"x\" is not a number"),
        "{error}"
    );
}

/// LanderPlant falling from 800 m, measured by LanderSensors, estimated by LanderFilter;
/// `events` thrown on the sensors.
fn navigation(events: &str) -> SystemDescription {
    let mut connections = String::new();
    for (from, to) in [
        ("plant.r_nue", "sensors.r_nue"),
        ("plant.v_nue", "sensors.v_nue"),
        ("plant.q_body_to_nue", "sensors.q_body_to_nue"),
        ("plant.omega_body", "sensors.omega_body"),
        ("plant.specific_force_body", "sensors.specific_force_body"),
        ("sensors.accel_body_meas", "filter.accel_body_meas"),
        ("sensors.gyro_body_meas", "filter.gyro_body_meas"),
        ("sensors.altimeter_range", "filter.altimeter_range"),
        ("sensors.altimeter_valid", "filter.altimeter_valid"),
        (
            "sensors.velocimeter_los_velocity",
            "filter.velocimeter_los_velocity",
        ),
        ("sensors.velocimeter_valid_1", "filter.velocimeter_valid_1"),
        ("sensors.velocimeter_valid_2", "filter.velocimeter_valid_2"),
        ("sensors.velocimeter_valid_3", "filter.velocimeter_valid_3"),
    ] {
        connections += &format!("[[connection]]\nfrom = \"{from}\"\nto = \"{to}\"\n");
    }
    let text = format!(
        r#"
name = "navigation"
stop_time = 20.0
step_size = 0.01
record = ["filter.covariance_diag", "filter.altimeter_dof", "filter.velocimeter_dof"]
[[instance]]
name = "plant"
fmu = "LanderPlant.fmu"
[[instance]]
name = "sensors"
fmu = "LanderSensors.fmu"
parameters = {{ seed = 3 }}
[[instance]]
name = "filter"
fmu = "LanderFilter.fmu"
parameters = {{ "r0_nue[2]" = 800.0 }}
{connections}
{events}
"#
    );
    toml_format::parse(&text, Path::new("navigation.toml")).unwrap_or_else(|e| panic!("{e}"))
}

fn fly_navigation(events: &str) -> Trajectory {
    let mut simulation = Simulation::new(navigation(events), &fmu_dir()).unwrap();
    let mut trajectory = Trajectory {
        names: simulation.column_names().to_vec(),
        ..Default::default()
    };
    simulation.run(&mut trajectory).unwrap();
    trajectory
}

#[test]
fn a_sensor_failure_thrown_by_an_event_makes_the_filter_coast_and_say_so() {
    // GIVEN both sensors failing at 5 s (the altimeter alone would leave the velocimeter's
    // updates, which bound the velocity but not the position)
    let failed = fly_navigation(
        r#"
[[event]]
name = "altimeter-out"
time = 5.0
set = "sensors.altimeter_available"
value = false
[[event]]
name = "velocimeter-out"
time = 5.0
set = "sensors.velocimeter_available"
value = false
"#,
    );
    let nominal = fly_navigation("");
    let at = |t: &Trajectory, column: &str, time: f64| {
        let k = t.times.iter().position(|&s| s >= time - 1e-9).unwrap();
        t.column(column).unwrap()[k]
    };
    // THEN from the step after the event on, the filter reports no update
    assert_eq!(at(&failed, "filter.altimeter_dof", 4.0), 1.0);
    assert_eq!(at(&failed, "filter.altimeter_dof", 6.0), 0.0);
    assert_eq!(at(&failed, "filter.velocimeter_dof", 6.0), 0.0);
    assert_eq!(at(&nominal, "filter.altimeter_dof", 6.0), 1.0);
    // AND its position and velocity variances grow while it coasts on the IMU, well past
    // those the nominal run keeps
    for element in [2, 5] {
        let column = format!("filter.covariance_diag[{element}]");
        let (before, after) = (at(&failed, &column, 5.0), at(&failed, &column, 19.0));
        let kept = at(&nominal, &column, 19.0);
        assert!(after > 2.0 * before, "{column}: {before} -> {after}");
        assert!(after > 2.0 * kept, "{column}: {after} vs nominal {kept}");
        let coasting = failed.column(&column).unwrap();
        let from = failed.times.iter().position(|&t| t >= 5.02).unwrap();
        assert!(
            coasting[from..].windows(2).all(|w| w[1] >= w[0]),
            "{column} must not shrink without measurements"
        );
    }
}

/// `landing-model-exchange` (LanderGnc as Co-Simulation, LanderPlant as Model Exchange) to
/// `stop_s`, with `events`; the plant as Co-Simulation instead when `co_simulation`.
fn landing(events: &str, stop_s: f64, co_simulation: bool) -> Trajectory {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../harness/scenarios/landing-model-exchange.toml");
    // The system only: `[verdict]` is the mission's (lander), not the master's.
    let text = std::fs::read_to_string(&path).unwrap();
    let system_part = text.split("\n[verdict]").next().unwrap();
    let mut system =
        toml_format::parse(&format!("{system_part}\n{events}"), &path).unwrap_or_else(|e| {
            panic!("{e}");
        });
    system.stop_time = stop_s;
    if co_simulation {
        system.instance_mut("plant").unwrap().model_exchange = None;
    }
    let mut simulation = Simulation::new(system, &fmu_dir()).unwrap();
    let mut trajectory = Trajectory {
        names: simulation.column_names().to_vec(),
        ..Default::default()
    };
    let end = simulation.run(&mut trajectory).unwrap();
    // The run goes on past the event to its stop time.
    assert_eq!(end, RunEnd::Completed);
    assert_eq!(*trajectory.times.last().unwrap(), stop_s);
    trajectory
}

/// Due at 20.003 s, during the descent from the 800 m hover: applied at the point 20.01 s.
const ENGINE_DEGRADED: &str = r#"
[[event]]
name = "engine-degraded"
time = 20.003
set = "plant.engine_health"
value = 0.93
"#;
const DEGRADED_AT_S: f64 = 20.01;

#[test]
fn an_engine_fault_on_the_model_exchange_plant_scales_its_thrust_from_the_events_point() {
    // GIVEN the landing with the plant as Model Exchange, its engines losing 7 % of their
    // thrust by an event, and the same landing without it
    let stop_s = 22.0;
    let degraded = landing(ENGINE_DEGRADED, stop_s, false);
    let nominal = landing("", stop_s, false);
    let width = degraded.names.len();
    let k = degraded
        .times
        .iter()
        .position(|&t| t == DEGRADED_AT_S)
        .unwrap();
    // THEN up to and including the event's point (its row shows the values before it), the
    // two runs are the same bit for bit
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(
        bits(&degraded.values[..(k + 1) * width]),
        bits(&nominal.values[..(k + 1) * width])
    );
    // AND from the next point on the plant delivers 0.93 of the command it gets (1 without
    // the fault), every point to the stop time
    let ratio = |t: &Trajectory, j: usize| {
        let (thrust, command) = (
            t.column("plant.thrust_actual").unwrap()[j],
            t.column("gnc.thrust_cmd").unwrap()[j],
        );
        // Inside the throttle range, so that only the health scales it.
        assert!(
            800.0 < command && command < 1600.0,
            "t = {}: {command} N",
            t.times[j]
        );
        thrust / command
    };
    assert_eq!(ratio(&degraded, k), 1.0);
    for j in k + 1..degraded.len() {
        let t = degraded.times[j];
        assert!((ratio(&degraded, j) - 0.93).abs() < 1e-12, "t = {t}");
        assert!((ratio(&nominal, j) - 1.0).abs() < 1e-12, "t = {t}");
    }
    // AND over the first step after the event the vertical velocity gains less than in the
    // nominal run by the lost thrust's vertical component over the mass, times the step:
    // (0.93 - 1) T u_up / m h, the thrust T commanded at the point and held over the step
    let at = |t: &Trajectory, column: &str, j: usize| t.column(column).unwrap()[j];
    let q = |i: usize| at(&degraded, &format!("plant.q_body_to_nue[{i}]"), k);
    // Up (NUE element 2) component of the body +y thrust axis: R[1][1] of (w, x, y, z).
    let up = 1.0 - 2.0 * (q(2) * q(2) + q(4) * q(4));
    let (thrust, mass) = (
        at(&degraded, "gnc.thrust_cmd", k),
        at(&degraded, "plant.mass", k),
    );
    let h = 0.01;
    let expected = (0.93 - 1.0) * thrust * up / mass * h;
    let gain = |t: &Trajectory| at(t, "plant.v_nue[2]", k + 1) - at(t, "plant.v_nue[2]", k);
    let difference = gain(&degraded) - gain(&nominal);
    assert!(
        (difference - expected).abs() < 1e-4 * expected.abs(),
        "dv_up degraded - nominal over [{DEGRADED_AT_S}, {}]: {difference} m/s, \
         expected {expected} m/s",
        DEGRADED_AT_S + h
    );
    // AND the whole degraded flight is the Co-Simulation plant's with the same event, to the
    // solver's tolerance (an event a step late would be 1e-3 m/s off in the vertical speed)
    let co_simulation = landing(ENGINE_DEGRADED, stop_s, true);
    assert_eq!(co_simulation.names, degraded.names);
    let mut largest = (0.0_f64, String::new());
    for (j, name) in degraded.names.iter().enumerate() {
        if !(name.starts_with("plant.r_nue") || name.starts_with("plant.v_nue")) {
            continue;
        }
        let (a, b) = (
            degraded.column(name).unwrap(),
            co_simulation.column(name).unwrap(),
        );
        for (x, y) in a.iter().zip(&b) {
            if (x - y).abs() > largest.0 {
                largest = ((x - y).abs(), format!("{name} (column {j})"));
            }
        }
    }
    println!(
        "Model Exchange vs Co-Simulation plant, engine fault at {DEGRADED_AT_S} s: {largest:?}"
    );
    assert!(largest.0 < 1e-7, "{largest:?}");
}

/// The engine health a held run's plant is linearized with, from its `B`: the partial of the
/// vertical acceleration with respect to the thrust command is `health u_up / m`, `u_up` the
/// up component of the body +y thrust axis and `m` the mass at the held point (its row).
fn health_held_at(at_s: f64, events: &[(&str, f64, f64)]) -> (f64, f64) {
    let mut system = crate::common::lander_loop();
    system.instance_mut("plant").unwrap().model_exchange =
        Some(cosim::master::SolverSettings::default());
    system.events = crate::common::engine_faults(events);
    let mut simulation = Simulation::new(system, &fmu_dir()).unwrap();
    let mut trajectory = Trajectory {
        names: simulation.column_names().to_vec(),
        ..Default::default()
    };
    let held = simulation.run_to(at_s, &mut trajectory).unwrap().unwrap();
    assert_eq!(*trajectory.times.last().unwrap(), held);
    let model = simulation.linearize(cosim::master::Jacobians::Fmu).unwrap();
    assert_eq!(model.time_s, held);
    let plant = model.units.iter().find(|u| u.instance == "plant").unwrap();
    let state = plant
        .states
        .iter()
        // Flat model: r_nue, then v_nue; its element 5 is v_nue[2], the up velocity.
        .position(|s| s == "plant.translation_state[5]")
        .unwrap_or_else(|| panic!("{:?}", plant.states));
    let input = plant
        .inputs
        .iter()
        .position(|s| s == "plant.thrust_cmd")
        .unwrap();
    let last = trajectory.len() - 1;
    let at = |column: &str| trajectory.column(column).unwrap()[last];
    let q = |i: usize| at(&format!("plant.q_body_to_nue[{i}]"));
    let up = 1.0 - 2.0 * (q(2) * q(2) + q(4) * q(4));
    (plant.b[(state, input)] * at("plant.mass") / up, held)
}

#[test]
fn a_run_held_for_linearization_has_applied_the_events_due_up_to_its_point_once() {
    // GIVEN engine faults at 4 s, at 10 s and at 10.005 s (applied at the point 10.01 s), the
    // plant as Model Exchange
    // Mild faults: the hover's 1,460 N stays inside the throttle range (0.9 of 1,600 N would
    // saturate the command, whose partial is then 0).
    let faults = [
        ("early", 4.0, 0.98),
        ("on-time", 10.0, 0.96),
        ("late", 10.005, 0.94),
    ];
    // WHEN the run is held at 10 s and linearized THEN the plant's thrust partial is that of
    // health 0.96: the events due up to and at the point are applied (the model is that of
    // the step from the point, which flies with them), the one due after it is not
    let (health, held) = health_held_at(10.0, &faults);
    assert_eq!(held, 10.0);
    assert!((health - 0.96).abs() < 1e-9, "{health}");
    // AND held a step earlier, only the first applies
    let (health, held) = health_held_at(9.99, &faults);
    assert_eq!(held, 9.99);
    assert!((health - 0.98).abs() < 1e-9, "{health}");
    // AND asked for 10.006 s, the point nearest it is 10.01 s, where the last is due
    let (health, held) = health_held_at(10.006, &faults);
    assert_eq!(held, 10.01);
    assert!((health - 0.94).abs() < 1e-9, "{health}");
    // AND without events the partial is that of a healthy engine (what the above tells apart)
    let (health, _) = health_held_at(10.0, &[]);
    assert!((health - 1.0).abs() < 1e-9, "{health}");
}
