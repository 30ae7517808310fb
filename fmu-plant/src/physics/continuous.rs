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
use super::frames::Body;
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

/// Smallest and largest |q| of an attitude state. The equations use only the direction of
/// `q`, and the norm term pulls |q| to 1; a reasonable integrator keeps |q| within about
/// `h omega^2 / (16 k)` of 1 (explicit Euler; RK4 far closer), and even a rejected trial step
/// of a variable-step solver with h omega = 2000 rad grows |q| only by ~1e3. A norm off by a
/// factor 1e6 is no attitude: the integrator's error is a million times the signal, and near
/// zero (or at a denormal) the direction cannot be computed at all. At 1e6 the norm term
/// `k (1 - |q|^2) q` is 1e18 /s, still finite.
pub const QUATERNION_NORM_RANGE: (f64, f64) = (1e-6, 1e6);

/// Fastest velocity element, m/s: the speed of light. The equations are Newtonian and no
/// lander moves faster; below it every square of a velocity (the spherical model's
/// `(u^2 + v^2) / r`, `u v tan(lat) / r`) is far from overflowing.
pub const SPEED_LIMIT_MPS: f64 = 299_792_458.0;

/// Farthest position, m (flat: each r_nue element; spherical: the radius minus the Moon's
/// radius): 1e12 m, beyond the Sun from the Moon, where a Moon-only gravity model describes
/// nothing. It keeps the spherical model's Moon-fixed position sums finite.
pub const DISTANCE_LIMIT_M: f64 = 1e12;

/// Smallest radius of the spherical model, as a fraction of the Moon's radius: there the
/// central gravity `mu / r^2` is 1e12 g and `lon' = u / (r cos lat)` stays finite for any
/// velocity below the speed of light; at `r = 0` the equations are singular.
pub const MIN_RADIUS_FRACTION: f64 = 1e-6;

/// One element of the state, as the declarations name it (vector elements 0-based).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StateElement {
    Translation(usize),
    /// The quaternion as a whole (refused for its norm).
    Attitude,
    /// One quaternion component (refused for not being finite).
    AttitudeComponent(usize),
    OmegaBody(usize),
    Mass,
    ThrustLag,
    TorqueLag(usize),
}

impl StateElement {
    /// The declared name, 1-based as in the model description (`attitude_state[2]`).
    pub fn name(&self) -> String {
        match self {
            Self::Translation(i) => format!("translation_state[{}]", i + 1),
            Self::Attitude => "attitude_state".into(),
            Self::AttitudeComponent(i) => format!("attitude_state[{}]", i + 1),
            Self::OmegaBody(i) => format!("omega_body[{}]", i + 1),
            Self::Mass => "mass".into(),
            Self::ThrustLag => "thrust_lag_state".into(),
            Self::TorqueLag(i) => format!("torque_lag_state_body[{}]", i + 1),
        }
    }
}

/// A state the equations cannot evaluate (some derivative, indicator or output would not
/// be finite, or the value means nothing physical): the element at fault and why.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{} = {value}: {reason}", element.name())]
pub struct Unevaluable {
    pub element: StateElement,
    pub value: String,
    pub reason: String,
}

fn refuse(element: StateElement, value: impl std::fmt::Display, reason: String) -> Unevaluable {
    Unevaluable {
        element,
        value: value.to_string(),
        reason,
    }
}

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
            engine_lag: plant.thrust_is_a_state(),
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
            .chain(lander_math::quaternion::from_nalgebra(q))
            .chain(x.omega_body.0.iter().copied())
            .chain([x.mass_kg]);
        let lags = [x.thrust_lag_n]
            .into_iter()
            .filter(|_| self.engine_lag)
            .chain(
                x.torque_lag_body_nm
                    .0
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
        let omega_body = Body(Vector3::from_fn(|_, _| take()));
        let mass_kg = take();
        let thrust_lag_n = if self.engine_lag { take() } else { 0.0 };
        let torque_lag_body_nm = if self.rcs_lag {
            Body(Vector3::from_fn(|_, _| take()))
        } else {
            Body::zeros()
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
            omega_body: Body::new(1.0, 1.0, 1.0),
            mass_kg: 1e3,
            thrust_lag_n: 1e3,
            torque_lag_body_nm: Body::new(100.0, 100.0, 100.0),
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

    /// Whether every derivative, event indicator and output at `x` is finite and `x` is a
    /// physical state, whatever the commands (they are saturated): the check of a state set
    /// by a foreign integrator or restored. The rules, element by element:
    /// * translation: flat positions within [`DISTANCE_LIMIT_M`]; spherical radius in
    ///   `[MIN_RADIUS_FRACTION R, R + DISTANCE_LIMIT_M]`, latitude within +-pi/2 (beyond it
    ///   is no latitude; `cos lat >= 6e-17` there), longitude finite; every velocity element
    ///   within [`SPEED_LIMIT_MPS`];
    /// * attitude: |q| within [`QUATERNION_NORM_RANGE`];
    /// * body rate: `4 |omega|^2 I_max / I_min`, a bound of the gyroscopic acceleration
    ///   `|omega x (I omega)| / I`, finite;
    /// * mass > 0 (the derivative uses `max(mass, dry mass)`; a state just past the dry mass
    ///   is an integrator that stepped over the exhaustion event before locating it);
    /// * lag states within what explicit Euler at its stability limit (`h = 2 tau`) reaches
    ///   from delivered values: thrust in `[-T_max, 2 T_max]`, each torque in `[-3 L, 3 L]`
    ///   (`T_max` all engines at full thrust, `L` the per-axis RCS torque limit).
    pub fn check_evaluable(&self, x: &PlantState) -> Result<(), Unevaluable> {
        let finite = |element: StateElement, v: f64| {
            if v.is_finite() {
                Ok(())
            } else {
                Err(refuse(element, v, "not finite".into()))
            }
        };
        for (i, v) in x.translation.iter().enumerate() {
            finite(StateElement::Translation(i), *v)?;
        }
        for (i, v) in [
            x.q_body_to_nue.w,
            x.q_body_to_nue.i,
            x.q_body_to_nue.j,
            x.q_body_to_nue.k,
        ]
        .into_iter()
        .enumerate()
        {
            finite(StateElement::AttitudeComponent(i), v)?;
        }
        for (i, v) in x.omega_body.0.iter().enumerate() {
            finite(StateElement::OmegaBody(i), *v)?;
        }
        finite(StateElement::Mass, x.mass_kg)?;
        finite(StateElement::ThrustLag, x.thrust_lag_n)?;
        for (i, v) in x.torque_lag_body_nm.0.iter().enumerate() {
            finite(StateElement::TorqueLag(i), *v)?;
        }

        let within = |element: StateElement, v: f64, low: f64, high: f64, why: &str| {
            if (low..=high).contains(&v) {
                Ok(())
            } else {
                Err(refuse(
                    element,
                    v,
                    format!("outside [{low:e}, {high:e}]: {why}"),
                ))
            }
        };
        let t = &x.translation;
        let light = "faster than light";
        match &self.translation {
            Translation::Flat { .. } => {
                for i in 0..3 {
                    let d = DISTANCE_LIMIT_M;
                    within(
                        StateElement::Translation(i),
                        t[i],
                        -d,
                        d,
                        "too far from the Moon",
                    )?;
                }
            }
            Translation::Spherical(moon) => {
                let r = moon.radius_m;
                let why = "no radius the spherical equations hold at";
                within(
                    StateElement::Translation(0),
                    t[0],
                    MIN_RADIUS_FRACTION * r,
                    r + DISTANCE_LIMIT_M,
                    why,
                )?;
                let half_pi = std::f64::consts::FRAC_PI_2;
                within(
                    StateElement::Translation(2),
                    t[2],
                    -half_pi,
                    half_pi,
                    "not a latitude",
                )?;
            }
        }
        for i in 3..6 {
            let c = SPEED_LIMIT_MPS;
            within(StateElement::Translation(i), t[i], -c, c, light)?;
        }

        let q = &x.q_body_to_nue;
        let norm = q.norm();
        let (low, high) = QUATERNION_NORM_RANGE;
        if !(low..=high).contains(&norm) {
            return Err(refuse(
                StateElement::Attitude,
                format!("[{}, {}, {}, {}]", q.w, q.i, q.j, q.k),
                format!(
                    "|q| = {norm:e} outside [{low:e}, {high:e}]: no attitude can be taken from it"
                ),
            ));
        }

        let inertia = &self.inertia_body_kgm2;
        let gyroscopic = 4.0 * x.omega_body.0.norm_squared() * (inertia.max() / inertia.min());
        if !gyroscopic.is_finite() {
            let i = x.omega_body.0.iamax();
            return Err(refuse(
                StateElement::OmegaBody(i),
                x.omega_body.0[i],
                "4 |omega_body|^2 I_max / I_min (a bound of the gyroscopic acceleration) overflows"
                    .into(),
            ));
        }

        if x.mass_kg <= 0.0 {
            return Err(refuse(
                StateElement::Mass,
                x.mass_kg,
                "not > 0: a body's mass is positive".into(),
            ));
        }

        let max_thrust_n = f64::from(self.engines.count) * self.engines.max_thrust_per_engine_n;
        within(
            StateElement::ThrustLag,
            x.thrust_lag_n,
            -max_thrust_n,
            2.0 * max_thrust_n,
            "beyond what a stable integration of the thrust lag reaches",
        )?;
        let limit = 3.0 * self.rcs.torque_limit_nm().abs();
        for (i, v) in x.torque_lag_body_nm.0.iter().enumerate() {
            within(
                StateElement::TorqueLag(i),
                *v,
                -limit,
                limit,
                "beyond what a stable integration of the torque lag reaches",
            )?;
        }
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
