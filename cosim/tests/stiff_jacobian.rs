//! BDF on an FMU's directional derivatives: the Reference-FMUs' VanDerPol with a stiff mu as
//! Model Exchange, its Jacobian from the FMU and from differences: the same trajectory, every
//! Jacobian the FMU's, fewer derivative calls. The counts and times printed here are those of
//! docs/model-exchange.md (`cargo test -p cosim --test main stiff_jacobian -- --nocapture`).
use cosim::master::{Simulation, Trajectory};
use cosim::system::toml_format;
use ode_solver::Statistics;
use std::path::Path;

#[path = "../../fmi-import/tests/fixtures/reference_fmus.rs"]
mod reference_fmus;

const MU: f64 = 1000.0;

fn fly(fmu: &Path, version: u8, jacobian: &str) -> (Trajectory, Statistics, f64) {
    let text = format!(
        r#"
name = "van-der-pol"
stop_time = 3000.0
step_size = 10.0
record = ["vdp.x0", "vdp.x1"]

[[instance]]
name = "vdp"
fmu = "{}"
interface = "model-exchange"
solver = "bdf"
relative_tolerance = 1e-6
absolute_tolerance = 1e-8
jacobian = "{jacobian}"
[instance.parameters]
mu = {MU:?}
"#,
        fmu.display()
    );
    let system = toml_format::parse(&text, Path::new("van-der-pol.toml")).unwrap();
    let mut simulation = Simulation::new(system, Path::new("/")).unwrap();
    let mut trajectory = Trajectory {
        names: simulation.column_names().to_vec(),
        ..Default::default()
    };
    let started = std::time::Instant::now();
    simulation.run(&mut trajectory).unwrap();
    let seconds = started.elapsed().as_secs_f64();
    let statistics = simulation.model_exchange_statistics()[0].1;
    println!(
        "VanDerPol FMI {version}, mu = {MU}, 0..3000 s, jacobian = {jacobian}: {} steps, {} \
         derivative calls, {} Jacobians ({} from the FMU), {} rejected, {seconds:.3} s",
        statistics.steps,
        statistics.rhs_evaluations,
        statistics.jacobian_evaluations,
        statistics.system_jacobians,
        statistics.rejected_steps
    );
    (trajectory, statistics, seconds)
}

#[test]
fn bdf_on_the_fmus_jacobian_flies_the_stiff_van_der_pol_as_on_differences() {
    let temp = tempfile::tempdir().unwrap();
    for version in [2, 3] {
        let Some(fmu) = reference_fmus::van_der_pol(version, temp.path()) else {
            return;
        };
        let (exact, exact_stats, _) = fly(&fmu, version, "fmu");
        let (fd, fd_stats, _) = fly(&fmu, version, "differences");
        // THEN every Jacobian of the first run is the FMU's, none of the second
        assert!(exact_stats.jacobian_evaluations > 0);
        assert_eq!(
            exact_stats.system_jacobians,
            exact_stats.jacobian_evaluations
        );
        assert_eq!(fd_stats.system_jacobians, 0);
        // AND the derivative calls a difference Jacobian costs (n + 1 = 3) are saved
        assert!(exact_stats.rhs_evaluations < fd_stats.rhs_evaluations);
        // AND the trajectories agree to the solver's tolerance (x0 is O(2), x1 up to O(mu))
        assert_eq!(exact.len(), fd.len());
        for k in 0..exact.len() {
            let (a, b) = (exact.row(k), fd.row(k));
            assert!(
                (a[0] - b[0]).abs() < 1e-3,
                "x0 at row {k}: {} vs {}",
                a[0],
                b[0]
            );
            assert!(
                (a[1] - b[1]).abs() < 1e-3 * (1.0 + b[1].abs()),
                "x1 at row {k}: {} vs {}",
                a[1],
                b[1]
            );
        }
        // AND it is the relaxation oscillation: x0 swings between about +2 and -2
        let x0 = exact.column("vdp.x0").unwrap();
        assert!(x0.iter().any(|v| *v > 1.9) && x0.iter().any(|v| *v < -1.9));
    }
}

/// `landing-model-exchange` with the plant on BDF, its Jacobian as `jacobian` says.
fn land(
    jacobian: cosim::system::JacobianSource,
) -> (cosim::master::RunEnd, Vec<f64>, Statistics, f64) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../harness/scenarios/landing-model-exchange.toml");
    // The system only: `[verdict]` is the mission's (lander), not the master's.
    let text = std::fs::read_to_string(&path).unwrap();
    let system_part = text.split("\n[verdict]").next().unwrap();
    let mut system = toml_format::parse(system_part, &path).unwrap();
    let plant = system.instance_mut("plant").unwrap();
    let settings = plant.model_exchange.as_mut().unwrap();
    settings.method = ode_solver::Method::Bdf;
    settings.jacobian = jacobian;
    let mut simulation = Simulation::new(system, &crate::common::fmu_dir()).unwrap();
    let mut trajectory = Trajectory {
        names: simulation.column_names().to_vec(),
        ..Default::default()
    };
    let started = std::time::Instant::now();
    let end = simulation.run(&mut trajectory).unwrap();
    let seconds = started.elapsed().as_secs_f64();
    let statistics = simulation.model_exchange_statistics()[0].1;
    println!(
        "landing-model-exchange, plant on bdf (1e-8, 1e-10), jacobian = {jacobian:?}: {end:?}, \
         {} steps, {} derivative calls, {} Jacobians ({} from the FMU), {} rejected, \
         {seconds:.2} s",
        statistics.steps,
        statistics.rhs_evaluations,
        statistics.jacobian_evaluations,
        statistics.system_jacobians,
        statistics.rejected_steps
    );
    let last = trajectory.row(trajectory.len() - 1).to_vec();
    (end, last, statistics, seconds)
}

#[test]
fn the_landing_on_bdf_is_the_same_with_the_plants_jacobian_and_with_differences() {
    use cosim::system::JacobianSource;
    let provides = fmi_import::read_description(crate::common::fmu_dir().join("LanderPlant.fmu"))
        .unwrap()
        .1
        .model_exchange
        .and_then(|me| me.provides_directional_derivative)
        == Some(true);
    let (exact_end, exact_last, exact, _) = land(JacobianSource::Fmu);
    let (fd_end, fd_last, fd, _) = land(JacobianSource::Differences);
    // THEN both land, at the same time to the solver's tolerance, in the same place
    let time = |end: &cosim::master::RunEnd| match end {
        cosim::master::RunEnd::Terminated { time, .. } => *time,
        other => panic!("no touchdown: {other:?}"),
    };
    assert!((time(&exact_end) - time(&fd_end)).abs() < 1e-6);
    for (a, b) in exact_last.iter().zip(&fd_last) {
        assert!((a - b).abs() < 1e-5 * (1.0 + b.abs()), "{a} vs {b}");
    }
    // AND the Jacobians are the plant's own exactly when its description says it gives them
    assert_eq!(fd.system_jacobians, 0);
    if provides {
        assert!(exact.jacobian_evaluations > 0);
        assert_eq!(exact.system_jacobians, exact.jacobian_evaluations);
    } else {
        assert_eq!(exact.system_jacobians, 0);
    }
}
