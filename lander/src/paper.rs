//! `harness paper`: one scenario flown with each control law, compared.
use crate::laws::{Law, Laws};
use crate::metrics::{self, Metrics};
use crate::provenance::Provenance;
use crate::verdict::{self, Envelope, Verdict};
use cosim::master::{MasterError, RunEnd, Trajectory};
use cosim::requirements::{Judged, Requirement};
use cosim::supervise::Runner;
use cosim::system::SystemDescription;
use std::path::Path;

/// One law's flight.
#[derive(Debug, Clone)]
pub struct Flight {
    pub law: Law,
    pub end: RunEnd,
    pub trajectory: Trajectory,
    /// The unit of each recorded column, as the FMUs declare it ("" for none).
    pub units: Vec<String>,
    pub metrics: Metrics,
    pub verdict: Verdict,
    /// The scenario's requirements judged on this flight.
    pub requirements: Vec<Judged>,
    /// The scenario and FMUs flown, its parameters as they stood before this flight set its
    /// law (for the report).
    pub provenance: std::sync::Arc<Provenance>,
}

/// Flies `system` once per law (its `gnc.control_law` overridden), reusing one loaded
/// simulation (the instances are reset between runs); touchdowns judged against `envelope`,
/// every flight against `requirements` (refused before the first flight when one names a
/// signal that is not recorded).
pub fn fly_all(
    system: SystemDescription,
    fmu_dir: &Path,
    laws: &[Law],
    envelope: &Envelope,
    requirements: &[Requirement],
) -> anyhow::Result<Vec<Flight>> {
    let mut simulation = Runner::new(system, fmu_dir)?;
    let mut problems = cosim::requirements::unrecorded(requirements, simulation.column_names());
    if let Err(unknown) = Laws::of_runner(&simulation, "gnc")?.check(laws) {
        problems.push(unknown);
    }
    if !problems.is_empty() {
        anyhow::bail!("{}", problems.join("\n"));
    }
    laws.iter()
        .map(|&law| fly_judged(&mut simulation, law, envelope, requirements))
        .collect()
}

/// Flies one law on a loaded simulation (touchdown judged against the default envelope).
pub fn fly(simulation: &mut Runner, law: Law) -> anyhow::Result<Flight> {
    fly_judged(simulation, law, &Envelope::default(), &[])
}

/// The law a scenario itself flies (its `gnc.control_law`), when it sets one that is one of
/// `laws`.
pub fn scenario_law(system: &SystemDescription, laws: &Laws) -> Option<Law> {
    let gnc = system.instance("gnc")?;
    let (_, value) = gnc.parameters.iter().find(|(n, _)| n == "control_law")?;
    let code = match value {
        cosim::system::ParamValue::Integer(i) => *i,
        cosim::system::ParamValue::Real(x) if x.fract() == 0.0 => *x as i64,
        _ => return None,
    };
    laws.of_value(code)
}

/// Flies one law on a loaded simulation and judges its end against `envelope` and its
/// trajectory against `requirements`.
pub fn fly_judged(
    simulation: &mut Runner,
    law: Law,
    envelope: &Envelope,
    requirements: &[Requirement],
) -> anyhow::Result<Flight> {
    let provenance = std::sync::Arc::new(Provenance::of(simulation));
    let value = Laws::of_runner(simulation, "gnc")?
        .parameter(law)
        .map_err(anyhow::Error::msg)?;
    simulation.set_parameter("gnc", crate::laws::PARAMETER, value)?;
    let mut trajectory = Trajectory {
        names: simulation.column_names().to_vec(),
        ..Default::default()
    };
    let end = simulation
        .run(&mut trajectory)
        .map_err(|e: MasterError| anyhow::anyhow!(e))?;
    let target = crate::scenarios::terminal_target_nue(simulation.system());
    let metrics = metrics::compute(&trajectory, &Default::default(), target)?;
    let verdict = verdict::judge(&trajectory, &end, envelope);
    let requirements = cosim::requirements::judge(requirements, &trajectory);
    Ok(Flight {
        law,
        end,
        trajectory,
        units: simulation.column_units().to_vec(),
        metrics,
        verdict,
        requirements,
        provenance,
    })
}

/// The text `harness paper` prints and keeps as `<name>-summary.txt`: the table, then per
/// law its verdict and each requirement's result. `own` is the law the scenario itself flies:
/// the other laws are flown for comparison, and a requirement they violate is the
/// comparison's finding (said so), not a failure of the scenario.
pub fn summary(
    name: &str,
    flights: &[Flight],
    expect: verdict::Expect,
    own: Option<Law>,
) -> String {
    let mut text = format!("scenario '{name}'\n{}\n", table(flights));
    for flight in flights {
        text += &format!(
            "{}: {}\n",
            flight.law.name(),
            flight.verdict.describe(expect)
        );
        for event in &flight.provenance.event {
            text += &format!("  {}\n", event.outcome(&flight.end));
        }
        let comparison = own.is_some_and(|own| own != flight.law);
        for judged in &flight.requirements {
            let note = if comparison && !judged.holds() {
                " [a comparison law: not the scenario's failure]"
            } else {
                ""
            };
            text += &format!("  {}{note}\n", judged.describe());
        }
    }
    text
}

/// The exit status of `harness paper`: every law's verdict, and the requirements of the law
/// the scenario flies (of every law when it sets none).
pub fn exit_code(flights: &[Flight], expect: verdict::Expect, own: Option<Law>) -> i32 {
    flights
        .iter()
        .map(|f| {
            let mut code = f.verdict.exit_code(expect);
            let binding = own.is_none_or(|own| own == f.law);
            if binding && f.requirements.iter().any(|r| !r.holds()) {
                code = code.max(verdict::EXIT_FAILED_VERDICT);
            }
            code
        })
        .max()
        .unwrap_or(verdict::EXIT_OK)
}

/// Writes into `dir` each law's trajectory (in `format`) and `<name>-summary.txt`; returns
/// the paths written (the figures and `report.html` are the report crate's, written after).
pub fn write_results(
    flights: &[Flight],
    dir: &Path,
    name: &str,
    summary: &str,
    format: cosim::results::Format,
) -> anyhow::Result<Vec<std::path::PathBuf>> {
    std::fs::create_dir_all(dir)?;
    let mut written = Vec::new();
    for flight in flights {
        let path = dir.join(format!(
            "{name}-{}.{}",
            flight.law.name(),
            format.extension()
        ));
        cosim::results::write_with_units(&path, &flight.trajectory, &flight.units, format)?;
        written.push(path);
    }
    let path = dir.join(format!("{name}-summary.txt"));
    std::fs::write(&path, summary)?;
    written.push(path);
    Ok(written)
}

/// Writes `provenance.toml` into `dir`: the scenario and FMUs of the first flight, with the
/// laws flown; nothing without flights.
pub fn write_provenance(
    flights: &[Flight],
    dir: &Path,
) -> anyhow::Result<Option<std::path::PathBuf>> {
    let Some(first) = flights.first() else {
        return Ok(None);
    };
    let mut provenance = (*first.provenance).clone();
    provenance.laws = flights.iter().map(|f| f.law.name().to_owned()).collect();
    Ok(Some(provenance.write(dir)?))
}

const LABEL: usize = 46;
const CELL: usize = 14;

/// The comparison table printed by `harness paper`: metrics, then the verdict and the
/// touchdown state ("-" where a law did not touch down).
pub fn table(flights: &[Flight]) -> String {
    use std::fmt::Write;
    let mut out = String::new();
    let _ = write!(out, "{:<LABEL$}", "");
    for f in flights {
        let _ = write!(out, "{:>CELL$}", f.law.name());
    }
    let _ = writeln!(out);
    type Row = (&'static str, fn(&Metrics) -> f64);
    let rows: [Row; 12] = [
        ("max horizontal deviation, flight (m)", |m| {
            m.max_horizontal_deviation_m
        }),
        ("max horizontal deviation, descent (m)", |m| {
            m.max_horizontal_deviation_descent_m
        }),
        ("position error, end of descent (m)", |m| {
            m.descent_end_position_error_m
        }),
        ("speed at the end of the run (m/s)", |m| {
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
        ("max tilt error, flight (deg)", |m| {
            m.max_tilt_error_rad.to_degrees()
        }),
        ("horizontal speed at descent start (m/s)", |m| {
            m.handover_horizontal_speed_mps
        }),
    ];
    for (label, get) in rows {
        let _ = write!(out, "{label:<LABEL$}");
        for f in flights {
            let _ = write!(out, "{:>CELL$.3}", get(&f.metrics));
        }
        let _ = writeln!(out);
    }
    let line = |out: &mut String, label: &str, cell: &dyn Fn(&Flight) -> String| {
        let _ = write!(out, "{label:<LABEL$}");
        for f in flights {
            let _ = write!(out, "{:>CELL$}", cell(f));
        }
        let _ = writeln!(out);
    };
    line(&mut out, "end of run (s)", &|f| match &f.end {
        RunEnd::Completed => format!("{:.2}", f.metrics.end_time_s),
        RunEnd::Terminated { time, .. } => format!("{time:.2}"),
    });
    line(&mut out, "verdict", &|f| f.verdict.word().to_owned());
    type Touch = (&'static str, fn(&verdict::Touchdown) -> f64);
    let touch: [Touch; 5] = [
        ("touchdown vertical speed (m/s)", |t| t.vertical_speed_mps),
        ("touchdown horizontal speed (m/s)", |t| {
            t.horizontal_speed_mps
        }),
        ("touchdown tilt (deg)", |t| t.tilt_deg),
        ("touchdown body rate (deg/s)", |t| t.body_rate_degps),
        ("touchdown distance from the site (m)", |t| {
            t.horizontal_position_m
        }),
    ];
    for (label, get) in touch {
        line(&mut out, label, &|f| match f.verdict.touchdown() {
            Some(t) => format!("{:.3}", get(t)),
            None => "-".to_owned(),
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::verdict::Touchdown;

    fn flight(law: Law, verdict: Verdict, end: RunEnd) -> Flight {
        let metrics = crate::metrics::nan_metrics();
        Flight {
            law,
            end,
            trajectory: Trajectory::default(),
            units: Vec::new(),
            metrics,
            verdict,
            requirements: Vec::new(),
            provenance: Default::default(),
        }
    }

    #[test]
    fn every_row_of_the_table_is_aligned_and_the_verdict_row_legible() {
        let touchdown = Touchdown {
            time_s: 141.73,
            vertical_speed_mps: 4.9,
            horizontal_speed_mps: 0.1,
            tilt_deg: 56.0,
            body_rate_degps: 3.0,
            horizontal_position_m: 1.0,
        };
        let flights = [
            flight(
                Law::COUPLED,
                Verdict::Completed {
                    end_time_s: 142.01,
                    touchdown_recorded: true,
                },
                RunEnd::Completed,
            ),
            flight(
                Law::DECOUPLED,
                Verdict::HardLanding {
                    touchdown,
                    broken: vec![],
                },
                RunEnd::Terminated {
                    instance: "plant".into(),
                    time: 141.73,
                },
            ),
        ];
        let text = table(&flights);
        let width = LABEL + 2 * CELL;
        for line in text.lines() {
            assert_eq!(line.chars().count(), width, "{line:?}");
        }
        let verdict = text.lines().find(|l| l.starts_with("verdict")).unwrap();
        assert!(
            verdict.ends_with("     completed  hard landing"),
            "{verdict:?}"
        );
        let tilt = text.lines().find(|l| l.contains("touchdown tilt")).unwrap();
        assert!(tilt.ends_with("             -        56.000"), "{tilt:?}");
    }
}
