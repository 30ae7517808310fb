//! The FMI face of the plant: the variable table (each variable declared once) and the
//! [`Model`] implementation. Names follow `docs/interface.md` to the letter.
mod derivatives;
mod model_exchange;

use crate::physics::continuous::unit_attitude;
use crate::physics::faults::RcsStuckMode;
use crate::physics::frames::{quaternion_to_scalar_first, Body};
use crate::physics::parameters::{
    PlantParameters, RcsModelKind, TranslationModelKind, MAX_SITE_LATITUDE_RAD,
};
use crate::physics::plant::{
    Advance, Commands, Delivered, Plant, PlantRun, RunCheckpoint, Translation,
};
use crate::physics::slosh::{Slosh, LINEAR_RANGE_RAD};
use crate::physics::thrusters::THRUSTER_COUNT;
use fmi_model::parameter::ParameterError;
use fmi_model::{
    decl, role, same, same_names, Declaration, Dependencies, Experiment, Log, MatchingRule, Member,
    Model, ModelError, StepEnd, Terminal,
};
use lander_math::signal_groups as groups;
use serde::{Deserialize, Serialize};
use std::cell::OnceCell;

/// Values the master reads, refreshed by `calculate_values`. In declaration order
/// (`repr(C)`), so that a master reading the navigation outputs in that order gets them
/// copied as one block.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[repr(C)]
struct Outputs {
    r_nue: [f64; 3],
    v_nue: [f64; 3],
    q_body_to_nue: [f64; 4],
    omega_body: [f64; 3],
    mass: f64,
    altitude: f64,
    propellant_used: f64,
}

impl Outputs {
    /// The outputs of `run`, written in place (the master reads them after every step).
    #[inline(always)]
    fn show(&mut self, plant: &Plant, run: &PlantRun, m0_kg: f64) {
        let x = &run.state;
        match plant.translation {
            // The flat model's state is the position and velocity in NUE, written as they
            // are rather than through `to_nue`'s pair of vectors.
            Translation::Flat { .. } => {
                let t = &x.translation;
                self.r_nue = [t[0], t[1], t[2]];
                self.v_nue = [t[3], t[4], t[5]];
            }
            Translation::Spherical(_) => {
                let (r_nue, v_nue) = plant.translation.to_nue(&x.translation);
                self.r_nue = r_nue.to_array();
                self.v_nue = v_nue.to_array();
            }
        }
        self.q_body_to_nue = quaternion_to_scalar_first(&unit_attitude(&x.q_body_to_nue));
        self.omega_body = x.omega_body.to_array();
        self.mass = x.mass_kg;
        self.altitude = plant.altitude(x);
        self.propellant_used = m0_kg - x.mass_kg;
    }
}

/// The LanderPlant FMU instance. Everything lives here: no global state.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct LanderPlant {
    parameters: PlantParameters,
    commands: Commands,
    /// Duty cycle of each RCS thruster over the coming step (thruster model).
    rcs_duty: [f64; THRUSTER_COUNT],
    /// Set by `exit_initialization` from the validated parameters.
    running: Option<(Plant, PlantRun)>,
    outputs: Outputs,
    /// What the actuators deliver at the current state and commands, computed by the first
    /// get that asks for it after a change: a master that exchanges the navigation outputs
    /// alone never pays for it. A cache, not state.
    #[serde(skip)]
    delivered: OnceCell<Delivered>,
    /// Model Exchange: the time the master's solver set last (the time of an event update).
    #[serde(default)]
    time_s: f64,
    /// The RCS commands on their way to the valves (`rcs_valve_delay`; empty without).
    #[serde(default)]
    rcs_history: crate::physics::plant::RcsHistory,
}

impl LanderPlant {
    /// Brings the running plant up to the fault parameters, which are tunable: a master may
    /// have set them since the last step or event (`physics::faults`). Refuses a stuck
    /// thruster the RCS model has none of.
    fn apply_faults(&mut self) -> Result<(), ModelError> {
        self.sync_engine_health();
        let Some((plant, _)) = self.running.as_ref() else {
            return Ok(());
        };
        match (self.parameters.rcs_stuck.fault(), &plant.thrusters) {
            (Some((k, _)), None) => Err(ModelError::Refused(format!(
                "rcs_stuck_thruster = {}: the torque model (rcs_model = 1) has no thrusters \
                 to stick; fly rcs_model = 2 (thrusters)",
                k + 1
            ))),
            _ => Ok(()),
        }
    }

    /// The engine health parameter, which is tunable, into the running plant (the part of
    /// [`LanderPlant::apply_faults`] that cannot refuse).
    #[inline]
    fn sync_engine_health(&mut self) {
        if let Some((plant, _)) = self.running.as_mut() {
            plant.engines.health = self.parameters.engines.health;
        }
    }

    /// The RCS duties the valves act on: the commanded ones with a stuck thruster's forced.
    fn valve_duty(&self) -> [f64; THRUSTER_COUNT] {
        self.parameters.rcs_stuck.duty(&self.rcs_duty)
    }

    fn refresh_outputs(&mut self) {
        // The outputs show the engine health set since the last step; a stuck thruster the
        // RCS model lacks is refused by the next step, not here.
        self.sync_engine_health();
        self.delivered = OnceCell::new();
        if let Some((plant, run)) = &self.running {
            self.outputs.show(plant, run, self.parameters.m0_kg);
            return;
        }
        // Initialization mode: show the initial state the parameters give, when they are
        // valid; otherwise the raw parameter values (validation reports the error).
        let p = &self.parameters;
        match Plant::new(p) {
            Ok((plant, run, _)) => self.outputs.show(&plant, &run, p.m0_kg),
            Err(_) => {
                self.outputs = Outputs {
                    r_nue: p.r0_nue_m.into(),
                    v_nue: p.v0_nue_mps.into(),
                    q_body_to_nue: p.q0_body_to_nue,
                    omega_body: p.omega0_body_radps.into(),
                    mass: p.m0_kg,
                    altitude: p.r0_nue_m.y,
                    ..Outputs::default()
                };
            }
        }
    }

    /// What the actuators deliver at the state the outputs show (see `delivered`); zero
    /// while invalid parameters leave no plant to show.
    fn delivered(&self) -> &Delivered {
        self.delivered.get_or_init(|| {
            let provisional;
            let (plant, run) = match &self.running {
                Some((plant, run)) => (plant, run),
                None => match Plant::new(&self.parameters) {
                    Ok((plant, run, _)) => {
                        provisional = (plant, run);
                        (&provisional.0, &provisional.1)
                    }
                    Err(_) => return Delivered::default(),
                },
            };
            // Thruster model: the thrusters commanded on at the start of the coming step.
            let firing = self.valve_duty().map(|d| d > 0.0);
            plant.delivered_run(
                run,
                &self.commands,
                &firing,
                plant.engines_cut(run) || plant.stopped_at(run).is_some(),
            )
        })
    }

    /// Element `i` of `specific_force_mean_body`: the mean over the last step, or before any
    /// step (and in Model Exchange) the instantaneous specific force.
    fn specific_force_mean(&self, i: usize) -> f64 {
        match self
            .running
            .as_ref()
            .and_then(|(_, run)| run.specific_force_mean_body())
        {
            Some(mean) => mean[i],
            None => self.delivered().specific_force_body_mps2[i],
        }
    }

    /// Element `i` of `omega_mean_body`: the mean over the last step, or before any step (and
    /// in Model Exchange) the body rate.
    fn omega_mean(&self, i: usize) -> f64 {
        match self
            .running
            .as_ref()
            .and_then(|(_, run)| run.omega_mean_body())
        {
            Some(mean) => mean[i],
            None => self.outputs.omega_body[i],
        }
    }

    /// The landing gear's view of the shown state (zeros and false without the gear or
    /// before initialization).
    fn gear_view(&self) -> crate::physics::plant::GearStatus {
        self.running
            .as_ref()
            .and_then(|(plant, run)| plant.gear_status(run))
            .unwrap_or_default()
    }

    fn touchdown_field(&self, f: impl Fn(&crate::physics::plant::Touchdown) -> f64) -> f64 {
        self.running
            .as_ref()
            .and_then(|(_, run)| run.touchdown.as_ref())
            .map_or(0.0, f)
    }
}

impl PlantParameters {
    /// Every check of the parameters: each value against its declaration (as the FMI layer
    /// checks it on every set, here for parameters that reach the plant without a layer),
    /// then what declarations cannot say ([`PlantParameters::validate`]).
    pub fn check(&self) -> Result<(), ParameterError> {
        let model = LanderPlant {
            parameters: self.clone(),
            ..LanderPlant::default()
        };
        fmi_model::parameter::check_declared(&model)?;
        self.validate()
    }
}

fn restored(field: &str, value: impl std::fmt::Display, reason: &str) -> ModelError {
    ModelError::Other(format!("restored state {field} = {value}: {reason}"))
}

/// How far the norm of a restored attitude quaternion may be from 1. The Co-Simulation
/// step renormalises after every sub-step, but a Model Exchange master integrates `q` as it
/// stands: the equations use only its direction (`body_to_nue` and the outputs normalise,
/// the event update renormalises) and the derivative's norm term
/// `k (1 - |q|^2) q` (`k = 1/s`) pulls |q| back to 1 against the integrator's drift. For
/// explicit Euler at step `h` the two balance at `|q|^2 - 1 ~ h omega^2 / (8 k)`, i.e.
/// `|q| - 1 ~ h omega^2 / 16`; RK4 stays orders closer. 0.1 admits Euler up to
/// `h omega^2 = 1.6` (at 0.1 s: 4 rad/s, 230 deg/s, where 0.1 s steps no longer resolve the
/// rotation), so every state a reasonable integrator leaves passes; a norm off by more is
/// no state an instance produced, though `set_states` still evaluates it (see
/// `physics::continuous::QUATERNION_NORM_RANGE`).
const RESTORED_QUATERNION_NORM_TOLERANCE: f64 = 0.1;

/// How far below the dry mass a restored mass may be, relative to the dry mass. The
/// exhaustion event cuts the engines at the dry mass, but a Model Exchange integrator steps
/// over the crossing before its master locates it: the accepted step can end up to one
/// step's burn below. 1e-3 (0.6 kg for the default plant) is over a second of full thrust
/// (0.54 kg/s by default), longer than any step that resolves a powered descent.
const RESTORED_MASS_BELOW_DRY_RELATIVE: f64 = 1e-3;

/// Whether |omega|^2 x the largest inertia, a bound of |omega x (I omega)|, is finite.
#[inline(always)]
fn gyroscopic_torque_representable(omega_body: &Body, plant: &Plant) -> bool {
    (omega_body.0.norm_squared() * plant.inertia_body_kgm2.max()).is_finite()
}

/// A run the plant could have reached, in Co-Simulation or under a reasonable Model
/// Exchange integrator: a state `set_states` would accept (`Plant::check_evaluable`:
/// finite, bounded, evaluable), propellant between just below dry mass and `m0_kg`, an
/// attitude of nearly unit norm, consistent event flags.
fn check_run(run: &PlantRun, plant: &Plant, m0_kg: f64) -> Result<(), ModelError> {
    let x = &run.state;
    if !x.is_finite() {
        return Err(restored("plant state", format!("{x:?}"), "not finite"));
    }
    if let Err(e) = plant.check_evaluable(x) {
        return Err(restored(&e.element.name(), e.value, &e.reason));
    }
    let lowest_mass_kg = plant.dry_mass_kg * (1.0 - RESTORED_MASS_BELOW_DRY_RELATIVE);
    if x.mass_kg < lowest_mass_kg || x.mass_kg > m0_kg {
        return Err(restored(
            "mass",
            x.mass_kg,
            &format!(
                "outside [dry_mass (1 - {RESTORED_MASS_BELOW_DRY_RELATIVE:e}), m0] = \
                 [{lowest_mass_kg}, {m0_kg}] kg"
            ),
        ));
    }
    // As for omega0_body at initialization: omega x (I omega) must stay representable.
    if !gyroscopic_torque_representable(&x.omega_body, plant) {
        return Err(restored(
            "omega_body",
            format!("{:?}", x.omega_body.0.as_slice()),
            "|omega_body|^2 x largest inertia (gyroscopic torque) overflows",
        ));
    }
    let norm = x.q_body_to_nue.norm();
    if (norm - 1.0).abs() > RESTORED_QUATERNION_NORM_TOLERANCE {
        return Err(restored(
            "q_body_to_nue norm",
            norm,
            "not a unit quaternion",
        ));
    }
    if run.propellant_exhausted && x.mass_kg != plant.dry_mass_kg {
        return Err(restored(
            "mass",
            x.mass_kg,
            "propellant exhausted but mass is not the dry mass",
        ));
    }
    // The optional effects' discrete state: finite, and empty when the effect is off.
    if !run.slosh.0.iter().all(|v| v.is_finite())
        || (plant.slosh.is_none() && run.slosh.0.iter().any(|v| *v != 0.0))
    {
        return Err(restored(
            "slosh_displacement",
            format!("{:?}", run.slosh.0),
            "not finite, or nonzero without slosh",
        ));
    }
    // Every step leaves each pendulum's direction a unit vector.
    if plant.slosh.is_some()
        && (0..crate::physics::slosh::TANK_COUNT)
            .any(|k| (run.slosh.direction(k).norm() - 1.0).abs() > 1e-9)
    {
        return Err(restored(
            "slosh_displacement",
            format!("{:?}", run.slosh.0),
            "a pendulum's direction is not a unit vector",
        ));
    }
    if run.gear.crashed_at_s.is_some_and(|t| !t.is_finite())
        || (plant.gear.is_none() && run.gear != crate::physics::plant::GearRun::default())
    {
        return Err(restored(
            "gear",
            format!("{:?}", run.gear),
            "not finite, or set without the gear",
        ));
    }
    let mean_finite = run
        .specific_force_integral_body
        .iter()
        .chain(run.omega_integral_body.iter())
        .all(|v| v.is_finite())
        && run.mean_span_s.is_finite()
        && run.mean_span_s >= 0.0;
    if !mean_finite {
        return Err(restored(
            "specific force and body rate integrals",
            format!(
                "{:?}, {:?} over {} s",
                run.specific_force_integral_body.as_slice(),
                run.omega_integral_body.as_slice(),
                run.mean_span_s
            ),
            "not finite, or a negative span",
        ));
    }
    if let Some(td) = &run.touchdown {
        let finite = td.time_s.is_finite()
            && td.tilt_rad.is_finite()
            && td.v_nue_mps.0.iter().all(|v| v.is_finite())
            && td.omega_body_radps.0.iter().all(|v| v.is_finite())
            && td.q_body_to_nue.coords.iter().all(|v| v.is_finite());
        if !finite {
            return Err(restored("touchdown", format!("{td:?}"), "not finite"));
        }
    }
    Ok(())
}

/// The RCS history of a restored state: finite, pulses that end after they start.
fn check_history(history: &crate::physics::plant::RcsHistory) -> Result<(), ModelError> {
    let pulses_finite = history
        .pulses
        .iter()
        .flatten()
        .flatten()
        .all(|(s, e)| s.is_finite() && e.is_finite() && s <= e);
    let torques_finite = history
        .torques
        .iter()
        .flatten()
        .all(|(from, torque)| from.is_finite() && torque.iter().all(|v| v.is_finite()));
    if !pulses_finite || !torques_finite {
        return Err(restored(
            "rcs history",
            format!("{history:?}"),
            "not finite (or a pulse ending before it starts)",
        ));
    }
    Ok(())
}

/// Most RK4 sub-steps one Co-Simulation step may take (about a second of CPU). Without a bound, a
/// huge communication step never returns: 1e300 s in orbit about the spherical Moon, or 1 s
/// with `integration_step` = 1e-12 s, would hang the master's call for minutes or forever.
const MAX_SUB_STEPS_PER_STEP: f64 = 1e6;

/// An IMU integrates rate and specific force over its sample: the sensors take the means
/// over the step that ends at the communication point, not the values at it.
const KINEMATICS: [Member; 5] = [
    same(groups::KINEMATICS[0]),
    same(groups::KINEMATICS[1]),
    same(groups::KINEMATICS[2]),
    Member {
        member: groups::KINEMATICS[3],
        variable: "omega_mean_body",
    },
    Member {
        member: groups::KINEMATICS[4],
        variable: "specific_force_mean_body",
    },
];

const TERMINALS: &[Terminal] = &[
    Terminal {
        name: "navigation",
        matching_rule: MatchingRule::Plug,
        kind: groups::NAVIGATION_KIND,
        description: "The true vehicle state, as a controller takes it",
        members: &same_names(groups::NAVIGATION),
    },
    Terminal {
        name: "commands",
        matching_rule: MatchingRule::Plug,
        kind: groups::COMMANDS_KIND,
        description: "Thrust, torque and RCS duty commands, from the controller",
        members: &same_names(groups::COMMANDS),
    },
    Terminal {
        name: "kinematics",
        matching_rule: MatchingRule::Plug,
        kind: groups::KINEMATICS_KIND,
        description: "The true motion and specific force, as the sensors take them",
        members: &KINEMATICS,
    },
];

impl Model for LanderPlant {
    const MODEL_IDENTIFIER: &'static str = "LanderPlant";
    /// 2: the RCS thruster model's state (modulators; pulses still firing at a step end);
    /// 3: the delivered actuation is no longer stored (computed when read);
    /// 4: the landing gear, the optional actuator effects and the RCS command history;
    /// 5: the specific force and the body rate integrated over the step;
    /// 6: slosh tanks following the fill level (the plant's slosh constants);
    /// 7: the faults (engine health, a stuck RCS thruster).
    const STATE_VERSION: u32 = 7;
    const MODEL_NAME: &'static str = "LanderPlant";
    const VERSION: &'static str = env!("CARGO_PKG_VERSION");
    const DESCRIPTION: &'static str = "6-DOF lunar lander: rigid-body attitude, flat (paper eq. 2) or spherical rotating \
         (eq. 1) translation, throttleable engines and RCS with saturation, RK4, touchdown and propellant events";
    const DEFAULT_EXPERIMENT: Experiment = Experiment {
        start_time: 0.0,
        stop_time: 172.0,
        step_size: 0.01,
        tolerance: None,
    };

    fn declarations() -> &'static [Declaration<Self>] {
        DECLARATIONS
    }

    fn terminals() -> &'static [Terminal] {
        TERMINALS
    }

    fn output_dependencies(output: &str) -> Dependencies {
        // The navigation outputs are functions of the state alone, so a controller can close
        // its loop through them without an algebraic loop. The delivered actuator values
        // depend on the current command when no lag is configured.
        match output {
            "thrust_actual" | "engine_torque_body" => Dependencies::Inputs(&["thrust_cmd"]),
            "specific_force_body" => Dependencies::Inputs(&["thrust_cmd", "rcs_duty"]),
            "torque_actual_body" => Dependencies::Inputs(&["torque_cmd_body", "rcs_duty"]),
            // The thrusters' force: on or off by rcs_duty; the torque model has none.
            "rcs_force_body" => Dependencies::Inputs(&["rcs_duty"]),
            _ => Dependencies::NoInputs,
        }
    }

    fn calculate_values(&mut self, _log: &mut Log) {
        self.refresh_outputs();
    }

    /// Exact, by forward-mode automatic differentiation of the equations
    /// (`physics::sensitivity`, `fmu::derivatives`).
    const PROVIDES_DIRECTIONAL_DERIVATIVES: bool = true;

    fn directional_derivative(
        &mut self,
        unknowns: &[fmi_model::ScalarRef],
        knowns: &[fmi_model::ScalarRef],
        seed: &[f64],
        sensitivity: &mut [f64],
    ) -> Result<(), ModelError> {
        self.directional(unknowns, knowns, seed, sensitivity)
    }

    fn exit_initialization(&mut self, _start_time: f64, log: &mut Log) -> Result<(), ModelError> {
        let (plant, run, warning) = Plant::new(&self.parameters).map_err(ModelError::from)?;
        if let Some(w) = warning {
            log.warning(w);
        }
        self.running = Some((plant, run));
        Ok(())
    }

    fn validate_restored(&self, initialized: bool) -> Result<(), ModelError> {
        let (true, Some((plant, run))) = (initialized, &self.running) else {
            // Before initialization parameters are checked at exit_initialization; a run
            // exists exactly after it.
            return match (initialized, &self.running) {
                (false, None) => Ok(()),
                _ => Err(restored(
                    "initialized",
                    initialized,
                    "disagrees with the model's run",
                )),
            };
        };
        let (fresh, _, _) = Plant::new(&self.parameters).map_err(ModelError::from)?;
        // A fault set since the last step reaches the plant at the next one.
        let mut synced = plant.clone();
        synced.engines.health = self.parameters.engines.health;
        if synced != fresh {
            return Err(restored(
                "plant constants",
                "",
                "differ from what the parameters give",
            ));
        }
        check_run(run, plant, self.parameters.m0_kg)?;
        check_history(&self.rcs_history)
    }

    fn do_step(&mut self, t: f64, h: f64, log: &mut Log) -> Result<StepEnd, ModelError> {
        self.apply_faults()?;
        let duty = self.valve_duty();
        let Some((plant, run)) = self.running.as_mut() else {
            return Err(ModelError::Other(
                "do_step before exit_initialization".into(),
            ));
        };
        if plant.stopped_at(run).is_some() {
            return Ok(StepEnd::Stopped {
                time: t,
                terminated: true,
                reason: "the lander is on the ground".into(),
            });
        }
        let finest_step_s = match &plant.gear {
            None => plant.integration_step_s,
            Some(gear) => plant.integration_step_s.min(gear.contact_step_s),
        };
        let sub_steps = h / finest_step_s;
        if sub_steps > MAX_SUB_STEPS_PER_STEP {
            return Err(ModelError::Refused(format!(
                "communicationStepSize {h} s would take {sub_steps:e} RK4 sub-steps of \
                 integration_step = {} s; at most {MAX_SUB_STEPS_PER_STEP:e} per step: \
                 use shorter communication steps",
                plant.integration_step_s
            )));
        }
        let history_span = (crate::physics::plant::RCS_HISTORY_CAPACITY - 2) as f64 * h;
        if plant.rcs_valve_delay_s > history_span {
            return Err(ModelError::Refused(format!(
                "rcs_valve_delay = {} s is longer than {} communication steps of {h} s, the \
                 most commands the valve history holds: use longer communication steps",
                plant.rcs_valve_delay_s,
                crate::physics::plant::RCS_HISTORY_CAPACITY - 2
            )));
        }
        let before = run.checkpoint(plant);
        run.start_means();
        let history_before = (plant.rcs_valve_delay_s > 0.0).then_some(self.rcs_history);
        let advance =
            plant.advance_with_history(run, &mut self.rcs_history, &self.commands, &duty, t, h);
        if !run.state.is_finite() {
            run.restore(&before);
            if let Some(history) = history_before {
                self.rcs_history = history;
            }
            return Err(ModelError::Other(format!(
                "the state became non-finite in the step from t = {t} s"
            )));
        }
        // A body rate can grow within a step until omega x (I omega) overflows (found by the
        // fuzzer from a restored rate of 1e85 rad/s): the outputs' derivatives would be NaN.
        if !gyroscopic_torque_representable(&run.state.omega_body, plant) {
            run.restore(&before);
            if let Some(history) = history_before {
                self.rcs_history = history;
            }
            return Err(ModelError::Other(format!(
                "the body rate became so large in the step from t = {t} s that its gyroscopic \
                 torque overflows"
            )));
        }
        if run.propellant_exhausted && !before.propellant_exhausted() {
            log.warning(format!(
                "propellant exhausted in the step from t = {t} s: mass = dry_mass = {} kg, engines cut",
                plant.dry_mass_kg
            ));
        }
        if let (Some(td), false) = (run.touchdown, before.had_touchdown()) {
            if plant.gear.is_some() {
                log.info(format!(
                    "touchdown (first footpad contact) at t = {} s: v_nue = [{:.3}, {:.3}, {:.3}] m/s, tilt = {:.2} deg",
                    td.time_s,
                    td.v_nue_mps.0.x,
                    td.v_nue_mps.0.y,
                    td.v_nue_mps.0.z,
                    td.tilt_rad.to_degrees()
                ));
            }
        }
        if run.gear.tipped_over && !before.gear().tipped_over {
            log.warning(format!("the lander tipped over in the step from t = {t} s"));
        }
        if let Some(slosh) = &plant.slosh {
            warn_of_slosh_swing(slosh, &before, run, t, log);
        }
        Ok(match advance {
            Advance::Reached => StepEnd::Complete,
            Advance::Touchdown(time) if plant.gear.is_some() => StepEnd::Stopped {
                time,
                terminated: true,
                reason: format!(
                    "the centre of mass reached the terrain at t = {time} s (the lander fell over or the gear gave way)"
                ),
            },
            Advance::Touchdown(time) => {
                let td = run
                    .touchdown
                    .expect("a touchdown advance records the touchdown");
                StepEnd::Stopped {
                    time,
                    terminated: true,
                    reason: format!(
                        "touchdown at t = {time} s: v_nue = [{:.3}, {:.3}, {:.3}] m/s, tilt = {:.2} deg",
                        td.v_nue_mps.0.x,
                        td.v_nue_mps.0.y,
                        td.v_nue_mps.0.z,
                        td.tilt_rad.to_degrees()
                    ),
                }
            }
        })
    }
}

/// A warning when a slosh pendulum swings out of the range its model holds in: past the
/// linear sloshing theory's 30 deg, and past level with its hinge (the liquid no longer at
/// the bottom of its tank: a tumble, or thrust against the liquid).
fn warn_of_slosh_swing(
    slosh: &Slosh,
    before: &RunCheckpoint,
    run: &PlantRun,
    t: f64,
    log: &mut Log,
) {
    let Some(pendulums_before) = before.slosh() else {
        return;
    };
    let was = slosh.largest_swing(pendulums_before, before.mass_kg());
    let now = slosh.largest_swing(&run.slosh, run.state.mass_kg);
    if now > LINEAR_RANGE_RAD && was <= LINEAR_RANGE_RAD {
        log.warning(format!(
            "slosh: a pendulum swung {:.1} deg from the thrust axis in the step from t = {t} s, \
             beyond the 30 deg of the linear sloshing theory its length and mass come from \
             (docs/plant-slosh.md)",
            now.to_degrees()
        ));
    }
    let level = std::f64::consts::FRAC_PI_2;
    if now > level && was <= level {
        log.warning(format!(
            "slosh: a pendulum swung {:.1} deg from the thrust axis in the step from t = {t} s, \
             above its hinge: the liquid has left the bottom of its tank, where no \
             equivalent pendulum describes it (docs/plant-slosh.md)",
            now.to_degrees()
        ));
    }
}

fmi_model::enumeration! {
    TranslationModelKind = "TranslationModel", "Translational equations of motion" {
        Flat: "flat", "Flat, non-rotating Moon, uniform gravity (paper eq. 2)";
        Spherical: "spherical", "Spherical Moon with rotation and central gravity (paper eq. 1, corrected)";
    }
}

fmi_model::enumeration! {
    RcsModelKind = "RcsModel", "How the reaction control system is modelled" {
        Torque: "torque", "Continuous torque per axis from torque_cmd_body, saturated at rcs_torque_limit (the paper's model)";
        Thrusters: "thrusters", "Eight on/off thrusters fired from the start of each step for rcs_duty of it";
    }
}

fmi_model::enumeration! {
    RcsStuckMode = "RcsStuckMode", "How a stuck RCS thruster's valve failed" {
        Off: "off", "Stuck closed: no force, whatever its command";
        On: "on", "Stuck open: full force over every step, commanded or not";
    }
}

fn running_flag(m: &LanderPlant, f: impl Fn(&PlantRun) -> bool) -> bool {
    m.running.as_ref().is_some_and(|(_, run)| f(run))
}

const NUE: &[&str] = &["North", "Up", "East"];
const NUE_AXES: &[&str] = &[
    "x (North) component of the vector part",
    "y (Up) component of the vector part",
    "z (East) component of the vector part",
];
const BODY: &[&str] = &[
    "about body x (yaw)",
    "about body y (roll, the thrust axis)",
    "about body z (pitch)",
];
const BODY_AXES: &[&str] = &["body x", "body y", "body z"];
const QUATERNION: &[&str] = &[
    "scalar part",
    "vector part x",
    "vector part y",
    "vector part z",
];
const Q_NUE: &[&str] = &["scalar part", NUE_AXES[0], NUE_AXES[1], NUE_AXES[2]];
const THRUSTERS: &[&str] = &[
    "thruster 1",
    "thruster 2",
    "thruster 3",
    "thruster 4",
    "thruster 5",
    "thruster 6",
    "thruster 7",
    "thruster 8",
];
const THRUSTER_XYZ: &[&str] = &[
    "thruster 1, body x",
    "thruster 1, body y",
    "thruster 1, body z",
    "thruster 2, body x",
    "thruster 2, body y",
    "thruster 2, body z",
    "thruster 3, body x",
    "thruster 3, body y",
    "thruster 3, body z",
    "thruster 4, body x",
    "thruster 4, body y",
    "thruster 4, body z",
    "thruster 5, body x",
    "thruster 5, body y",
    "thruster 5, body z",
    "thruster 6, body x",
    "thruster 6, body y",
    "thruster 6, body z",
    "thruster 7, body x",
    "thruster 7, body y",
    "thruster 7, body z",
    "thruster 8, body x",
    "thruster 8, body y",
    "thruster 8, body z",
];
const LEGS: &[&str] = &["leg 1", "leg 2", "leg 3", "leg 4"];
const LEG_XYZ: &[&str] = &[
    "leg 1, body x",
    "leg 1, body y",
    "leg 1, body z",
    "leg 2, body x",
    "leg 2, body y",
    "leg 2, body z",
    "leg 3, body x",
    "leg 3, body y",
    "leg 3, body z",
    "leg 4, body x",
    "leg 4, body y",
    "leg 4, body z",
];
const TANKS: &[&str] = &["tank 1", "tank 2"];
const SLOSH_XZ: &[&str] = &[
    "tank 1, body x",
    "tank 1, body z",
    "tank 2, body x",
    "tank 2, body z",
];
const TANK_XYZ: &[&str] = &[
    "tank 1, body x",
    "tank 1, body y",
    "tank 1, body z",
    "tank 2, body x",
    "tank 2, body y",
    "tank 2, body z",
];
const HALF_PI: f64 = std::f64::consts::FRAC_PI_2;
const TRANSLATION_STATE: &[&str] = &[
    "1 (flat: r_nue North; spherical: radius)",
    "2 (flat: r_nue Up; spherical: longitude)",
    "3 (flat: r_nue East; spherical: latitude)",
    "4 (flat: v_nue North; spherical: East velocity)",
    "5 (flat: v_nue Up; spherical: North velocity)",
    "6 (flat: v_nue East; spherical: Up velocity)",
];

/// The declarations, one line each so that they read as a table. Start values are those of
/// `LanderPlant::default()`; the bounds of a single value are checked here only
/// (`PlantParameters::check`), relations between parameters in `PlantParameters::validate`.
#[rustfmt::skip]
static DECLARATIONS: &[Declaration<LanderPlant>] = &[
    // Inputs (LanderGnc outputs).
    decl!(1, input thrust_cmd: commands.thrust_cmd_n, "N", "Commanded total engine thrust along body +y; at or below engine_off_threshold the engines are off, otherwise saturated to engine_count x [engine_thrust_min, engine_thrust_max]"),
    decl!(2, input torque_cmd_body[3]: commands.torque_cmd_body_nm, "N.m", "Commanded RCS torque, saturated to rcs_torque_limit (torque model; ignored by the thruster model)", components = BODY),
    decl!(60, input rcs_duty[8]: rcs_duty, "1", "Thruster model: fraction of the coming communication step during which each RCS thruster fires, from the step's start; clamped to [0, 1]; a pulse below rcs_min_impulse_bit is not fired unless it continues one (ignored by the torque model)", components = THRUSTERS),
    // Outputs (LanderGnc inputs).
    decl!(10, output r_nue[3]: outputs.r_nue, "m", "Position of the centre of mass (landing site at the origin)", components = NUE),
    decl!(13, output v_nue[3]: outputs.v_nue, "m/s", "Velocity relative to the Moon's surface", components = NUE),
    decl!(16, output q_body_to_nue[4]: outputs.q_body_to_nue, "1", "Attitude quaternion body to NUE (Hamilton)", components = Q_NUE),
    decl!(20, output omega_body[3]: outputs.omega_body, "rad/s", "Body angular rate", components = BODY),
    decl!(23, output mass: outputs.mass, "kg", "Current total mass"),
    // Extra outputs.
    decl!(24, output altitude: outputs.altitude, "m", "Height above the surface: r_nue[2] for the flat Moon, radius minus moon_radius for the spherical one"),
    decl!(25, output thrust_actual: get |m, _| m.delivered().thrust_n, "N", "Engine thrust delivered after saturation, lag and propellant cut-off"),
    decl!(26, output torque_actual_body[3]: get |m, i| m.delivered().rcs_torque_body_nm[i], "N.m", "RCS torque delivered after saturation and lag (thruster model: of the thrusters commanded on at the start of the coming step)", components = BODY_AXES),
    decl!(47, output rcs_force_body[3]: get |m, i| m.delivered().rcs_force_body_n[i], "N", "Thruster model: force of the thrusters commanded on at the start of the coming step (0 in the torque model)", components = BODY_AXES),
    decl!(70, output specific_force_body[3]: get |m, i| m.delivered().specific_force_body_mps2[i], "m/s2", "Non-gravitational acceleration of the centre of mass (engine thrust, RCS thruster forces and, with the landing gear, contact forces, over the mass) in body axes: what an ideal accelerometer at the centre of mass measures (0 in free fall and once the run is frozen at touchdown)", components = BODY_AXES),
    decl!(73, output specific_force_mean_body[3]: get |m, i| m.specific_force_mean(i), "m/s2", "Mean of specific_force_body over the last communication step: its integral over [t - h, t] (RK4 quadrature along the plant's sub-steps, split at thruster switch times and events) over h, what an ideal accelerometer's velocity increment over the step divided by h gives; a step cut short by the end of the run: over the part flown. Before the first step, and in Model Exchange, specific_force_body itself (the instantaneous value, which depends on the inputs then; the declared dependencies, none, are those of Co-Simulation steps)", components = BODY_AXES),
    decl!(76, output omega_mean_body[3]: get |m, i| m.omega_mean(i), "rad/s", "Mean of omega_body over the last communication step: its integral over [t - h, t] (RK4 quadrature along the plant's sub-steps, as specific_force_mean_body) over h, what an ideal gyro's angle increment over the step divided by h gives (to first order in the turn over the step); a step cut short by the end of the run: over the part flown. Before the first step, and in Model Exchange, omega_body itself", components = BODY_AXES),
    decl!(29, output engine_torque_body[3]: get |m, i| m.delivered().engine_torque_body_nm[i], "N.m", "Disturbance torque of the misaligned/offset thrust line", components = BODY_AXES),
    decl!(32, output propellant_used: outputs.propellant_used, "kg", "m0 minus the current mass"),
    Declaration::boolean(33, "propellant_exhausted", role::discrete_output, "True once the mass has reached dry_mass; the engines deliver no thrust from then on", |m| running_flag(m, |r| r.propellant_exhausted), |_, _| {}),
    Declaration::boolean(34, "touchdown", role::discrete_output, "True once the altitude has reached 0; the simulation ends there (the FMU asks the master to terminate). With gear_enabled: true from the first footpad contact with the terrain, and the simulation goes on (it ends when the centre of mass reaches the terrain)", |m| running_flag(m, |r| r.touchdown.is_some()), |_, _| {}),
    decl!(35, discrete_output touchdown_time: get |m, _| m.touchdown_field(|t| t.time_s), "s", "Time of touchdown (0 before touchdown)"),
    decl!(36, discrete_output touchdown_v_nue[3]: get |m, i| m.touchdown_field(|t| t.v_nue_mps.0[i]), "m/s", "Velocity at touchdown (0 before touchdown)", components = NUE),
    decl!(39, discrete_output touchdown_q_body_to_nue[4]: get |m, i| m.touchdown_field(|t| quaternion_to_scalar_first(&t.q_body_to_nue)[i]), "1", "Attitude at touchdown (0 before touchdown)", components = QUATERNION),
    decl!(43, discrete_output touchdown_omega_body[3]: get |m, i| m.touchdown_field(|t| t.omega_body_radps.0[i]), "rad/s", "Body rate at touchdown (0 before touchdown)", components = BODY_AXES),
    decl!(46, discrete_output touchdown_tilt: get |m, _| m.touchdown_field(|t| t.tilt_rad), "rad", "Angle between the thrust axis and the local vertical at touchdown (0 before touchdown)"),
    // Landing gear and terrain (gear_enabled; docs/plant-gear.md).
    decl!(80, discrete_output foot_contact[4]: get |m, i| if m.gear_view().contact.stroke_m[i] > 0.0 { 1.0 } else { 0.0 }, "1", "Landing gear: 1 while footpad k touches the terrain, else 0 (0 without the gear)", components = LEGS),
    decl!(84, output leg_stroke[4]: get |m, i| m.gear_view().contact.stroke_m[i], "m", "Landing gear: compression of leg k, the footpad's penetration along the terrain normal (0 without the gear)", components = LEGS),
    Declaration::boolean(88, "tipped_over", role::discrete_output, "Landing gear: true once, after touchdown, the centre of mass seen along gravity has left the footprint of the footpads (tilt beyond gear_static_stability_angle on flat ground) or the lander lies on its side (tilt from the terrain normal > 80 deg)", |m| m.gear_view().tipped_over, |_, _| {}),
    Declaration::boolean(89, "settled", role::discrete_output, "Landing gear: true while at rest on the gear after touchdown (three or more footpads on the terrain, |v_nue| < 0.01 m/s, |omega_body| < 0.01 rad/s, not tipped over)", |m| m.gear_view().settled, |_, _| {}),
    decl!(400, parameter gear_enabled: parameters.gear.enabled as bool, "Landing gear and terrain contact (Co-Simulation only: refused in Model Exchange); false: no ground contact, the run ends at altitude 0 as without the gear"),
    decl!(401, parameter gear_footpad_body[12]: parameters.gear.footpad_body_m, "m", "Footpad k (elements 3k+1..3k+3) of the unloaded leg relative to the centre of mass, body axes; default radius 1.2 m at azimuths 45, 135, 225, 315 deg, 1 m below (body y = -1)", components = LEG_XYZ),
    decl!(413, parameter gear_stiffness: parameters.gear.stiffness_npm, "N/m", "Spring stiffness of one leg along the terrain normal", above = 0.0),
    decl!(414, parameter gear_damping: parameters.gear.damping_nspm, "N.s/m", "Damping of one leg along the terrain normal", min = 0.0),
    decl!(415, parameter gear_max_stroke: parameters.gear.max_stroke_m, "m", "Stroke at which a leg bottoms out (stiffness x 100 beyond it)", above = 0.0),
    decl!(416, parameter gear_friction_coefficient: parameters.gear.friction_coefficient, "1", "Coulomb friction coefficient footpad/soil", min = 0.0),
    decl!(417, parameter gear_friction_velocity: parameters.gear.friction_velocity_mps, "m/s", "Regularisation velocity of the friction: full Coulomb friction well above it, viscous below", above = 0.0),
    decl!(418, parameter terrain_height: parameters.gear.terrain_height_m, "m", "Height (Up) of the terrain plane at the landing site (NUE origin)"),
    decl!(419, parameter terrain_slope: parameters.gear.terrain_slope_rad, "rad", "Slope of the terrain plane from the horizontal, [0, 60 deg)", min = 0.0, below = crate::physics::parameters::MAX_TERRAIN_SLOPE_RAD),
    decl!(420, parameter terrain_slope_azimuth: parameters.gear.terrain_slope_azimuth_rad, "rad", "Direction the terrain falls towards, from North towards East"),
    decl!(421, parameter engine_cutoff_mode: parameters.gear.engine_cutoff_mode as i32, "Landing gear engine cut-off: 0 none, 1 at the first footpad contact (touchdown sensor), 2 when the lowest footpad is engine_cutoff_height above the terrain; the thrust is 0 from then on", int_min = 0, int_max = 2),
    decl!(422, parameter engine_cutoff_height: parameters.gear.engine_cutoff_height_m, "m", "engine_cutoff_mode 2: height of the lowest footpad above the terrain (along its normal) at which the engines are cut", min = 0.0),
    decl!(423, parameter gear_contact_step: parameters.gear.contact_step_s, "s", "Largest RK4 sub-step while a footpad is on or near the terrain (the contact is stiff)", above = 0.0),
    decl!(424, calculated_parameter gear_static_stability_angle: get |m, _| crate::physics::gear::Gear::new(&m.parameters.gear).static_stability_angle_rad, "rad", "Static stability angle of the footprint: atan(d / h), d the shortest distance from the centre of mass to a footprint edge, h the centre of mass height above the footpads"),
    // Propellant slosh (slosh_enabled; docs/plant-slosh.md).
    decl!(90, output slosh_displacement[4]: get |m, i| m.running.as_ref().and_then(|(plant, run)| plant.slosh.as_ref().map(|s| s.displacement_m(&run.slosh, run.state.mass_kg, i / 2)[i % 2])).unwrap_or(0.0), "m", "Slosh: displacement of tank k's sloshing mass across the thrust axis from its hinge (elements 2k+1, 2k+2: body x, body z; 0 without slosh)", components = SLOSH_XZ),
    decl!(440, parameter slosh_enabled: parameters.slosh.enabled as bool, "Propellant slosh, one spherical pendulum per tank coupled both ways with the rigid body (Co-Simulation only: refused in Model Exchange)"),
    decl!(441, parameter slosh_tank_radius[2]: parameters.slosh.tank_radius_m, "m", "Radius of each upright cylindrical tank", above = 0.0, components = TANKS),
    decl!(443, parameter slosh_fill_height[2]: parameters.slosh.fill_height_m, "m", "Liquid depth in each tank at the initial mass m0 (it falls with the propellant left)", above = 0.0, components = TANKS),
    decl!(445, parameter slosh_liquid_mass[2]: parameters.slosh.liquid_mass_kg, "kg", "Liquid mass in each tank at the initial mass m0 (0: no slosh in it; it falls with the propellant left); the sloshing part is slosh_mass", min = 0.0, components = TANKS),
    decl!(447, parameter slosh_hinge_body[6]: parameters.slosh.hinge_body_m, "m", "Hinge of tank k's pendulum (elements 3k+1..3k+3) at the initial fill, relative to the rigid part's centre of mass, body axes; the tank bottom lies below it on body -y, and the hinge moves with the fill", components = TANK_XYZ),
    decl!(453, parameter slosh_damping_ratio: parameters.slosh.damping_ratio, "1", "Damping ratio of the first sloshing mode", min = 0.0, max = 1.0),
    decl!(454, parameter slosh_delta0[4]: parameters.slosh.delta0_m, "m", "Initial displacement of tank k's sloshing mass (elements 2k+1, 2k+2: body x, body z)", components = SLOSH_XZ),
    decl!(458, calculated_parameter slosh_pendulum_length[2]: get |m, i| crate::physics::slosh::Slosh::new(&m.parameters.slosh, m.parameters.dry_mass_kg, m.parameters.m0_kg).pendulums[i].length_m, "m", "Pendulum length at the initial fill, L = R / (1.8412 tanh(1.8412 h / R)); the tank-fixed slosh frequency is sqrt(g_eff / L), g_eff = thrust / mass", components = TANKS),
    decl!(460, calculated_parameter slosh_mass[2]: get |m, i| crate::physics::slosh::Slosh::new(&m.parameters.slosh, m.parameters.dry_mass_kg, m.parameters.m0_kg).pendulums[i].mass_kg, "kg", "Sloshing mass at the initial fill, m_1 = m_F 2 tanh(1.8412 h / R) / (1.8412 (1.8412^2 - 1) h / R)", components = TANKS),
    decl!(470, parameter inertia_dry_body[3]: parameters.inertia_dry_body_kgm2, "kg.m2", "Principal inertia at dry_mass; the inertia moves linearly with the propellant from inertia_body (at m0) to it; all 0 (default): inertia_body whatever the mass", min = 0.0, components = &["about body x (Ixx)", "about body y (Iyy)", "about body z (Izz)"]),
    decl!(473, parameter com_offset_dry_body[3]: parameters.com_offset_dry_body_m, "m", "With inertia_dry_body: centre of mass at dry_mass relative to where it is at m0 (moves linearly with the propellant; shifts the engine's lever arm)", components = BODY_AXES),
    // Initial state.
    decl!(100, parameter r0_nue[3]: parameters.r0_nue_m, "m", "Initial position (Up: must be above the surface)", components = NUE),
    decl!(103, parameter v0_nue[3]: parameters.v0_nue_mps, "m/s", "Initial velocity", components = NUE),
    decl!(106, parameter q0_body_to_nue[4]: parameters.q0_body_to_nue, "1", "Initial attitude body to NUE (normalised if |q0| is within 1e-3 of 1, refused otherwise)", components = QUATERNION),
    decl!(110, parameter omega0_body[3]: parameters.omega0_body_radps, "rad/s", "Initial body rate", components = BODY_AXES),
    decl!(113, parameter m0: parameters.m0_kg, "kg", "Initial total mass, > dry_mass", above = 0.0),
    // Vehicle and environment.
    decl!(120, parameter g: parameters.gravity_mps2, "m/s2", "Surface gravity of the Moon (spherical model: mu = g moon_radius^2)", above = 0.0),
    decl!(121, parameter isp: parameters.isp_s, "s", "Specific impulse of the main engines", above = 0.0),
    decl!(122, parameter g0: parameters.g0_mps2, "m/s2", "Standard gravity in the rocket equation m' = -T / (isp g0)", above = 0.0),
    decl!(123, parameter dry_mass: parameters.dry_mass_kg, "kg", "Mass without propellant; at it the engines cut out", above = 0.0),
    decl!(124, parameter inertia_body[3]: parameters.inertia_body_kgm2, "kg.m2", "Principal moment of inertia (each at most the sum of the other two)", above = 0.0, components = &["about body x (Ixx)", "about body y (Iyy)", "about body z (Izz)"]),
    Declaration::integer(130, "engine_count", role::parameter, "Number of throttleable main engines, fired together", |m: &LanderPlant| i32::try_from(m.parameters.engines.count).unwrap_or(i32::MAX), |m: &mut LanderPlant, v| m.parameters.engines.count = u32::try_from(v).unwrap_or(0)).field("parameters.engines.count").int_min(1),
    decl!(131, parameter engine_thrust_min: parameters.engines.min_thrust_per_engine_n, "N", "Minimum thrust of one engine when on, <= engine_thrust_max", min = 0.0),
    decl!(132, parameter engine_thrust_max: parameters.engines.max_thrust_per_engine_n, "N", "Maximum thrust of one engine", min = 0.0),
    decl!(133, parameter engine_off_threshold: parameters.engines.off_threshold_n, "N", "A thrust command at or below this value switches the engines off", min = 0.0),
    decl!(134, parameter engine_time_constant: parameters.engines.time_constant_s, "s", "First-order lag of the delivered thrust (0 = none)", min = 0.0),
    decl!(146, parameter engine_thrust_scale: parameters.engines.thrust_scale, "1", "Delivered over commanded thrust once the throttle limits apply: a thrust-level error the GNC does not know (1 nominal), at most 2", above = 0.0, max = 2.0),
    decl!(147, tunable engine_health: parameters.engines.health, "1", "Fault, tunable during the run: the fraction of the thrust the engines still deliver, after engine_thrust_scale (1 healthy; 0.5 one of two engines lost); the GNC is not told", min = 0.0, max = 1.0),
    decl!(135, parameter thrust_misalignment: parameters.thrust_line.misalignment_rad, "rad", "Angle between the thrust direction and body +y", above = -HALF_PI, below = HALF_PI),
    decl!(136, parameter thrust_misalignment_azimuth: parameters.thrust_line.misalignment_azimuth_rad, "rad", "Direction of the misalignment in the body x-z plane, from +x towards +z"),
    decl!(137, parameter thrust_point_body[3]: parameters.thrust_line.point_body_m, "m", "Thrust application point relative to the centre of mass", components = &["body x (lateral offset)", "body y (nozzle below the centre of mass)", "body z (lateral offset)"]),
    decl!(430, parameter throttle_rate_limit: parameters.actuators.throttle_rate_limit_nps, "N/s", "Fastest change of the delivered engine thrust (0 = none); with engine_time_constant the lag's rate is clipped to it; without it Co-Simulation only", min = 0.0),
    decl!(431, parameter rcs_valve_delay: parameters.actuators.rcs_valve_delay_s, "s", "Delay between an RCS command (rcs_duty pulses, or torque_cmd_body in the torque model) and the valves acting on it, exact (0 = none); Co-Simulation only", min = 0.0),
    decl!(432, parameter rcs_isp: parameters.actuators.rcs_isp_s, "s", "Specific impulse of the RCS thrusters: their propellant flow sum|F| / (rcs_isp g0) is taken from the mass (0 = not booked); torque model: |tau| / rcs_moment_arm per axis", min = 0.0),
    decl!(140, parameter rcs_thruster_force: parameters.rcs.thruster_force_n, "N", "Force of one RCS thruster", min = 0.0),
    decl!(141, parameter rcs_moment_arm: parameters.rcs.moment_arm_m, "m", "Moment arm of an RCS couple", min = 0.0),
    decl!(142, parameter rcs_time_constant: parameters.rcs.time_constant_s, "s", "First-order lag of the delivered RCS torque (0 = none)", min = 0.0),
    decl!(144, parameter rcs_model: parameters.rcs_model as enum RcsModelKind, "RCS model: 1 torque per axis (default, the paper), 2 eight thrusters driven by rcs_duty", as_integer = true),
    decl!(145, parameter rcs_min_impulse_bit: parameters.thrusters.min_impulse_bit_ns, "N.s", "Thruster model: a pulse of smaller impulse (rcs_thruster_force x on-time) is not fired, unless it continues a pulse that lasted to the end of the previous step", min = 0.0),
    decl!(148, tunable rcs_stuck_thruster: parameters.rcs_stuck.thruster as i32, "Fault, tunable during the run (thruster model only): the RCS thruster 1..8 (docs/rcs-layout.md) whose valve is stuck as rcs_stuck_mode says; 0 none", int_min = 0, int_max = 8),
    decl!(149, tunable rcs_stuck_mode: parameters.rcs_stuck.mode as enum RcsStuckMode, "Fault: how rcs_stuck_thruster's valve is stuck: 1 off (no force, whatever rcs_duty), 2 on (full force over every step, commanded or not)", as_integer = true),
    decl!(300, parameter rcs_position_body[24]: parameters.thrusters.position_body_m, "m", "Thruster model: nozzle position of thruster k (elements 3k+1..3k+3) relative to the centre of mass; default: docs/rcs-layout.md", components = THRUSTER_XYZ),
    decl!(324, parameter rcs_direction_body[24]: parameters.thrusters.direction_body, "1", "Thruster model: unit direction of the force thruster k (elements 3k+1..3k+3) applies to the lander", components = THRUSTER_XYZ),
    decl!(143, calculated_parameter rcs_torque_limit: get |m, _| m.parameters.rcs.torque_limit_nm(), "N.m", "Per-axis RCS torque limit: one couple, 2 x rcs_thruster_force x rcs_moment_arm"),
    // Translation model.
    // An Integer in the model description, so that every master can select it (libcosim and
    // Ecos ignore FMI 2.0 Enumerations); the values are listed from TranslationModelKind.
    decl!(150, parameter translation_model: parameters.translation_model as enum TranslationModelKind, "Translational equations of motion (flat: paper eq. 2; spherical rotating Moon: eq. 1)", as_integer = true),
    decl!(151, parameter moon_radius: parameters.moon_radius_m, "m", "Mean radius of the Moon (spherical model)", above = 0.0),
    decl!(152, parameter moon_rotation_rate: parameters.moon_rotation_rate_radps, "rad/s", "Sidereal rotation rate of the Moon (spherical model)"),
    decl!(153, parameter site_latitude: parameters.site_latitude_rad, "rad", "Latitude of the landing site (spherical model; default Chandrayaan-3, 69.373 deg S); within +-85 deg", min = -MAX_SITE_LATITUDE_RAD, max = MAX_SITE_LATITUDE_RAD),
    decl!(154, parameter site_longitude: parameters.site_longitude_rad, "rad", "Longitude of the landing site (spherical model; default Chandrayaan-3, 32.319 deg E)"),
    decl!(160, parameter integration_step: parameters.integration_step_s, "s", "Maximum RK4 sub-step; a communication step is split into sub-steps of this size, the last one shortened", above = 0.0),
    // Model Exchange: the states a foreign solver integrates (with omega_body and mass above)
    // and their derivatives, in state-vector order.
    decl!(200, continuous_state translation_state[6]: get |m, i| m.state_element(model_exchange::TRANSLATION + i), "1", "Translational state of the selected model: flat r_nue (m), v_nue (m/s); spherical radius (m), longitude, latitude (rad), East, North, Up velocity (m/s)", components = TRANSLATION_STATE, field = "translation_state"),
    decl!(206, continuous_state attitude_state[4]: get |m, i| m.state_element(model_exchange::ATTITUDE + i), "1", "Attitude quaternion body to NUE as integrated (q_body_to_nue is its normalisation)", components = QUATERNION, field = "attitude_state"),
    decl!(210, continuous_state thrust_lag_state: get |m, _| m.state_element(model_exchange::THRUST_LAG), "N", "State of the engine thrust lag (constant while engine_time_constant = 0)", field = "thrust_lag_state"),
    decl!(211, continuous_state torque_lag_state_body[3]: get |m, i| m.state_element(model_exchange::TORQUE_LAG + i), "N.m", "State of the RCS torque lag (constant while rcs_time_constant = 0)", components = BODY_AXES, field = "torque_lag_state_body"),
    decl!(220, derivative der_translation_state[6]: get |m, i| m.derivative_element(model_exchange::TRANSLATION + i), "1", "Time derivative of translation_state", components = TRANSLATION_STATE),
    decl!(226, derivative der_attitude_state[4]: get |m, i| m.derivative_element(model_exchange::ATTITUDE + i), "1/s", "Time derivative of attitude_state, with the term that pulls |q| back to 1", components = QUATERNION),
    decl!(230, derivative der_omega_body[3]: get |m, i| m.derivative_element(model_exchange::ATTITUDE + 4 + i), "rad/s2", "Body angular acceleration", components = BODY_AXES),
    decl!(233, derivative der_mass: get |m, _| m.derivative_element(model_exchange::THRUST_LAG - 1), "kg/s", "Mass flow (negative while the engines burn)"),
    decl!(234, derivative der_thrust_lag_state: get |m, _| m.derivative_element(model_exchange::THRUST_LAG), "N/s", "Time derivative of thrust_lag_state"),
    decl!(235, derivative der_torque_lag_state_body[3]: get |m, i| m.derivative_element(model_exchange::TORQUE_LAG + i), "N.m/s", "Time derivative of torque_lag_state_body", components = BODY_AXES),
    decl!(240, local touchdown_indicator: get |m, _| m.event_indicator(0), "m", "Event indicator of touchdown: the altitude until touchdown, -1 after it"),
    decl!(241, local exhaustion_indicator: get |m, _| m.event_indicator(1), "kg", "Event indicator of propellant exhaustion: mass - dry_mass until exhaustion, -1 after it"),
];

#[cfg(test)]
mod tests {
    use super::*;
    use fmi_model::Causality;

    #[test]
    fn the_export_layer_accepts_the_declarations() {
        assert_eq!(fmi2_export::check_table::<LanderPlant>(), Ok(()));
    }

    #[test]
    fn navigation_outputs_depend_on_no_input_even_in_initialization() {
        let vars = fmi2_export::variables::<LanderPlant>();
        let index_of = |name: &str| 1 + vars.iter().position(|v| v.name() == name).unwrap() as u32;
        let inputs: Vec<u32> = vars
            .iter()
            .enumerate()
            .filter(|(_, v)| v.causality == Causality::Input)
            .map(|(i, _)| i as u32 + 1)
            .collect();
        let structure = fmi2_export::model_description::<LanderPlant>().model_structure;
        let dependencies = |list: &Option<model_description::UnknownList>, name: &str| {
            let unknown = list
                .as_ref()
                .unwrap()
                .unknowns
                .iter()
                .find(|u| u.index == index_of(name))
                .unwrap_or_else(|| panic!("{name} is not listed"));
            let text = unknown.dependencies.clone().expect("dependencies declared");
            text.split_whitespace()
                .map(|i| i.parse::<u32>().unwrap())
                .collect::<Vec<u32>>()
        };
        for name in ["r_nue[2]", "q_body_to_nue[1]", "omega_body[3]", "mass"] {
            for list in [&structure.outputs, &structure.initial_unknowns] {
                let deps = dependencies(list, name);
                assert!(deps.iter().all(|d| !inputs.contains(d)), "{name}: {deps:?}");
            }
        }
        let initial = dependencies(&structure.initial_unknowns, "r_nue[2]");
        assert!(initial.contains(&index_of("r0_nue[2]")), "{initial:?}");
        let thrust = dependencies(&structure.outputs, "thrust_actual");
        assert_eq!(thrust, vec![index_of("thrust_cmd")]);
        let torque = dependencies(&structure.outputs, "torque_actual_body[2]");
        assert!(
            torque.contains(&index_of("torque_cmd_body[2]")),
            "{torque:?}"
        );
        assert!(torque.contains(&index_of("rcs_duty[8]")), "{torque:?}");
    }

    #[test]
    fn the_interface_contract_names_are_all_present_with_their_causality() {
        let vars = fmi2_export::variables::<LanderPlant>();
        let find = |n: &str| {
            vars.iter()
                .find(|v| v.name() == n)
                .unwrap_or_else(|| panic!("{n} missing"))
        };
        let mut contract = vec![
            ("thrust_cmd".to_string(), Causality::Input),
            ("mass".into(), Causality::Output),
            ("m0".into(), Causality::Parameter),
        ];
        for (base, n, c) in [
            ("torque_cmd_body", 3, Causality::Input),
            ("r_nue", 3, Causality::Output),
            ("v_nue", 3, Causality::Output),
            ("q_body_to_nue", 4, Causality::Output),
            ("omega_body", 3, Causality::Output),
            ("r0_nue", 3, Causality::Parameter),
            ("v0_nue", 3, Causality::Parameter),
            ("q0_body_to_nue", 4, Causality::Parameter),
            ("omega0_body", 3, Causality::Parameter),
        ] {
            contract.extend((1..=n).map(|k| (format!("{base}[{k}]"), c)));
        }
        for (name, causality) in contract {
            assert_eq!(find(&name).causality, causality, "{name}");
        }
    }

    #[test]
    fn scalar_first_quaternion_output_matches_the_parameter_order() {
        // GIVEN q0 = a 90 deg rotation about body z, scalar first
        let mut m = LanderPlant::default();
        let h = std::f64::consts::FRAC_1_SQRT_2;
        m.parameters.q0_body_to_nue = [h, 0.0, 0.0, h];
        let mut log = Log::default();
        m.exit_initialization(0.0, &mut log).unwrap();
        // WHEN the outputs are computed
        m.calculate_values(&mut log);
        // THEN q_body_to_nue[1] is the scalar part, [4] the z part
        assert!((m.outputs.q_body_to_nue[0] - h).abs() < 1e-15);
        assert!((m.outputs.q_body_to_nue[3] - h).abs() < 1e-15);
        assert_eq!(m.outputs.q_body_to_nue[1], 0.0);
    }

    /// The declared output `specific_force_body`, read as a master reads it.
    fn specific_force_output(m: &LanderPlant) -> [f64; 3] {
        let d = DECLARATIONS
            .iter()
            .find(|d| d.name == "specific_force_body")
            .expect("declared");
        let fmi_model::Kind::Real { get, .. } = d.kind else {
            unreachable!("a Real")
        };
        std::array::from_fn(|i| get(m, i))
    }

    #[test]
    fn specific_force_is_t_over_m_in_co_simulation_and_model_exchange() {
        use fmi_model::ContinuousModel;
        // GIVEN a lander at 1400 N in Co-Simulation
        let mut m = LanderPlant::default();
        m.commands.thrust_cmd_n = 1400.0;
        let mut log = Log::default();
        m.exit_initialization(0.0, &mut log).unwrap();
        for k in 0..10 {
            m.do_step(f64::from(k) * 0.01, 0.01, &mut log).unwrap();
        }
        m.calculate_values(&mut log);
        let mass = m.outputs.mass;
        assert_eq!(specific_force_output(&m), [0.0, 1400.0 / mass, 0.0]);
        // AND in Model Exchange, at a state set by the solver (mass 850 kg)
        let mut x = [0.0; model_exchange::STATE_COUNT];
        m.states(&mut x);
        x[model_exchange::THRUST_LAG - 1] = 850.0;
        m.set_states(&x).unwrap();
        m.calculate_values(&mut log);
        assert_eq!(specific_force_output(&m), [0.0, 1400.0 / 850.0, 0.0]);
        // AND with the engines off it reads 0 (free fall)
        m.commands.thrust_cmd_n = 0.0;
        m.calculate_values(&mut log);
        assert_eq!(specific_force_output(&m), [0.0; 3]);
    }

    /// The declared output `specific_force_mean_body`, read as a master reads it.
    fn specific_force_mean_output(m: &LanderPlant) -> [f64; 3] {
        let d = DECLARATIONS
            .iter()
            .find(|d| d.name == "specific_force_mean_body")
            .expect("declared");
        let fmi_model::Kind::Real { get, .. } = d.kind else {
            unreachable!("a Real")
        };
        std::array::from_fn(|i| get(m, i))
    }

    #[test]
    fn the_mean_specific_force_of_a_constant_thrust_is_t_over_m() {
        // GIVEN 1400 N with a negligible mass flow (the mass stays m0 to the last bit)
        let mut m = LanderPlant::default();
        m.parameters.isp_s = 1e30;
        m.commands.thrust_cmd_n = 1400.0;
        let mut log = Log::default();
        m.exit_initialization(0.0, &mut log).unwrap();
        m.calculate_values(&mut log);
        // THEN before the first step the mean reads the instantaneous value
        assert_eq!(specific_force_mean_output(&m), specific_force_output(&m));
        // WHEN stepping
        m.do_step(0.0, 0.01, &mut log).unwrap();
        m.calculate_values(&mut log);
        // THEN the mean over the step is T / m to rounding
        let mean = specific_force_mean_output(&m);
        let exact = 1400.0 / m.outputs.mass;
        assert_eq!(m.outputs.mass, m.parameters.m0_kg);
        assert_eq!([mean[0], mean[2]], [0.0, 0.0]);
        assert!(
            (mean[1] - exact).abs() <= 4.0 * f64::EPSILON * exact,
            "{mean:?}"
        );
    }

    #[test]
    fn the_mean_specific_force_of_a_burning_engine_is_the_rocket_equation_over_the_step() {
        // GIVEN 1600 N burning at isp 300 s: m(t) = m0 - T t / (isp g0)
        let mut m = LanderPlant::default();
        m.commands.thrust_cmd_n = 1600.0;
        let mut log = Log::default();
        m.exit_initialization(0.0, &mut log).unwrap();
        m.calculate_values(&mut log);
        let m_start = m.outputs.mass;
        // WHEN stepping over 0.5 s (50 RK4 sub-steps)
        m.do_step(0.0, 0.5, &mut log).unwrap();
        m.calculate_values(&mut log);
        // THEN the mean is the integral of T / m(t) over the step, divided by it:
        // isp g0 ln(m_start / m_end) / h, with the burnt mass dm = T h / (isp g0) (from the
        // plant's m_end the logarithm would carry the rounding of 50 sub-steps of the mass,
        // 1e-11 of the 0.27 kg burnt)
        let p = &m.parameters;
        let thrust = m.delivered().thrust_n;
        assert_eq!(thrust, 1600.0);
        let burnt = thrust * 0.5 / (p.isp_s * p.g0_mps2);
        assert!(
            (m_start - m.outputs.mass - burnt).abs() < 1e-10,
            "{}",
            m.outputs.mass
        );
        let exact = p.isp_s * p.g0_mps2 * libm::log1p(burnt / (m_start - burnt)) / 0.5;
        let mean = specific_force_mean_output(&m)[1];
        assert!((mean - exact).abs() < 1e-14 * exact, "{mean} vs {exact}");
        // AND it lies between the instantaneous values at the step's ends
        let end = specific_force_output(&m)[1];
        assert!(mean > 1600.0 / m_start && mean < end, "{mean} {end}");
    }

    #[test]
    fn the_mean_specific_force_of_a_lagged_engine_is_the_lag_integrated_over_the_step() {
        // GIVEN engines off until t = 0, then 1400 N through a 50 ms lag, mass constant
        let mut m = LanderPlant::default();
        m.parameters.isp_s = 1e30;
        m.parameters.engines.time_constant_s = 0.05;
        m.parameters.integration_step_s = 1e-3;
        m.commands.thrust_cmd_n = 1400.0;
        let mut log = Log::default();
        m.exit_initialization(0.0, &mut log).unwrap();
        // WHEN stepping 10 ms
        let h = 0.01;
        m.do_step(0.0, h, &mut log).unwrap();
        m.calculate_values(&mut log);
        // THEN the mean is T (1 - tau / h (1 - exp(-h / tau))) / m, well below the
        // instantaneous T (1 - exp(-h / tau)) / m at the step's end. RK4's quadrature of the
        // lag state is T h - tau (x(h) - x(0)) exactly, so its error is tau / h times RK4's
        // error in x(h), (h_sub / tau)^5 / 120 per sub-step: 1.4e-9 of T / m
        let (tau, mass) = (0.05, m.outputs.mass);
        let exact = 1400.0 * (1.0 - tau / h * (1.0 - libm::exp(-h / tau))) / mass;
        let instantaneous = 1400.0 * (1.0 - libm::exp(-h / tau)) / mass;
        let mean = specific_force_mean_output(&m)[1];
        assert!(
            (mean - exact).abs() < 3e-9 * 1400.0 / mass,
            "{mean} vs {exact}"
        );
        assert!((specific_force_output(&m)[1] - instantaneous).abs() < 1e-8 * instantaneous);
        assert!(instantaneous - mean > 0.4 * mean, "{mean} {instantaneous}");
    }

    #[test]
    fn the_mean_specific_force_of_a_thruster_on_for_half_the_step_is_half_its_force() {
        // GIVEN the thruster model, engines off, the RCS propellant not booked
        let mut m = LanderPlant::default();
        m.parameters.rcs_model = RcsModelKind::Thrusters as i32;
        let mut log = Log::default();
        m.exit_initialization(0.0, &mut log).unwrap();
        let thrusters = m.running.as_ref().unwrap().0.thrusters.unwrap();
        for k in [0, 5] {
            // WHEN thruster k fires for the first half of a step
            m.rcs_duty = [0.0; THRUSTER_COUNT];
            m.rcs_duty[k] = 0.5;
            let t = f64::from(k as u32) * 0.01;
            m.do_step(t, 0.01, &mut log).unwrap();
            m.calculate_values(&mut log);
            // THEN the mean over the step is half its force over the mass, to rounding,
            // while the instantaneous value (commanded on at the next step's start) is all of it
            let force = thrusters.direction_body[k] * thrusters.force_n;
            let mean = specific_force_mean_output(&m);
            let instantaneous = specific_force_output(&m);
            for i in 0..3 {
                let exact = 0.5 * force[i] / m.outputs.mass;
                assert!(
                    (mean[i] - exact).abs() < 1e-15,
                    "{k} {i}: {mean:?} vs {exact}"
                );
                assert!(
                    (instantaneous[i] - 2.0 * exact).abs() < 1e-15,
                    "{instantaneous:?}"
                );
            }
        }
    }

    /// The declared output `omega_mean_body`, read as a master reads it.
    fn omega_mean_output(m: &LanderPlant) -> [f64; 3] {
        let d = DECLARATIONS
            .iter()
            .find(|d| d.name == "omega_mean_body")
            .expect("declared");
        let fmi_model::Kind::Real { get, .. } = d.kind else {
            unreachable!("a Real")
        };
        std::array::from_fn(|i| get(m, i))
    }

    #[test]
    fn the_mean_body_rate_under_a_constant_torque_is_the_rate_at_mid_step() {
        // GIVEN a lander at rest under a constant RCS torque about body z
        let mut m = LanderPlant::default();
        m.commands.torque_cmd_body_nm = nalgebra::Vector3::new(0.0, 0.0, 50.0);
        let mut log = Log::default();
        m.exit_initialization(0.0, &mut log).unwrap();
        m.calculate_values(&mut log);
        assert_eq!(omega_mean_output(&m), [0.0; 3]);
        let alpha = 50.0 / m.parameters.inertia_body_kgm2[2];
        for k in 0..2 {
            // WHEN stepping 10 ms
            m.do_step(f64::from(k) * 0.01, 0.01, &mut log).unwrap();
            m.calculate_values(&mut log);
            // THEN omega grows linearly and its mean over the step is its value at mid-step,
            // half a step behind the instantaneous one
            let mid = alpha * (f64::from(k) + 0.5) * 0.01;
            let mean = omega_mean_output(&m);
            assert_eq!([mean[0], mean[1]], [0.0, 0.0]);
            assert!((mean[2] - mid).abs() < 1e-15, "{mean:?} vs {mid}");
            let end = alpha * f64::from(k + 1) * 0.01;
            assert!((m.outputs.omega_body[2] - end).abs() < 1e-15);
        }
    }

    #[test]
    fn a_slosh_swing_past_thirty_degrees_is_logged_as_beyond_the_linear_theory() {
        // GIVEN slosh on, hovering, the RCS spinning the lander up about its thrust axis
        // (the sloshing masses lean out as omega^2 r grows against g_eff)
        let mut m = LanderPlant::default();
        m.parameters.slosh.enabled = true;
        m.commands.thrust_cmd_n = 1458.0;
        m.commands.torque_cmd_body_nm = nalgebra::Vector3::new(0.0, 116.0, 0.0);
        let mut log = Log::default();
        m.exit_initialization(0.0, &mut log).unwrap();
        let swung = |log: &Log| {
            log.entries
                .iter()
                .filter(|(_, w)| w.starts_with("slosh: a pendulum swung"))
                .count()
        };
        let mut k = 0;
        while swung(&log) == 0 && k < 1000 {
            m.do_step(f64::from(k) * 0.01, 0.01, &mut log).unwrap();
            k += 1;
        }
        // THEN the warning comes as the swing passes 30 deg, with the step's time
        let (plant, run) = m.running.as_ref().unwrap();
        let swing = plant
            .slosh
            .as_ref()
            .unwrap()
            .largest_swing(&run.slosh, run.state.mass_kg);
        assert_eq!(swung(&log), 1, "{:?}", log.entries);
        assert!(swing > LINEAR_RANGE_RAD && swing < 0.6, "{swing}");
        assert!(log.has_warning());
    }

    #[test]
    fn with_the_gear_touchdown_is_the_first_contact_and_the_run_goes_on_in_co_simulation() {
        // GIVEN the gear on, footpads 1 m above flat ground, engines off
        let mut m = LanderPlant::default();
        m.parameters.gear.enabled = true;
        m.parameters.r0_nue_m.y = 2.0;
        let mut log = Log::default();
        m.exit_initialization(0.0, &mut log).unwrap();
        // WHEN stepping for 5 s
        for k in 0..500 {
            let end = m.do_step(f64::from(k) * 0.01, 0.01, &mut log).unwrap();
            assert_eq!(end, StepEnd::Complete, "step {k}");
        }
        m.calculate_values(&mut log);
        // THEN touchdown is true at sqrt(2 / g), the four feet are on the ground, and no more
        let t_exact = (2.0 / 1.62f64).sqrt();
        assert!((m.touchdown_field(|t| t.time_s) - t_exact).abs() < 1e-9);
        assert!(running_flag(&m, |r| r.touchdown.is_some()));
        let status = m.gear_view();
        assert!(
            status.contact.stroke_m.iter().all(|s| *s > 0.0),
            "{status:?}"
        );
    }

    #[test]
    fn the_gear_is_refused_in_model_exchange_naming_gear_enabled() {
        use fmi_model::ContinuousModel;
        let mut m = LanderPlant::default();
        m.parameters.gear.enabled = true;
        m.exit_initialization(0.0, &mut Log::default()).unwrap();
        let mut dx = [0.0; model_exchange::STATE_COUNT];
        let err = m.derivatives(&mut dx).unwrap_err();
        assert!(
            matches!(&err, ModelError::InvalidParameter { field: "gear.enabled", reason, .. } if reason.contains("Co-Simulation only")),
            "{err:?}"
        );
        let mut x = [0.0; model_exchange::STATE_COUNT];
        m.states(&mut x);
        assert!(m.set_states(&x).is_err());
        let mut z = [0.0; 2];
        assert!(m.event_indicators(&mut z).is_err());
    }

    #[test]
    fn a_lagless_rate_limit_and_the_valve_delay_are_refused_in_model_exchange() {
        use fmi_model::ContinuousModel;
        let mut dx = [0.0; model_exchange::STATE_COUNT];
        for (rate, tau, delay, field) in [
            (800.0, 0.0, 0.0, Some("actuators.throttle_rate_limit_nps")),
            (800.0, 0.2, 0.0, None),
            (0.0, 0.0, 0.02, Some("actuators.rcs_valve_delay_s")),
        ] {
            let mut m = LanderPlant::default();
            m.parameters.actuators.throttle_rate_limit_nps = rate;
            m.parameters.engines.time_constant_s = tau;
            m.parameters.actuators.rcs_valve_delay_s = delay;
            m.exit_initialization(0.0, &mut Log::default()).unwrap();
            match (m.derivatives(&mut dx), field) {
                (Ok(()), None) => {}
                (Err(ModelError::InvalidParameter { field: f, .. }), Some(expected)) => {
                    assert_eq!(f, expected)
                }
                (other, _) => panic!("{rate} {tau} {delay}: {other:?}"),
            }
        }
    }

    #[test]
    fn a_restored_state_with_crafted_gear_slosh_or_rcs_history_values_is_refused() {
        let fresh = || {
            let mut m = LanderPlant::default();
            m.exit_initialization(0.0, &mut Log::default()).unwrap();
            m
        };
        assert_eq!(fresh().validate_restored(true), Ok(()));
        let mut m = fresh();
        m.rcs_history.torques[0] = Some((f64::INFINITY, nalgebra::Vector3::zeros()));
        assert!(m.validate_restored(true).is_err(), "rcs history");
        let crafted: [fn(&mut PlantRun); 3] = [
            |run| run.slosh.0[2] = f64::NAN,
            |run| run.slosh.0[0] = 0.01,
            |run| run.gear.tipped_over = true,
        ];
        for (k, craft) in crafted.iter().enumerate() {
            let mut m = fresh();
            craft(&mut m.running.as_mut().unwrap().1);
            assert!(m.validate_restored(true).is_err(), "case {k}");
        }
    }

    #[test]
    fn a_bad_parameter_is_refused_by_name_at_exit_initialization() {
        let mut m = LanderPlant::default();
        m.parameters.dry_mass_kg = 1000.0;
        let err = m.exit_initialization(0.0, &mut Log::default()).unwrap_err();
        assert!(
            matches!(err, ModelError::InvalidParameter { field: "m0_kg", .. }),
            "{err:?}"
        );
    }

    #[test]
    fn a_step_needing_more_sub_steps_than_the_bound_is_refused_before_integrating() {
        // GIVEN a lander climbing so fast that it stays aloft for 1.2e6 s
        let mut m = LanderPlant::default();
        m.parameters.v0_nue_mps.y = 1e6;
        let mut log = Log::default();
        m.exit_initialization(0.0, &mut log).unwrap();
        let before = m.running.as_ref().unwrap().1.state;
        // WHEN a master asks for one step of 1e300 s (or just over the bound)
        for h in [1e300, (MAX_SUB_STEPS_PER_STEP + 1.0) * 0.01] {
            let err = m.do_step(0.0, h, &mut log).unwrap_err();
            // THEN it is refused at once, naming the step size, and the state is untouched
            assert!(err.to_string().contains("communicationStepSize"), "{err}");
            assert_eq!(m.running.as_ref().unwrap().1.state, before);
        }
        // AND a step at the bound is still taken
        assert!(m
            .do_step(0.0, MAX_SUB_STEPS_PER_STEP * 0.01 * 1e-3, &mut log)
            .is_ok());
    }

    #[test]
    fn touchdown_stops_the_step_at_the_crossing_and_terminates() {
        // GIVEN a free fall from 5 m (engines off)
        let mut m = LanderPlant::default();
        m.parameters.r0_nue_m.y = 5.0;
        let mut log = Log::default();
        m.exit_initialization(0.0, &mut log).unwrap();
        // WHEN stepping in 0.1 s steps
        let mut t = 0.0;
        let end = loop {
            match m.do_step(t, 0.1, &mut log).unwrap() {
                StepEnd::Complete => t += 0.1,
                stopped => break stopped,
            }
            assert!(t < 10.0, "no touchdown");
        };
        // THEN it stops at sqrt(2 h / g) with the free-fall velocity, and stays stopped
        let t_exact = (2.0 * 5.0 / 1.62f64).sqrt();
        let StepEnd::Stopped {
            time, terminated, ..
        } = end
        else {
            unreachable!()
        };
        assert!(terminated);
        assert!((time - t_exact).abs() < 1e-9, "{time} vs {t_exact}");
        m.calculate_values(&mut log);
        let v_td = m.touchdown_field(|td| td.v_nue_mps.0.y);
        assert!((v_td + 1.62 * t_exact).abs() < 1e-8, "{v_td}");
        assert!(m.outputs.altitude.abs() < 1e-9);
        assert!(matches!(
            m.do_step(time, 0.1, &mut log),
            Ok(StepEnd::Stopped {
                terminated: true,
                ..
            })
        ));
    }
}
