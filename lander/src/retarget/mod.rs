//! `harness retarget`: a scenario with a retarget (LanderGnc's `retarget_time`,
//! `retarget_site_nue`), flown with each attitude law twice: with the divert re-planned for
//! the lateral authority (`retarget_replan` = true) and with the target only moved (false),
//! and compared by the divert's figures of merit ([`command`]).
pub mod command;

pub use command::{divert_metrics, DivertMetrics, RetargetCommand, SETTLE_RADIUS_M};

use crate::laws::Law;
use crate::paper::{self, Flight};
use crate::verdict::Envelope;
use cosim::master::RunEnd;
use cosim::supervise::Runner;
use cosim::system::{ParamValue, SystemDescription};
use std::path::{Path, PathBuf};

/// The laws `harness retarget` compares: the paper's pair.
pub const LAWS: [Law; 2] = [Law::COUPLED, Law::DECOUPLED];

/// One law flown one way.
pub struct DivertFlight {
    pub flight: Flight,
    pub replan: bool,
    pub metrics: DivertMetrics,
}

impl DivertFlight {
    /// `decoupled, re-planned` / `coupled, target moved`.
    pub fn label(&self) -> String {
        format!(
            "{}, {}",
            self.flight.law.name(),
            if self.replan {
                "re-planned"
            } else {
                "target moved"
            }
        )
    }

    /// The file-name part: `decoupled-replanned` / `coupled-moved`.
    pub fn stem(&self) -> String {
        format!(
            "{}-{}",
            self.flight.law.name(),
            if self.replan { "replanned" } else { "moved" }
        )
    }
}

/// Flies `system` once per law and way (re-planned, then target only moved).
pub fn fly_all(
    system: SystemDescription,
    fmu_dir: &Path,
    laws: &[Law],
    envelope: &Envelope,
) -> anyhow::Result<(RetargetCommand, Vec<DivertFlight>)> {
    let command = RetargetCommand::of(&system)?;
    let mut simulation = Runner::new(system, fmu_dir)?;
    let mut flights = Vec::new();
    for replan in [true, false] {
        simulation.set_parameter("gnc", "retarget_replan", ParamValue::Boolean(replan))?;
        for &law in laws {
            let flight = paper::fly_judged(&mut simulation, law, envelope, &[])?;
            let metrics = divert_metrics(&flight.trajectory, &command)?;
            flights.push(DivertFlight {
                flight,
                replan,
                metrics,
            });
        }
    }
    Ok((command, flights))
}

const LABEL: usize = 44;
const CELL: usize = 12;

/// The comparison table: a column per law and way, a row per figure of merit.
pub fn table(name: &str, command: &RetargetCommand, flights: &[DivertFlight]) -> String {
    use std::fmt::Write;
    let [n, u, e] = command.site_nue;
    let mut out = format!(
        "scenario '{name}': retarget at {} s to ({n}, {u}, {e}) m NUE\n",
        command.time_s
    );
    let _ = write!(out, "{:<LABEL$}", "");
    for f in flights {
        let _ = write!(out, "{:>CELL$}", f.flight.law.name());
    }
    let _ = writeln!(out);
    let _ = write!(out, "{:<LABEL$}", "");
    for f in flights {
        let way = if f.replan { "re-planned" } else { "moved" };
        let _ = write!(out, "{way:>CELL$}");
    }
    let _ = writeln!(out);
    type Row = (&'static str, fn(&DivertMetrics) -> f64);
    let rows: [Row; 9] = [
        ("overshoot past the site (m)", |m| m.overshoot_m),
        ("cross-track deviation (m)", |m| m.cross_track_m),
        ("final error from the site (m)", |m| m.final_error_m),
        ("final horizontal error (m)", |m| m.final_horizontal_error_m),
        ("peak tilt from vertical (deg)", |m| m.peak_tilt_deg),
        ("peak tilt error (deg)", |m| m.peak_tilt_error_deg),
        ("settled within 1 m after (s)", |m| m.settle_time_s),
        ("lowest altitude (m)", |m| m.min_altitude_m),
        ("highest altitude (m)", |m| m.max_altitude_m),
    ];
    for (label, get) in rows {
        let _ = write!(out, "{label:<LABEL$}");
        for f in flights {
            let value = get(&f.metrics);
            if value.is_nan() {
                let _ = write!(out, "{:>CELL$}", "never");
            } else {
                let _ = write!(out, "{value:>CELL$.3}");
            }
        }
        let _ = writeln!(out);
    }
    let _ = write!(out, "{:<LABEL$}", "end of run (s)");
    for f in flights {
        let end = match &f.flight.end {
            RunEnd::Completed => f.flight.metrics.end_time_s,
            RunEnd::Terminated { time, .. } => *time,
        };
        let _ = write!(out, "{end:>CELL$.2}");
    }
    let _ = writeln!(out);
    out
}

/// Writes each flight's trajectory and `<name>-summary.txt` into `dir`; returns the paths
/// written (the figures are `report::plots::retarget`'s).
pub fn write_results(
    flights: &[DivertFlight],
    dir: &Path,
    name: &str,
    summary: &str,
) -> anyhow::Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir)?;
    let mut written = Vec::new();
    for f in flights {
        let path = dir.join(format!("{name}-{}.csv", f.stem()));
        cosim::results::write(&path, &f.flight.trajectory, cosim::results::Format::Csv)?;
        written.push(path);
    }
    let path = dir.join(format!("{name}-summary.txt"));
    std::fs::write(&path, summary)?;
    written.push(path);
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shipped_retarget_scenario_commands_its_divert() {
        let system = crate::scenarios::load("retarget").unwrap();
        let command = RetargetCommand::of(&system).unwrap();
        assert_eq!(command.site_nue, [30.0, 150.0, 0.0]);
        assert!(command.time_s > 130.0 && command.time_s < 145.0);
        // AND the paper scenario commands none
        assert!(RetargetCommand::of(&crate::scenarios::load("paper").unwrap()).is_err());
    }
}
