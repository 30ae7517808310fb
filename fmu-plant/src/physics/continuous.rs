//! The plant as a flat ODE for an integrator that is not ours (Model Exchange): a state
//! vector, its nominals, its derivative, event indicators and the event update.
//!
//! Everything here is a view of [`Plant::derivative`], the same equations the Co-Simulation
//! step integrates with RK4: one physics, two interfaces.
//!
//! Quaternion drift: our RK4 renormalises the attitude after every sub-step, a foreign
//! integrator cannot. So the derivative seen from outside adds
//! `QUATERNION_NORM_GAIN_PER_S * (1 - |q|^2) q` to `q'`. The term vanishes on the unit sphere
//! (the physical trajectory is unchanged) and pulls |q| back to 1 with a time constant of
//! `1 / (2 k)` s wherever the integrator's error pushed it. The equations already use only
//! the direction of `q` (`body_to_nue` normalises), and the event update renormalises the
//! state; outputs are the normalised quaternion.
use super::plant::{Commands, Plant, PlantRun, Translation};
use super::state::PlantState;
use nalgebra::{Quaternion, Vector3, Vector6};

/// Gain of the norm-restoring term, 1/s. Slow against any integrator step, fast against the
/// drift an error-controlled integrator lets accumulate; the term adds no stiffness.
pub const QUATERNION_NORM_GAIN_PER_S: f64 = 1.0;

/// Number of event indicators: touchdown (altitude) and propellant exhaustion (mass).
pub const EVENT_INDICATOR_COUNT: usize = 2;

/// Indicator value of an event that has happened and cannot happen again: a constant below
/// zero, so no integrator sees another crossing.
const SPENT_INDICATOR: f64 = -1.0;

/// Which states the flat vector holds. Position and velocity (the translation model's six),
/// the scalar-first quaternion, body rates and mass always; each actuator's lag states only
/// when that lag is on, unless a fixed layout is asked for (a model description is static).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StateLayout {
    pub engine_lag: bool,
    pub rcs_lag: bool,
}

/// A flat vector of the wrong length.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("expected {expected} values, got {got}")]
pub struct LengthMismatch {
    pub expected: usize,
    pub got: usize,
}

const CORE_STATES: usize = 6 + 4 + 3 + 1;

impl StateLayout {
    /// Every state, lags included: the layout an interface with a fixed state count declares.
    /// The lag states then have a zero derivative while their lag is off.
    pub const ALL: Self = Self {
        engine_lag: true,
        rcs_lag: true,
    };

    /// Only the states the plant's configuration needs.
    pub fn compact(plant: &Plant) -> Self {
        Self {
            engine_lag: plant.engines.time_constant_s > 0.0,
            rcs_lag: plant.rcs.time_constant_s > 0.0,
        }
    }

    pub fn len(&self) -> usize {
        CORE_STATES + usize::from(self.engine_lag) + 3 * usize::from(self.rcs_lag)
    }

    pub fn is_empty(&self) -> bool {
        false
    }

    fn check(&self, got: usize) -> Result<(), LengthMismatch> {
        if got == self.len() {
            Ok(())
        } else {
            Err(LengthMismatch {
                expected: self.len(),
                got,
            })
        }
    }

    /// Writes `x` into `out` (quaternion scalar first).
    pub fn pack(&self, x: &PlantState, out: &mut [f64]) -> Result<(), LengthMismatch> {
        self.check(out.len())?;
        let q = &x.q_body_to_nue;
        let mut values = x
            .translation
            .iter()
            .copied()
            .chain([q.w, q.i, q.j, q.k])
            .chain(x.omega_body.iter().copied())
            .chain([x.mass_kg]);
        let lags = [x.thrust_lag_n]
            .into_iter()
            .filter(|_| self.engine_lag)
            .chain(
                x.torque_lag_body_nm
                    .iter()
                    .copied()
                    .filter(|_| self.rcs_lag),
            );
        for (slot, value) in out.iter_mut().zip(values.by_ref().chain(lags)) {
            *slot = value;
        }
        Ok(())
    }

    /// Reads a state from `v`; lag states outside the layout are zero.
    pub fn unpack(&self, v: &[f64]) -> Result<PlantState, LengthMismatch> {
        self.check(v.len())?;
        let mut next = v.iter().copied();
        let mut take = || next.next().unwrap_or(0.0);
        let translation = Vector6::from_fn(|_, _| take());
        let (w, i, j, k) = (take(), take(), take(), take());
        let omega_body = Vector3::from_fn(|_, _| take());
        let mass_kg = take();
        let thrust_lag_n = if self.engine_lag { take() } else { 0.0 };
        let torque_lag_body_nm = if self.rcs_lag {
            Vector3::from_fn(|_, _| take())
        } else {
            Vector3::zeros()
        };
        Ok(PlantState {
            translation,
            q_body_to_nue: Quaternion::new(w, i, j, k),
            omega_body,
            mass_kg,
            thrust_lag_n,
            torque_lag_body_nm,
        })
    }
}

impl Plant {
    /// Typical magnitudes of the states, for an integrator's absolute tolerances.
    pub fn nominals(&self, layout: &StateLayout, out: &mut [f64]) -> Result<(), LengthMismatch> {
        let translation = match &self.translation {
            // r_nue (m), v_nue (m/s)
            Translation::Flat { .. } => Vector6::new(1e3, 1e3, 1e3, 10.0, 10.0, 10.0),
            // radius (m), longitude, latitude (rad: 1 km on the Moon ~ 6e-4), u, v, w (m/s)
            Translation::Spherical(moon) => {
                Vector6::new(moon.radius_m, 1e-3, 1e-3, 10.0, 10.0, 10.0)
            }
        };
        let nominal = PlantState {
            translation,
            q_body_to_nue: Quaternion::new(1.0, 1.0, 1.0, 1.0),
            omega_body: Vector3::repeat(1.0),
            mass_kg: 1e3,
            thrust_lag_n: 1e3,
            torque_lag_body_nm: Vector3::repeat(100.0),
        };
        layout.pack(&nominal, out)
    }

    /// `run.state` from a flat vector set by an integrator (stored as given: no normalisation,
    /// so that the derivative is a function of exactly what the integrator holds).
    pub fn set_continuous_states(
        &self,
        layout: &StateLayout,
        run: &mut PlantRun,
        v: &[f64],
    ) -> Result<(), LengthMismatch> {
        let mut x = layout.unpack(v)?;
        if !layout.engine_lag {
            x.thrust_lag_n = run.state.thrust_lag_n;
        }
        if !layout.rcs_lag {
            x.torque_lag_body_nm = run.state.torque_lag_body_nm;
        }
        run.state = x;
        Ok(())
    }

    /// The time derivative of `run.state`, with the quaternion norm term; zero after
    /// touchdown (the lander stands still, as in Co-Simulation).
    pub fn continuous_derivative(
        &self,
        layout: &StateLayout,
        run: &PlantRun,
        commands: &Commands,
        out: &mut [f64],
    ) -> Result<(), LengthMismatch> {
        if run.touchdown.is_some() {
            layout.check(out.len())?;
            out.fill(0.0);
            return Ok(());
        }
        let x = &run.state;
        let mut d = self.derivative(x, commands, run.propellant_exhausted);
        let q = &x.q_body_to_nue;
        d.q_body_to_nue += q * (QUATERNION_NORM_GAIN_PER_S * (1.0 - q.norm_squared()));
        layout.pack(&d, out)
    }

    /// `[altitude (m), mass - dry mass (kg)]`; each crosses zero from above at its event and
    /// stays at a negative constant once the event has happened.
    pub fn event_indicators(&self, run: &PlantRun) -> [f64; EVENT_INDICATOR_COUNT] {
        let altitude = if run.touchdown.is_some() {
            SPENT_INDICATOR
        } else {
            self.altitude(&run.state)
        };
        let propellant = if run.propellant_exhausted {
            SPENT_INDICATOR
        } else {
            run.state.mass_kg - self.dry_mass_kg
        };
        [altitude, propellant]
    }

    /// The event update at time `t`: renormalises the attitude, cuts the engines at the dry
    /// mass and records (and from then on freezes) a touchdown, as the Co-Simulation step does
    /// at its located events. Returns what happened at this call.
    pub fn update_at_event(&self, run: &mut PlantRun, t: f64) -> EventOutcome {
        run.state = run.state.renormalised();
        let mut outcome = EventOutcome::default();
        if run.touchdown.is_some() {
            return outcome;
        }
        if !run.propellant_exhausted && run.state.mass_kg <= self.dry_mass_kg {
            self.exhaust(run);
            outcome.exhausted = true;
        }
        if self.altitude(&run.state) <= 0.0 {
            run.touchdown = Some(self.touchdown_at(&run.state, t));
            outcome.touchdown = true;
        }
        outcome
    }
}

/// The attitude to publish: `q` itself when it is a unit quaternion to round-off (every
/// state the Co-Simulation step produces, so its outputs keep their bits), else `q / |q|` (a
/// state set by a foreign integrator between two event updates).
pub fn unit_attitude(q: &Quaternion<f64>) -> Quaternion<f64> {
    if (q.norm_squared() - 1.0).abs() <= 4.0 * f64::EPSILON {
        *q
    } else {
        crate::physics::state::normalised(q)
    }
}

/// What an event update did.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct EventOutcome {
    pub touchdown: bool,
    pub exhausted: bool,
}
