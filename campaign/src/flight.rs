//! Flying one flight of a campaign: apply the run's dispersion and the flight's law and
//! phi_cmd to a loaded simulation, run it, and compute the metrics.
use crate::definition::Flight;
use crate::dispersion::{Dispersion, DispersionRanges, Nominal};
use crate::estimator_start::{self, ClaimedStartError, FILTER, SENSORS};
use crate::manifest::{End, Judged, Row};
use cosim::master::{RunEnd, Trajectory};
use cosim::supervise::Runner;
use cosim::system::{ParamValue, SystemDescription};
use lander::laws::Laws;
use lander::metrics::{self, nan_metrics, Metrics};
use lander::retarget::{divert_metrics, RetargetCommand};
use lander::verdict::{self, Spec};
use model_description::StartValue;
use std::path::Path;

/// Instance names a Monte Carlo scenario must use (those of the shipped scenarios, which
/// the metrics read).
pub const PLANT: &str = "plant";
pub const GNC: &str = "gnc";
/// The navigation-error FMU, when the scenario has one.
pub const NAV: &str = "nav";

/// The columns [`metrics::compute`] reads: all a campaign records.
pub const METRIC_COLUMNS: [&str; 9] = [
    "plant.r_nue",
    "plant.v_nue",
    "plant.omega_body",
    "plant.propellant_used",
    "gnc.guidance_phase",
    "gnc.err_roll",
    "gnc.phi_b",
    "gnc.tilt_error",
    "plant.touchdown",
];

/// The columns the divert's metrics read beyond [`METRIC_COLUMNS`], recorded when the
/// scenario commands a retarget.
pub const DIVERT_COLUMNS: [&str; 1] = ["plant.q_body_to_nue"];

/// Verdict columns a plant may declare (a plant with landing gear does), read at the end of
/// each flight where it does.
const OPTIONAL_VERDICT_COLUMNS: [&str; 1] = ["plant.tipped_over"];

/// One loaded FMU instance pair with its recording buffer, reused flight after flight.
pub struct Flyer {
    simulation: Runner,
    spec: Spec,
    nominal: Nominal,
    /// Where the scenario's flights should end (terminal errors are measured from it).
    target_nue: [f64; 3],
    trajectory: Trajectory,
    /// The last row of `trajectory` followed by the simulation's final values: all the
    /// verdict and the touchdown metrics read.
    last: Trajectory,
    /// The scenario's requirements: a flight that violates one did not end as expected.
    requirements: Vec<cosim::requirements::Requirement>,
    /// What the scenario's navigation filter claims about its initial error, when it has
    /// one: each run starts it from the dispersed truth off by an error of that spread.
    filter_claim: Option<ClaimedStartError>,
    /// The laws of the GNC FMU, which every flight's law is one of.
    laws: Laws,
    /// The scenario's retarget command, when it has one: each flight's divert is measured.
    retarget: Option<RetargetCommand>,
}

impl Flyer {
    /// Loads the FMUs of `system` (as it is: set `system.record` before, see
    /// [`METRIC_COLUMNS`]) and reads the plant's nominal start; flights are judged by `spec`.
    /// The verdict's columns that `system.record` leaves out are read once, at the end of
    /// each flight (they matter only there).
    pub fn new(system: SystemDescription, spec: Spec, fmu_dir: &Path) -> anyhow::Result<Self> {
        let gnc_present = system.instance(GNC).is_some();
        let target_nue = lander::scenarios::terminal_target_nue(&system);
        anyhow::ensure!(
            gnc_present,
            "scenario '{}' has no instance '{GNC}'",
            system.name
        );
        let final_only: Vec<String> = match &system.record {
            Some(recorded) => verdict::VERDICT_COLUMNS
                .iter()
                .filter(|c| !recorded.iter().any(|r| r == *c))
                .map(|c| c.to_string())
                .collect(),
            None => Vec::new(),
        };
        let mut simulation = Runner::new(system, fmu_dir)?;
        let plant_index = simulation
            .system()
            .instances
            .iter()
            .position(|i| i.name == PLANT)
            .ok_or_else(|| {
                anyhow::anyhow!(
                    "scenario '{}' has no instance '{PLANT}'",
                    simulation.system().name
                )
            })?;
        let (_, description) = simulation.description(plant_index);
        let mut final_only = final_only;
        if simulation.system().record.is_some() {
            final_only.extend(
                OPTIONAL_VERDICT_COLUMNS
                    .iter()
                    .filter(|c| {
                        c.strip_prefix("plant.")
                            .is_some_and(|name| description.variable(name).is_some())
                    })
                    .map(|c| c.to_string()),
            );
        }
        simulation.set_final_columns(&final_only)?;
        let (_, description) = simulation.description(plant_index);
        let start_of = |name: &str| match description.variable(name)?.start()? {
            StartValue::Real(x) => Some(x),
            StartValue::Integer(i) => Some(f64::from(i)),
            _ => None,
        };
        let nominal = Nominal::from_scenario(simulation.system(), PLANT, start_of)
            .map_err(anyhow::Error::msg)?;
        let laws = Laws::of_runner(&simulation, GNC)?;
        let filter_claim = claimed_start_error(&simulation)?;
        let retarget = RetargetCommand::of(simulation.system()).ok();
        let trajectory = Trajectory {
            names: simulation.column_names().to_vec(),
            ..Default::default()
        };
        let last = Trajectory {
            names: [simulation.column_names(), simulation.final_column_names()].concat(),
            ..Default::default()
        };
        Ok(Self {
            simulation,
            laws,
            spec,
            nominal,
            target_nue,
            trajectory,
            last,
            requirements: Vec::new(),
            filter_claim,
            retarget,
        })
    }

    /// Judges every flight by these requirements too (their signals must be recorded:
    /// [`campaign_system`] records them).
    pub fn with_requirements(
        mut self,
        requirements: Vec<cosim::requirements::Requirement>,
    ) -> anyhow::Result<Self> {
        let problems =
            cosim::requirements::unrecorded(&requirements, self.simulation.column_names());
        anyhow::ensure!(problems.is_empty(), "{}", problems.join("\n"));
        self.requirements = requirements;
        Ok(self)
    }

    pub fn simulation(&self) -> &Runner {
        &self.simulation
    }

    /// The laws of the GNC FMU.
    pub fn laws(&self) -> &Laws {
        &self.laws
    }

    pub fn nominal(&self) -> &Nominal {
        &self.nominal
    }

    /// The trajectory of the last flight (the recorded columns only).
    pub fn trajectory(&self) -> &Trajectory {
        &self.trajectory
    }

    /// Flies `flight`. A failure is not an error here: it is the flight's result, recorded
    /// in [`Row::end`] with NaN metrics, and the campaign goes on.
    pub fn fly(&mut self, flight: &Flight, ranges: &DispersionRanges) -> Row {
        let dispersion = Dispersion::draw(flight.run_seed, ranges);
        let (metrics, end, verdict) = match self.try_fly(flight, &dispersion) {
            Ok(result) => result,
            Err(error) => (
                nan_metrics(),
                End::Error {
                    message: format!("{error:#}"),
                },
                Judged::error(),
            ),
        };
        Row {
            flight: *flight,
            dispersion,
            metrics,
            end,
            verdict,
        }
    }

    fn try_fly(
        &mut self,
        flight: &Flight,
        dispersion: &Dispersion,
    ) -> anyhow::Result<(Metrics, End, Judged)> {
        let sim = &mut self.simulation;
        let law = self
            .laws
            .parameter(flight.law)
            .map_err(anyhow::Error::msg)?;
        sim.set_parameter(GNC, lander::laws::PARAMETER, law)?;
        sim.set_parameter(
            GNC,
            "phi_cmd",
            ParamValue::Real(flight.phi_cmd_deg.to_radians()),
        )?;
        for (name, value) in self.nominal.apply(dispersion) {
            sim.set_parameter(PLANT, name, ParamValue::Real(value))?;
        }
        // Navigation errors are drawn per run too: the run seed (a pure function of the
        // campaign seed and the run) seeds them, so every law and phi_cmd of a run sees the
        // same errors and a replay the same bits. Its top 31 bits fit the FMI Integer.
        if sim.system().instance(NAV).is_some() {
            let nav_seed = i64::try_from(flight.run_seed >> 33).expect("31 bits fit");
            sim.set_parameter(NAV, "seed", ParamValue::Integer(nav_seed))?;
        }
        if sim.system().instance(SENSORS).is_some() {
            let seed = estimator_start::sensors_seed(flight.run_seed);
            sim.set_parameter(SENSORS, "seed", ParamValue::Integer(seed))?;
        }
        if let Some(claim) = &self.filter_claim {
            let truth = estimator_start::Start {
                r0_nue_m: std::array::from_fn(|i| {
                    self.nominal.r0_nue_m[i] + dispersion.delta_r0_nue_m[i]
                }),
                v0_nue_mps: std::array::from_fn(|i| {
                    self.nominal.v0_nue_mps[i] + dispersion.delta_v0_nue_mps[i]
                }),
                q0_body_to_nue: self.nominal.start_attitude(dispersion),
            };
            let estimate = estimator_start::estimate(flight.run_seed, &truth, claim);
            for (name, value) in estimator_start::parameters(&estimate) {
                sim.set_parameter(FILTER, &name, ParamValue::Real(value))?;
            }
        }
        self.trajectory.times.clear();
        self.trajectory.values.clear();
        let run_end = sim.run(&mut self.trajectory)?;
        self.last.times.clear();
        self.last.values.clear();
        if let Some(&time) = self.trajectory.times.last() {
            self.last.times.push(time);
            let last_row = self.trajectory.row(self.trajectory.len() - 1);
            self.last.values.extend_from_slice(last_row);
            self.last.values.extend_from_slice(sim.final_values());
        }
        let judged = verdict::judge(&self.last, &run_end, &self.spec.envelope);
        let end = match run_end {
            RunEnd::Completed => End::Completed,
            RunEnd::Terminated { instance, .. } => End::Terminated { instance },
        };
        let metrics = metrics::compute_with_final(
            &self.trajectory,
            &self.last,
            &metrics::Columns::default(),
            self.target_nue,
        )?;
        let metrics = match &self.retarget {
            Some(command) => metrics.with_divert(&divert_metrics(&self.trajectory, command)?),
            None => metrics,
        };
        let mut judged = Judged::of(&judged, self.spec.expect);
        let violated: Vec<String> =
            cosim::requirements::judge(&self.requirements, &self.trajectory)
                .iter()
                .filter(|r| !r.holds())
                .map(|r| r.describe())
                .collect();
        if !violated.is_empty() {
            judged.as_expected = false;
            let detail = std::mem::take(&mut judged.detail);
            judged.detail = [detail]
                .into_iter()
                .filter(|d| !d.is_empty())
                .chain(violated)
                .collect::<Vec<_>>()
                .join("; ");
        }
        Ok((metrics, end, judged))
    }
}

/// The scenario of a campaign and its verdict spec, recording at every step only what the
/// metrics need (`record_all` = false; [`Flyer`] reads the verdict's other columns at the
/// end) or every output (replay).
pub fn campaign_system(
    scenario: &str,
    sets: &[String],
    record_all: bool,
) -> anyhow::Result<(SystemDescription, Spec)> {
    let (mut system, spec) = lander::scenarios::spec::load(scenario)?;
    // The law and phi_cmd of each flight are the campaign's grid; a --set of either would
    // be overwritten by every flight.
    let (problems, _) = lander::overrides::apply_sets(
        &mut system,
        sets,
        &[
            ("gnc.control_law", "the campaign flies the laws of --law"),
            (
                "gnc.phi_cmd",
                "the campaign flies the grid of --phi-cmd-deg",
            ),
        ],
    );
    if !problems.is_empty() {
        anyhow::bail!("{}", problems.join("\n"));
    }
    system.record = if record_all {
        None
    } else {
        let mut record: Vec<String> = METRIC_COLUMNS.iter().map(|c| c.to_string()).collect();
        if RetargetCommand::of(&system).is_ok() {
            record.extend(DIVERT_COLUMNS.iter().map(|c| c.to_string()));
        }
        cosim::requirements::record_signals(
            &mut record,
            &lander::scenarios::spec::requirements(scenario)?,
        );
        Some(record)
    };
    Ok((system, spec))
}

/// The initial 1-sigma errors the scenario's filter claims (its parameters as the scenario
/// sets them, else the FMU's start values); `None` without a filter instance.
fn claimed_start_error(simulation: &Runner) -> anyhow::Result<Option<ClaimedStartError>> {
    let Some(index) = simulation
        .system()
        .instances
        .iter()
        .position(|i| i.name == FILTER)
    else {
        return Ok(None);
    };
    let instance = &simulation.system().instances[index];
    let (_, description) = simulation.description(index);
    let value = |name: &str| -> anyhow::Result<f64> {
        let set = instance.parameters.iter().find(|(n, _)| n == name);
        let value = match set {
            Some((_, ParamValue::Real(x))) => Some(*x),
            Some((_, ParamValue::Integer(i))) => Some(*i as f64),
            Some(_) => None,
            None => match description.variable(name).and_then(|v| v.start()) {
                Some(StartValue::Real(x)) => Some(x),
                _ => None,
            },
        };
        value.ok_or_else(|| {
            anyhow::anyhow!(
                "instance '{FILTER}' has no real parameter '{name}': a campaign starts the \
                 navigation filter from each run's dispersed start with the error it claims"
            )
        })
    };
    Ok(Some(ClaimedStartError {
        r0_sigma_m: value("r0_sigma")?,
        v0_sigma_mps: value("v0_sigma")?,
        attitude0_sigma_rad: value("attitude0_sigma")?,
    }))
}
