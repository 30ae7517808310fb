//! `harness paper`: one scenario flown with each control law, compared.
use crate::master::{MasterError, RunEnd, Simulation, Trajectory};
use crate::metrics::{self, Metrics};
use crate::scenarios::{Law, TERMINAL_TARGET_NUE};
use crate::system::SystemDescription;
use std::path::Path;

/// One law's flight.
#[derive(Debug, Clone)]
pub struct Flight {
    pub law: Law,
    pub end: RunEnd,
    pub trajectory: Trajectory,
    pub metrics: Metrics,
}

/// Flies `system` once per law (its `gnc.control_law` overridden), reusing one loaded
/// simulation (the instances are reset between runs).
pub fn fly_all(
    system: SystemDescription,
    fmu_dir: &Path,
    laws: &[Law],
) -> anyhow::Result<Vec<Flight>> {
    let mut simulation = Simulation::new(system, fmu_dir)?;
    laws.iter().map(|&law| fly(&mut simulation, law)).collect()
}

/// Flies one law on a loaded simulation.
pub fn fly(simulation: &mut Simulation, law: Law) -> anyhow::Result<Flight> {
    simulation.set_parameter("gnc", "control_law", law.parameter())?;
    let mut trajectory = Trajectory {
        names: simulation.column_names().to_vec(),
        ..Default::default()
    };
    let end = simulation
        .run(&mut trajectory)
        .map_err(|e: MasterError| anyhow::anyhow!(e))?;
    let metrics = metrics::compute(&trajectory, &Default::default(), TERMINAL_TARGET_NUE)?;
    Ok(Flight {
        law,
        end,
        trajectory,
        metrics,
    })
}

/// The comparison table printed by `harness paper`.
pub fn table(flights: &[Flight]) -> String {
    use std::fmt::Write;
    let mut out = String::new();
    let _ = write!(out, "{:<44}", "");
    for f in flights {
        let _ = write!(out, "{:>12}", f.law.name());
    }
    let _ = writeln!(out);
    type Row = (&'static str, fn(&Metrics) -> f64);
    let rows: [Row; 10] = [
        ("max horizontal deviation, flight (m)", |m| {
            m.max_horizontal_deviation_m
        }),
        ("max horizontal deviation, descent (m)", |m| {
            m.max_horizontal_deviation_descent_m
        }),
        ("terminal position error (m)", |m| {
            m.terminal_position_error_m
        }),
        ("terminal velocity error (m/s)", |m| {
            m.terminal_velocity_error_mps
        }),
        ("final altitude (m)", |m| m.final_altitude_m),
        ("max body rate (deg/s)", |m| {
            m.max_body_rate_radps.to_degrees()
        }),
        ("propellant used (kg)", |m| m.propellant_used_kg),
        ("thrust-axis manoeuvre done at (s, |err|<2 deg)", |m| {
            m.roll_settling_time_s
        }),
        ("final phi_b (deg)", |m| m.final_phi_b_rad.to_degrees()),
        ("max tilt error after 30 s (deg)", |m| {
            m.max_tilt_error_after_30s_rad.to_degrees()
        }),
    ];
    for (label, get) in rows {
        let _ = write!(out, "{label:<44}");
        for f in flights {
            let _ = write!(out, "{:>12.3}", get(&f.metrics));
        }
        let _ = writeln!(out);
    }
    let _ = write!(out, "{:<44}", "end of run");
    for f in flights {
        let end = match &f.end {
            RunEnd::Completed => "completed".to_owned(),
            RunEnd::Terminated { time, .. } => format!("stop {time:.2}s"),
        };
        let _ = write!(out, "{end:>12}");
    }
    let _ = writeln!(out);
    out
}
