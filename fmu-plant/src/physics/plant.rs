//! The plant: equations of motion, the sub-stepped RK4 advance and its events.
use super::actuators::{lag_rate, lagged_or_direct, Engines, Rcs, ThrustLine};
use super::events::find_crossing;
use super::frames::{body_to_nue, tilt_from_vertical};
use super::integrator::{rk4_step, SubSteps};
use super::parameters::{ParameterError, PlantParameters, RcsModelKind, TranslationModelKind};
use super::rigid_body::{omega_dot_body, quaternion_rate, PrincipalInertia};
use super::state::PlantState;
use super::thrusters::{pieces, Firing, Thrusters, NONE_FIRING, THRUSTER_COUNT};
use super::translation_flat;
use super::translation_spherical::SphericalMoon;
use nalgebra::{Quaternion, Vector3, Vector6};
use serde::{Deserialize, Serialize};

/// The translation model with whatever it needs to evaluate.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Translation {
    Flat { gravity_mps2: f64 },
    Spherical(SphericalMoon),
}

impl Translation {
    pub fn from_nue(&self, r_nue: &Vector3<f64>, v_nue: &Vector3<f64>) -> Vector6<f64> {
        match self {
            Self::Flat { .. } => translation_flat::pack(r_nue, v_nue),
            Self::Spherical(moon) => moon.from_nue(r_nue, v_nue),
        }
    }

    /// Position (m) and Moon-relative velocity (m/s) in site NUE.
    pub fn to_nue(&self, x: &Vector6<f64>) -> (Vector3<f64>, Vector3<f64>) {
        match self {
            Self::Flat { .. } => (
                translation_flat::position_nue(x),
                translation_flat::velocity_nue(x),
            ),
            Self::Spherical(moon) => moon.to_nue(x),
        }
    }

    /// Height above the surface (the plane, or the sphere), m.
    pub fn altitude(&self, x: &Vector6<f64>) -> f64 {
        match self {
            Self::Flat { .. } => translation_flat::altitude(x),
            Self::Spherical(moon) => moon.altitude(x),
        }
    }

    fn derivative(&self, x: &Vector6<f64>, a_thrust_nue: &Vector3<f64>) -> Vector6<f64> {
        match self {
            Self::Flat { gravity_mps2 } => {
                translation_flat::derivative(x, *gravity_mps2, a_thrust_nue)
            }
            Self::Spherical(moon) => moon.derivative(x, a_thrust_nue),
        }
    }
}

/// Commands held constant over a communication step (zero-order hold).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct Commands {
    pub thrust_cmd_n: f64,
    pub torque_cmd_body_nm: Vector3<f64>,
}

/// What the actuators deliver at a state.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Delivered {
    pub thrust_n: f64,
    pub rcs_torque_body_nm: Vector3<f64>,
    /// Force of the firing RCS thrusters, body axes (zero in the torque model).
    pub rcs_force_body_n: Vector3<f64>,
    /// Torque of the (misaligned or offset) thrust line about the centre of mass.
    pub engine_torque_body_nm: Vector3<f64>,
}

/// The state of a touchdown, frozen at the crossing.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Touchdown {
    pub time_s: f64,
    pub v_nue_mps: Vector3<f64>,
    pub q_body_to_nue: Quaternion<f64>,
    pub omega_body_radps: Vector3<f64>,
    /// Angle between the thrust axis and the local vertical, rad.
    pub tilt_rad: f64,
}

/// Everything that evolves: the integrated state and the discrete flags.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PlantRun {
    pub state: PlantState,
    pub propellant_exhausted: bool,
    pub touchdown: Option<Touchdown>,
    /// Thrusters whose pulse lasted to the end of the last step: their next pulse continues
    /// it and is fired whatever its length (thruster model).
    pub rcs_firing_at_step_end: Firing,
}

/// How an advance ended.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Advance {
    Reached,
    /// Touchdown at this time (<= the requested end).
    Touchdown(f64),
}

/// The plant with validated, pre-computed parameters.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Plant {
    pub translation: Translation,
    pub inertia_body_kgm2: PrincipalInertia,
    pub engines: Engines,
    pub rcs: Rcs,
    /// The thrusters when the RCS is modelled by them; `None`: the per-axis torque model.
    pub thrusters: Option<Thrusters>,
    pub thrust_line: ThrustLine,
    thrust_direction_body: Vector3<f64>,
    /// `1 / (Isp g0)`, s/m: mass flow per newton of thrust.
    mass_flow_per_newton: f64,
    pub dry_mass_kg: f64,
    pub integration_step_s: f64,
}

/// The actuator set-points before any lag.
struct Targets {
    thrust_n: f64,
    rcs_torque_body_nm: Vector3<f64>,
}

/// Which event ended an RK4 piece.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Event {
    Touchdown,
    Exhaustion,
}

impl Plant {
    /// Validates the parameters and builds the plant and its initial run state; the second
    /// element is a warning worth logging (a noticeably non-unit q0 that was normalised).
    pub fn new(p: &PlantParameters) -> Result<(Self, PlantRun, Option<String>), ParameterError> {
        p.validate()?;
        let (q0, warning) = p.validated_q0()?;
        let translation = match p.translation_model_kind()? {
            TranslationModelKind::Flat => Translation::Flat {
                gravity_mps2: p.gravity_mps2,
            },
            TranslationModelKind::Spherical => Translation::Spherical(SphericalMoon::new(
                p.moon_radius_m,
                p.gravity_mps2,
                p.moon_rotation_rate_radps,
                p.site_latitude_rad,
                p.site_longitude_rad,
            )),
        };
        let plant = Self {
            translation,
            inertia_body_kgm2: p.inertia_body_kgm2,
            engines: p.engines,
            rcs: p.rcs,
            thrusters: match p.rcs_model_kind()? {
                RcsModelKind::Torque => None,
                RcsModelKind::Thrusters => {
                    Some(Thrusters::new(&p.thrusters, p.rcs.thruster_force_n))
                }
            },
            thrust_line: p.thrust_line,
            thrust_direction_body: p.thrust_line.direction_body(),
            mass_flow_per_newton: 1.0 / (p.isp_s * p.g0_mps2),
            dry_mass_kg: p.dry_mass_kg,
            integration_step_s: p.integration_step_s,
        };
        let translation_state = translation.from_nue(&p.r0_nue_m, &p.v0_nue_mps);
        let altitude = translation.altitude(&translation_state);
        if altitude.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return Err(ParameterError {
                field: "r0_nue_m",
                index: Some(1),
                value: p.r0_nue_m.y.to_string(),
                reason: format!(
                    "the altitude above the surface is {altitude} m; it must be > 0: \
                     the plant starts in flight (ground contact is not modelled)"
                ),
            });
        }
        let state = PlantState {
            translation: translation_state,
            q_body_to_nue: q0,
            omega_body: p.omega0_body_radps,
            mass_kg: p.m0_kg,
            thrust_lag_n: 0.0,
            torque_lag_body_nm: Vector3::zeros(),
        };
        let run = PlantRun {
            state,
            propellant_exhausted: false,
            touchdown: None,
            rcs_firing_at_step_end: NONE_FIRING,
        };
        Ok((plant, run, warning))
    }

    /// The steady-state actuator targets: each command saturated once per evaluation.
    fn targets(&self, commands: &Commands, exhausted: bool) -> Targets {
        Targets {
            thrust_n: if exhausted {
                0.0
            } else {
                self.engines.saturate(commands.thrust_cmd_n)
            },
            rcs_torque_body_nm: self.rcs.saturate(&commands.torque_cmd_body_nm),
        }
    }

    /// Whether the actuator lag states take part in the dynamics (either time constant > 0).
    pub fn has_actuator_lags(&self) -> bool {
        self.engines.time_constant_s > 0.0 || self.rcs.time_constant_s > 0.0
    }

    /// What the actuators deliver at state `x` under `commands` (thruster model: none firing).
    pub fn delivered(&self, x: &PlantState, commands: &Commands, exhausted: bool) -> Delivered {
        self.delivered_firing(x, commands, &NONE_FIRING, exhausted)
    }

    /// What the actuators deliver at state `x` under `commands` with these thrusters firing
    /// (ignored in the torque model).
    pub fn delivered_firing(
        &self,
        x: &PlantState,
        commands: &Commands,
        firing: &Firing,
        exhausted: bool,
    ) -> Delivered {
        self.delivered_from(x, &self.targets(commands, exhausted), firing, exhausted)
    }

    fn delivered_from(
        &self,
        x: &PlantState,
        targets: &Targets,
        firing: &Firing,
        exhausted: bool,
    ) -> Delivered {
        let thrust_n = if exhausted {
            0.0
        } else {
            lagged_or_direct(
                targets.thrust_n,
                x.thrust_lag_n,
                self.engines.time_constant_s,
            )
        };
        let (rcs_force_body_n, rcs_torque_body_nm) = match &self.thrusters {
            Some(thrusters) => thrusters.force_and_torque_body(firing),
            None => {
                let tau = self.rcs.time_constant_s;
                let torque = Vector3::from_fn(|k, _| {
                    lagged_or_direct(targets.rcs_torque_body_nm[k], x.torque_lag_body_nm[k], tau)
                });
                (Vector3::zeros(), torque)
            }
        };
        Delivered {
            thrust_n,
            rcs_torque_body_nm,
            rcs_force_body_n,
            engine_torque_body_nm: self
                .thrust_line
                .torque_body_nm(&self.thrust_direction_body, thrust_n),
        }
    }

    /// Time derivative of the whole state (thruster model: none firing): the one set of
    /// equations of motion behind both the Co-Simulation step (RK4 below) and Model Exchange
    /// (`continuous`).
    pub fn derivative(&self, x: &PlantState, commands: &Commands, exhausted: bool) -> PlantState {
        self.derivative_firing(x, commands, &NONE_FIRING, exhausted)
    }

    /// Time derivative of the whole state with these thrusters firing.
    pub fn derivative_firing(
        &self,
        x: &PlantState,
        commands: &Commands,
        firing: &Firing,
        exhausted: bool,
    ) -> PlantState {
        self.derivative_from(x, &self.targets(commands, exhausted), firing, exhausted)
    }

    /// [`Plant::derivative_firing`] with the commands already saturated: they are constant
    /// over a step, so an RK4 step saturates them once, not at each of its four stages.
    #[inline]
    fn derivative_from(
        &self,
        x: &PlantState,
        targets: &Targets,
        firing: &Firing,
        exhausted: bool,
    ) -> PlantState {
        let d = self.delivered_from(x, targets, firing, exhausted);
        self.derivative_delivered(x, &d, targets)
    }

    /// The derivative at `x` with the actuators delivering `d` (from [`Plant::delivered_from`]
    /// at `x`; without lags it does not depend on `x`, and an RK4 step computes it once).
    #[inline(always)]
    fn derivative_delivered(&self, x: &PlantState, d: &Delivered, targets: &Targets) -> PlantState {
        // Until the exhaustion event the engines burn on, so the mass stays linear in time
        // across the dry mass and the event search sees a smooth function. An RK4 stage of
        // the sub-step holding the event can lie past the dry mass (never the accepted
        // state); clamping the mass there keeps the stage finite for any sub-step length
        // without touching states before the event.
        let mass_kg = x.mass_kg.max(self.dry_mass_kg);
        let thrust_body = match self.thrusters {
            // Separate branch: the torque model's arithmetic stays what it was, bit for bit.
            None => self.thrust_direction_body * (d.thrust_n / mass_kg),
            Some(_) => (self.thrust_direction_body * d.thrust_n + d.rcs_force_body_n) / mass_kg,
        };
        let a_thrust_nue = body_to_nue(&x.q_body_to_nue, &thrust_body);
        let torque_body = d.rcs_torque_body_nm + d.engine_torque_body_nm;
        // Without lags the lag states stay at zero: skip their rates altogether. The torque
        // lag belongs to the torque model; with thrusters it stays at rest.
        let (thrust_lag_n, torque_lag_body_nm) = if self.has_actuator_lags() {
            let tau_rcs = self.rcs.time_constant_s;
            (
                lag_rate(
                    targets.thrust_n,
                    x.thrust_lag_n,
                    self.engines.time_constant_s,
                ),
                match self.thrusters {
                    None => Vector3::from_fn(|k, _| {
                        lag_rate(
                            targets.rcs_torque_body_nm[k],
                            x.torque_lag_body_nm[k],
                            tau_rcs,
                        )
                    }),
                    Some(_) => Vector3::zeros(),
                },
            )
        } else {
            (0.0, Vector3::zeros())
        };
        PlantState {
            translation: self.translation.derivative(&x.translation, &a_thrust_nue),
            q_body_to_nue: quaternion_rate(&x.q_body_to_nue, &x.omega_body),
            omega_body: omega_dot_body(&self.inertia_body_kgm2, &x.omega_body, &torque_body),
            mass_kg: -d.thrust_n * self.mass_flow_per_newton,
            thrust_lag_n,
            torque_lag_body_nm,
        }
    }

    /// The touchdown record of state `x` reached at time `t`.
    pub(crate) fn touchdown_at(&self, x: &PlantState, t: f64) -> Touchdown {
        let (_, v_nue) = self.translation.to_nue(&x.translation);
        Touchdown {
            time_s: t,
            v_nue_mps: v_nue,
            q_body_to_nue: x.q_body_to_nue,
            omega_body_radps: x.omega_body,
            tilt_rad: tilt_from_vertical(&x.q_body_to_nue),
        }
    }

    /// Exhaustion: the engines are cut and the mass is pinned at the dry mass (the located
    /// state lies within the crossing tolerance past it).
    pub(crate) fn exhaust(&self, run: &mut PlantRun) {
        run.propellant_exhausted = true;
        run.state.mass_kg = self.dry_mass_kg;
        run.state.thrust_lag_n = 0.0;
    }

    fn rk4(
        &self,
        x: &PlantState,
        commands: &Commands,
        firing: &Firing,
        exhausted: bool,
        t: f64,
        h: f64,
    ) -> PlantState {
        let targets = self.targets(commands, exhausted);
        if self.has_actuator_lags() {
            rk4_step(
                |_t, s: &PlantState| self.derivative_from(s, &targets, firing, exhausted),
                t,
                x,
                h,
            )
            .renormalised()
        } else {
            // Without lags what the actuators deliver is constant over the step.
            let d = self.delivered_from(x, &targets, firing, exhausted);
            rk4_step(
                #[inline(always)]
                |_t, s: &PlantState| self.derivative_delivered(s, &d, &targets),
                t,
                x,
                h,
            )
            .renormalised()
        }
    }

    pub fn altitude(&self, x: &PlantState) -> f64 {
        self.translation.altitude(&x.translation)
    }

    /// Advances `run` from `t` to `t + h` under constant `commands`, in RK4 sub-steps of at
    /// most `integration_step_s`, stopping at a touchdown. After a touchdown it does not move.
    /// In the thruster model no thruster fires (see [`Plant::advance_with_duty`]).
    pub fn advance(&self, run: &mut PlantRun, commands: &Commands, t: f64, h: f64) -> Advance {
        if let Some(td) = run.touchdown {
            return Advance::Touchdown(td.time_s);
        }
        match self.advance_span(run, commands, &NONE_FIRING, t, h, t + h) {
            Some(time) => Advance::Touchdown(time),
            None => Advance::Reached,
        }
    }

    /// [`Plant::advance`] with the RCS duties of the step: in the thruster model thruster `k`
    /// fires from `t` for `rcs_duty[k] h` (see `Thrusters::on_times_s`), and the step is
    /// integrated in pieces that end at every pulse end. The torque model ignores the duties.
    pub fn advance_with_duty(
        &self,
        run: &mut PlantRun,
        commands: &Commands,
        rcs_duty: &[f64; THRUSTER_COUNT],
        t: f64,
        h: f64,
    ) -> Advance {
        let Some(thrusters) = &self.thrusters else {
            return self.advance(run, commands, t, h);
        };
        if let Some(td) = run.touchdown {
            return Advance::Touchdown(td.time_s);
        }
        let on_times_s = thrusters.on_times_s(rcs_duty, h, &run.rcs_firing_at_step_end);
        run.rcs_firing_at_step_end = on_times_s.map(|s| s >= h);
        let mut start = 0.0;
        for (end, firing) in pieces(&on_times_s, h) {
            let span_end = if end >= h { t + h } else { t + end };
            if let Some(time) =
                self.advance_span(run, commands, &firing, t + start, end - start, span_end)
            {
                return Advance::Touchdown(time);
            }
            start = end;
        }
        Advance::Reached
    }

    /// From `t` over `h` s ending at `end_time` (= t + h, passed so that a whole step ends
    /// exactly at the master's time) with constant firing, in RK4 sub-steps of at most
    /// `integration_step_s`; returns the touchdown time if any.
    fn advance_span(
        &self,
        run: &mut PlantRun,
        commands: &Commands,
        firing: &Firing,
        t: f64,
        h: f64,
        end_time: f64,
    ) -> Option<f64> {
        // A state at or past the dry mass with the engines still on (restored from a Model
        // Exchange run whose integrator stepped over the exhaustion event) has no crossing
        // left to find: the exhaustion happens now.
        if !run.propellant_exhausted && run.state.mass_kg <= self.dry_mass_kg {
            self.exhaust(run);
        }
        let schedule = SubSteps::new(h, self.integration_step_s);
        for k in 0..schedule.count {
            let (offset, size) = schedule.get(k);
            let start = t + offset;
            let end = if k + 1 == schedule.count {
                end_time
            } else {
                start + size
            };
            if let Some(time) = self.advance_piecewise(run, commands, firing, start, end) {
                return Some(time);
            }
        }
        None
    }

    /// One sub-step from `start` to `end`, split at events; returns the touchdown time if any.
    fn advance_piecewise(
        &self,
        run: &mut PlantRun,
        commands: &Commands,
        firing: &Firing,
        start: f64,
        end: f64,
    ) -> Option<f64> {
        let mut t = start;
        // An event piece can end a hair before `end`; a remainder below the crossing tolerance
        // is not worth an RK4 step (it would only add round-off).
        while end - t > super::events::crossing_tolerance_s(end) {
            let h = end - t;
            let exhausted = run.propellant_exhausted;
            let x1 = self.rk4(&run.state, commands, firing, exhausted, t, h);
            let x0 = &run.state;
            let crossing = |g: &dyn Fn(&PlantState) -> f64, g0: f64, g1: f64| {
                find_crossing(
                    |s| g(&self.rk4(x0, commands, firing, exhausted, t, s)),
                    g0,
                    g1,
                    h,
                    t,
                )
            };
            let mut first: Option<(f64, Event)> = None;
            // The event functions are evaluated directly on both ends; only a sign change
            // (rare) searches through the dynamically dispatched re-integration.
            if !exhausted {
                let (g0, g1) = (x0.mass_kg - self.dry_mass_kg, x1.mass_kg - self.dry_mass_kg);
                if g0 > 0.0 && g1 <= 0.0 {
                    let tau = crossing(&|x: &PlantState| x.mass_kg - self.dry_mass_kg, g0, g1);
                    first = Some((tau, Event::Exhaustion));
                }
            }
            let (g0, g1) = (self.altitude(x0), self.altitude(&x1));
            if g0 > 0.0 && g1 <= 0.0 {
                let tau = crossing(&|x: &PlantState| self.altitude(x), g0, g1);
                if first.is_none_or(|(best, _)| tau < best) {
                    first = Some((tau, Event::Touchdown));
                }
            }
            let Some((tau, event)) = first else {
                run.state = x1;
                return None;
            };
            run.state = if tau >= h {
                x1
            } else {
                self.rk4(&run.state, commands, firing, exhausted, t, tau)
            };
            t = if tau >= h { end } else { t + tau };
            match event {
                Event::Exhaustion => self.exhaust(run),
                Event::Touchdown => {
                    run.touchdown = Some(self.touchdown_at(&run.state, t));
                    return Some(t);
                }
            }
        }
        None
    }
}
