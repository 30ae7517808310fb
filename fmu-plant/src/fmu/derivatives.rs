//! Exact directional derivatives of LanderPlant: the layer's knowns and unknowns mapped onto
//! `physics::sensitivity`, evaluated once on dual numbers seeded with the master's seed.
//!
//! Knowns: `thrust_cmd`, `torque_cmd_body`, `rcs_duty` (whose pulses are on or off: its
//! derivative is 0 everywhere) and, under Model Exchange, the 18 continuous states.
//! Unknowns: the continuous outputs and, under Model Exchange, the state derivatives. The
//! dependencies the model description declares (`output_dependencies`,
//! `state_dependencies`) hold every nonzero.
use super::LanderPlant;
use crate::physics::dual::Dual;
use crate::physics::plant::Plant;
use crate::physics::sensitivity::{
    Flags, Knowns, ATTITUDE, MASS, OMEGA, STATES, THRUST_LAG, TORQUE_LAG, TRANSLATION,
};
use fmi_model::{Model, ModelError, ScalarRef};

/// Where a known enters the equations.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Known {
    State(usize),
    ThrustCommand,
    TorqueCommand(usize),
    /// No effect on any derivative (`rcs_duty`).
    Constant,
}

fn name(r: ScalarRef) -> &'static str {
    LanderPlant::declarations()[r.declaration].name
}

fn refused(what: &str, r: ScalarRef, why: &str) -> ModelError {
    let element = if LanderPlant::declarations()[r.declaration].shape().len() > 1 {
        format!("[{}]", r.element + 1)
    } else {
        String::new()
    };
    ModelError::Refused(format!("{what} {}{element}: {why}", name(r)))
}

fn known(r: ScalarRef) -> Result<Known, ModelError> {
    let e = r.element;
    Ok(match name(r) {
        "thrust_cmd" => Known::ThrustCommand,
        "torque_cmd_body" => Known::TorqueCommand(e),
        "rcs_duty" => Known::Constant,
        "translation_state" => Known::State(TRANSLATION + e),
        "attitude_state" => Known::State(ATTITUDE + e),
        "omega_body" => Known::State(OMEGA + e),
        "mass" => Known::State(MASS),
        "thrust_lag_state" => Known::State(THRUST_LAG),
        "torque_lag_state_body" => Known::State(TORQUE_LAG + e),
        _ => return Err(refused("known", r, "no derivative with respect to it")),
    })
}

/// The state derivative an unknown is, if it is one.
fn derivative_slot(r: ScalarRef) -> Option<usize> {
    let e = r.element;
    Some(match name(r) {
        "der_translation_state" => TRANSLATION + e,
        "der_attitude_state" => ATTITUDE + e,
        "der_omega_body" => OMEGA + e,
        "der_mass" => MASS,
        "der_thrust_lag_state" => THRUST_LAG,
        "der_torque_lag_state_body" => TORQUE_LAG + e,
        _ => return None,
    })
}

fn flags_of(plant: &Plant, run: &crate::physics::plant::PlantRun) -> Flags {
    Flags {
        exhausted: run.propellant_exhausted,
        engines_off_for_outputs: plant.engines_cut(run) || plant.stopped_at(run).is_some(),
        touchdown: run.touchdown.is_some(),
    }
}

impl LanderPlant {
    /// `sensitivity = J seed` at the current state and commands (see the module doc).
    pub(super) fn directional(
        &self,
        unknowns: &[ScalarRef],
        knowns: &[ScalarRef],
        seed: &[f64],
        sensitivity: &mut [f64],
    ) -> Result<(), ModelError> {
        let view = self.continuous_view().ok_or_else(|| {
            ModelError::Refused(
                "no derivatives while the parameters give no valid plant (see \
                 fmi2ExitInitializationMode's checks)"
                    .into(),
            )
        })?;
        let (plant, run) = view.as_ref();
        let mapped: Vec<Known> = knowns.iter().map(|&k| known(k)).collect::<Result<_, _>>()?;
        let model_exchange = mapped.iter().any(|k| matches!(k, Known::State(_)))
            || unknowns.iter().any(|&u| derivative_slot(u).is_some());
        if model_exchange {
            super::model_exchange::co_simulation_only(plant)?;
        }
        let mut x = [0.0; STATES];
        crate::physics::continuous::StateLayout::ALL
            .pack(&run.state, &mut x)
            .map_err(|e| ModelError::Other(format!("continuous state vector: {e}")))?;
        let mut k = Knowns {
            x: x.map(Dual::from),
            thrust_cmd_n: Dual::from(self.commands.thrust_cmd_n),
            torque_cmd_body_nm: self.commands.torque_cmd_body_nm.map(Dual::from).into(),
        };
        for (known, s) in mapped.iter().zip(seed) {
            match *known {
                Known::State(i) => k.x[i].eps += s,
                Known::ThrustCommand => k.thrust_cmd_n.eps += s,
                Known::TorqueCommand(i) => k.torque_cmd_body_nm[i].eps += s,
                Known::Constant => {}
            }
        }
        let flags = flags_of(plant, run);
        let inputs_seeded = mapped
            .iter()
            .any(|k| matches!(k, Known::ThrustCommand | Known::TorqueCommand(_)));
        let u = plant.evaluate(&k, flags);
        for (out, &r) in sensitivity.iter_mut().zip(unknowns) {
            *out = self
                .dual_of(plant, run, r, &k, &u, inputs_seeded)?
                .map_or(0.0, |d| d.eps);
        }
        Ok(())
    }

    /// Unknown `r` with its tangent from one evaluation; `None` for a value no known
    /// changes (its derivative is 0).
    fn dual_of(
        &self,
        plant: &Plant,
        run: &crate::physics::plant::PlantRun,
        r: ScalarRef,
        k: &Knowns<Dual>,
        u: &crate::physics::sensitivity::Unknowns<Dual>,
        inputs_seeded: bool,
    ) -> Result<Option<Dual>, ModelError> {
        if let Some(i) = derivative_slot(r) {
            return Ok(Some(u.derivative[i]));
        }
        let e = r.element;
        let slosh = || {
            refused(
                "unknown",
                r,
                "with slosh_enabled its value is the rigid part's, solved with the pendulums; \
                 its derivatives are not provided",
            )
        };
        Ok(Some(match name(r) {
            "r_nue" => u.r_nue[e],
            "v_nue" => u.v_nue[e],
            "q_body_to_nue" => u.q_unit[e],
            "omega_body" => k.x[OMEGA + e],
            "mass" => k.x[MASS],
            "propellant_used" => Dual::from(self.parameters.m0_kg) - k.x[MASS],
            "altitude" => u.altitude,
            "thrust_actual" => u.thrust_n,
            "engine_torque_body" => u.engine_torque_body_nm[e],
            // Thrusters on or off: a constant force and torque.
            "rcs_force_body" => return Ok(None),
            "torque_actual_body" => u.rcs_torque_body_nm[e],
            "specific_force_body" if plant.slosh.is_some() => return Err(slosh()),
            "specific_force_body" => u.specific_force_body_mps2[e],
            // After a step: the mean over it, a number the current knowns do not change.
            "specific_force_mean_body" | "omega_mean_body" if run.mean_span_s > 0.0 => {
                return Ok(None)
            }
            "specific_force_mean_body" if inputs_seeded => {
                return Err(refused(
                    "unknown",
                    r,
                    "before the first step (and in Model Exchange) it is specific_force_body, \
                     which depends on the inputs its declared dependencies (those of \
                     Co-Simulation steps) leave out: ask specific_force_body",
                ))
            }
            "specific_force_mean_body" if plant.slosh.is_some() => return Err(slosh()),
            "specific_force_mean_body" => u.specific_force_body_mps2[e],
            "omega_mean_body" => k.x[OMEGA + e],
            // The landing gear's and the pendulums' (Co-Simulation only): functions of the
            // state, which is no known there.
            "leg_stroke" | "slosh_displacement" => return Ok(None),
            _ => return Err(refused("unknown", r, "no derivative of it")),
        }))
    }

    /// The values of `unknowns` as the equations on dual numbers give them (`None` where
    /// they do not model the value): for the test that keeps the two copies of the
    /// equations in step.
    pub fn values_on_dual_numbers(&self, unknowns: &[ScalarRef]) -> Vec<Option<f64>> {
        let Some(view) = self.continuous_view() else {
            return vec![None; unknowns.len()];
        };
        let (plant, run) = view.as_ref();
        let mut x = [0.0; STATES];
        let _ = crate::physics::continuous::StateLayout::ALL.pack(&run.state, &mut x);
        let k = Knowns {
            x: x.map(Dual::from),
            thrust_cmd_n: Dual::from(self.commands.thrust_cmd_n),
            torque_cmd_body_nm: self.commands.torque_cmd_body_nm.map(Dual::from).into(),
        };
        let u = plant.evaluate(&k, flags_of(plant, run));
        unknowns
            .iter()
            .map(|&r| {
                self.dual_of(plant, run, r, &k, &u, false)
                    .ok()
                    .flatten()
                    .map(|d| d.re)
            })
            .collect()
    }
}
