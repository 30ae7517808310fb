//! The plant: equations of motion, the sub-stepped RK4 advance and its events.
use super::actuators::{lag_rate, lagged_or_direct, Engines, Rcs, ThrustLine};
use super::events::find_crossing;
use super::frames::{body_to_nue, tilt_from_vertical, Body, Nue};
use super::gear::{EngineCutoff, Gear};
use super::integrator::{rk4_step_with_quadrature, OdeState, SubSteps};
use super::parameters::{ParameterError, PlantParameters, RcsModelKind, TranslationModelKind};
use super::rigid_body::{omega_dot_body, quaternion_rate, PrincipalInertia};
use super::slosh::{Slosh, SloshState};
use super::slosh_dynamics::{self, RigidLoads};
use super::state::PlantState;
use super::thrusters::{pieces, Firing, Thrusters, NONE_FIRING, THRUSTER_COUNT};
use super::translation_flat;
use super::translation_spherical::SphericalMoon;
use nalgebra::{Quaternion, UnitQuaternion, Vector3, Vector6};
use serde::{Deserialize, Serialize};

/// The translation model with whatever it needs to evaluate.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Translation {
    Flat { gravity_mps2: f64 },
    Spherical(SphericalMoon),
}

impl Translation {
    #[inline]
    pub fn from_nue(&self, r_nue: &Nue, v_nue: &Nue) -> Vector6<f64> {
        match self {
            Self::Flat { .. } => translation_flat::pack(r_nue, v_nue),
            Self::Spherical(moon) => moon.from_nue(r_nue, v_nue),
        }
    }

    /// Position (m) and Moon-relative velocity (m/s) in site NUE.
    #[inline]
    pub fn to_nue(&self, x: &Vector6<f64>) -> (Nue, Nue) {
        match self {
            Self::Flat { .. } => (
                translation_flat::position_nue(x),
                translation_flat::velocity_nue(x),
            ),
            Self::Spherical(moon) => moon.to_nue(x),
        }
    }

    /// Height above the surface (the plane, or the sphere), m.
    #[inline]
    pub fn altitude(&self, x: &Vector6<f64>) -> f64 {
        match self {
            Self::Flat { .. } => translation_flat::altitude(x),
            Self::Spherical(moon) => moon.altitude(x),
        }
    }

    #[inline]
    fn derivative(&self, x: &Vector6<f64>, a_thrust_nue: &Nue) -> Vector6<f64> {
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
    /// Non-gravitational acceleration of the centre of mass (engines, RCS forces and, with
    /// the landing gear, contact forces, over the mass), body axes, m/s^2: what an ideal
    /// accelerometer at the centre of mass measures. Filled by [`Plant::delivered_firing`]
    /// (the integration never reads it).
    pub specific_force_body_mps2: Vector3<f64>,
    /// Thruster model: sum of the firing thrusters' force magnitudes, N (computed only when
    /// the RCS propellant is booked).
    pub rcs_thrust_sum_n: f64,
}

/// The state of a touchdown, frozen at the crossing.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Touchdown {
    pub time_s: f64,
    pub v_nue_mps: Nue,
    pub q_body_to_nue: Quaternion<f64>,
    pub omega_body_radps: Body,
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
    /// The landing gear's discrete state (unused without the gear).
    #[serde(default)]
    pub gear: GearRun,
    /// The slosh pendulums (unused without slosh).
    #[serde(default)]
    pub slosh: SloshState,
    /// Integral of the specific force (body axes) over the time advanced since
    /// [`PlantRun::start_means`], m/s: RK4's quadrature along the stages of each accepted
    /// sub-step, split where the sub-steps split (thruster switch times, events).
    #[serde(default)]
    pub specific_force_integral_body: Vector3<f64>,
    /// Integral of the body rate over the same time, rad (the same quadrature).
    #[serde(default)]
    pub omega_integral_body: Vector3<f64>,
    /// The time advanced since [`PlantRun::start_means`], s.
    #[serde(default)]
    pub mean_span_s: f64,
}

impl PlantRun {
    /// Starts new means of the specific force and the body rate (the Co-Simulation step
    /// does, at its start).
    #[inline]
    pub fn start_means(&mut self) {
        self.specific_force_integral_body = Vector3::zeros();
        self.omega_integral_body = Vector3::zeros();
        self.mean_span_s = 0.0;
    }

    /// The mean specific force over the time advanced since [`PlantRun::start_means`],
    /// body axes, m/s^2; `None` when no time was advanced.
    pub fn specific_force_mean_body(&self) -> Option<Vector3<f64>> {
        (self.mean_span_s > 0.0).then(|| self.specific_force_integral_body / self.mean_span_s)
    }

    /// The mean body rate over the time advanced since [`PlantRun::start_means`], rad/s;
    /// `None` when no time was advanced.
    pub fn omega_mean_body(&self) -> Option<Vector3<f64>> {
        (self.mean_span_s > 0.0).then(|| self.omega_integral_body / self.mean_span_s)
    }

    /// Takes the state `x` and the pendulums `pendulums` (`None`: unchanged, without slosh)
    /// reached over `span_s`, with the integrals of the means over it.
    #[inline]
    fn accept(
        &mut self,
        x: PlantState,
        pendulums: Option<SloshState>,
        integrals: &Vector6<f64>,
        span_s: f64,
    ) {
        self.state = x;
        if let Some(pendulums) = pendulums {
            self.slosh = pendulums;
        }
        self.accumulate_means(integrals, span_s);
    }

    /// Adds a sub-step's integrals (specific force, then body rate) over `span_s`.
    #[inline]
    fn accumulate_means(&mut self, integrals: &Vector6<f64>, span_s: f64) {
        self.specific_force_integral_body += integrals.fixed_rows::<3>(0);
        self.omega_integral_body += integrals.fixed_rows::<3>(3);
        self.mean_span_s += span_s;
    }
}

/// What a Co-Simulation step may change in a [`PlantRun`], kept to put the run back when the
/// step fails: the run but the touchdown record, which a step only ever sets where there was
/// none, and the pendulums, which only slosh moves. Smaller than the run, it is copied in a
/// few moves where the whole run took a `memcpy` at every step.
#[derive(Debug, Clone, Copy)]
pub struct RunCheckpoint {
    // The state field by field: copied whole (144 bytes) it would be a `memcpy` call.
    translation: Vector6<f64>,
    q_body_to_nue: Quaternion<f64>,
    omega_body: Body,
    mass_kg: f64,
    thrust_lag_n: f64,
    torque_lag_body_nm: Body,
    propellant_exhausted: bool,
    had_touchdown: bool,
    rcs_firing_at_step_end: Firing,
    gear: GearRun,
    slosh: Option<SloshState>,
    specific_force_integral_body: Vector3<f64>,
    omega_integral_body: Vector3<f64>,
    mean_span_s: f64,
}

impl RunCheckpoint {
    /// Whether the propellant was exhausted at the checkpoint.
    pub fn propellant_exhausted(&self) -> bool {
        self.propellant_exhausted
    }

    /// Whether the touchdown was recorded at the checkpoint.
    pub fn had_touchdown(&self) -> bool {
        self.had_touchdown
    }

    /// The landing gear's latches at the checkpoint.
    pub fn gear(&self) -> &GearRun {
        &self.gear
    }

    /// The mass at the checkpoint, kg.
    pub fn mass_kg(&self) -> f64 {
        self.mass_kg
    }

    /// The pendulums at the checkpoint (`None`: not kept, without slosh).
    pub fn slosh(&self) -> Option<&SloshState> {
        self.slosh.as_ref()
    }
}

impl PlantRun {
    /// What [`PlantRun::restore`] needs to undo a step of `plant` from here.
    #[inline]
    pub fn checkpoint(&self, plant: &Plant) -> RunCheckpoint {
        let x = &self.state;
        RunCheckpoint {
            translation: x.translation,
            q_body_to_nue: x.q_body_to_nue,
            omega_body: x.omega_body,
            mass_kg: x.mass_kg,
            thrust_lag_n: x.thrust_lag_n,
            torque_lag_body_nm: x.torque_lag_body_nm,
            propellant_exhausted: self.propellant_exhausted,
            had_touchdown: self.touchdown.is_some(),
            rcs_firing_at_step_end: self.rcs_firing_at_step_end,
            gear: self.gear,
            slosh: plant.slosh.is_some().then_some(self.slosh),
            specific_force_integral_body: self.specific_force_integral_body,
            omega_integral_body: self.omega_integral_body,
            mean_span_s: self.mean_span_s,
        }
    }

    /// The run as it was at `checkpoint`, taken before a step of the same plant.
    pub fn restore(&mut self, checkpoint: &RunCheckpoint) {
        self.state = PlantState {
            translation: checkpoint.translation,
            q_body_to_nue: checkpoint.q_body_to_nue,
            omega_body: checkpoint.omega_body,
            mass_kg: checkpoint.mass_kg,
            thrust_lag_n: checkpoint.thrust_lag_n,
            torque_lag_body_nm: checkpoint.torque_lag_body_nm,
        };
        self.propellant_exhausted = checkpoint.propellant_exhausted;
        if !checkpoint.had_touchdown {
            self.touchdown = None;
        }
        self.rcs_firing_at_step_end = checkpoint.rcs_firing_at_step_end;
        self.gear = checkpoint.gear;
        if let Some(pendulums) = checkpoint.slosh {
            self.slosh = pendulums;
        }
        self.specific_force_integral_body = checkpoint.specific_force_integral_body;
        self.omega_integral_body = checkpoint.omega_integral_body;
        self.mean_span_s = checkpoint.mean_span_s;
    }
}

/// What [`PlantRun`]'s means integrate at a state: the specific force (body axes), then the
/// body rate.
#[inline]
fn mean_integrand(specific_force_body: &Vector3<f64>, omega_body: &Vector3<f64>) -> Vector6<f64> {
    Vector6::new(
        specific_force_body.x,
        specific_force_body.y,
        specific_force_body.z,
        omega_body.x,
        omega_body.y,
        omega_body.z,
    )
}

/// [`PlantState`] without the actuator lag states, which rest when there are no lags.
#[derive(Debug, Clone, Copy)]
struct RigidState {
    translation: Vector6<f64>,
    q_body_to_nue: Quaternion<f64>,
    omega_body: Body,
    mass_kg: f64,
}

impl OdeState for RigidState {
    /// [`PlantState::add_scaled`]'s operations on these components.
    #[inline(always)]
    fn add_scaled(&self, h: f64, d: &Self) -> Self {
        Self {
            translation: self.translation + d.translation * h,
            q_body_to_nue: self.q_body_to_nue + d.q_body_to_nue * h,
            omega_body: self.omega_body + d.omega_body * h,
            mass_kg: self.mass_kg + d.mass_kg * h,
        }
    }
}

/// The plant state and the slosh pendulums, integrated together when slosh is on.
#[derive(Debug, Clone, Copy)]
struct Coupled {
    plant: PlantState,
    slosh: SloshState,
}

impl OdeState for Coupled {
    fn add_scaled(&self, h: f64, d: &Self) -> Self {
        Self {
            plant: self.plant.add_scaled(h, &d.plant),
            slosh: self.slosh.add_scaled(h, &d.slosh),
        }
    }
}

/// Most RCS commands in flight at once per thruster (and torque commands): a valve delay of
/// up to `RCS_HISTORY_CAPACITY - 2` communication steps.
pub const RCS_HISTORY_CAPACITY: usize = 16;

/// The RCS commands issued but not yet acted on (or still acting), absolute times in s.
/// Kept apart from [`PlantRun`] (which a step checkpoints to restore it on an error): 3.7 kB
/// that only a valve delay needs, passed to [`Plant::advance_with_history`].
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct RcsHistory {
    /// Thruster model: the pulses `(start, end)` of each thruster, delayed.
    pub pulses: [[Option<(f64, f64)>; RCS_HISTORY_CAPACITY]; THRUSTER_COUNT],
    /// Torque model: `(from, torque command)`, each acting from its time until the next.
    pub torques: [Option<(f64, Vector3<f64>)>; RCS_HISTORY_CAPACITY],
}

/// The landing gear at a state, as the outputs show it.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct GearStatus {
    pub contact: super::gear::Contact,
    pub tipped_over: bool,
    /// At rest on the gear after touchdown: three or more footpads on the terrain, slower
    /// than `SETTLED_SPEED_MPS` and `SETTLED_RATE_RADPS`, not tipped over.
    pub settled: bool,
}

/// What the landing gear has latched.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct GearRun {
    /// The gear's engine cut-off has fired: no thrust from then on.
    pub engine_cut: bool,
    /// Time the centre of mass reached the terrain (the run ends there).
    pub crashed_at_s: Option<f64>,
    /// The centre of mass has been outside the footprint (or the lander on its side) after
    /// touchdown.
    pub tipped_over: bool,
}

/// How an advance ended.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Advance {
    Reached,
    /// Touchdown at this time (<= the requested end). With the landing gear: the centre of
    /// mass reached the terrain at this time (the lander fell over or the gear gave way; the
    /// touchdown proper, the first footpad contact, does not stop the advance).
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
    /// The landing gear and terrain; `None` (the default) without.
    #[serde(default)]
    pub gear: Option<Gear>,
    /// Fastest change of the delivered thrust, N/s; 0 = none.
    #[serde(default)]
    pub throttle_rate_limit_nps: f64,
    /// RCS valve delay, s; 0 = none.
    #[serde(default)]
    pub rcs_valve_delay_s: f64,
    /// `1 / (rcs_isp g0)`, s/m: RCS mass flow per newton of thruster force; `None`: the RCS
    /// propellant is not booked.
    #[serde(default)]
    pub rcs_mass_flow_per_newton: Option<f64>,
    /// Propellant slosh; `None` (the default) without.
    #[serde(default)]
    pub slosh: Option<Slosh>,
    /// Inertia and centre of mass moving with the propellant; `None` (the default): fixed.
    #[serde(default)]
    pub mass_properties: Option<super::mass_properties::MassProperties>,
}

/// The actuator set-points before any lag.
struct Targets {
    thrust_n: f64,
    rcs_torque_body_nm: Vector3<f64>,
    /// Rate-limited thrust without a lag: the constant rate of the delivered thrust over
    /// the RK4 piece (+-limit towards the target, 0 at it), N/s; fixed at the piece start.
    thrust_ramp_nps: f64,
}

/// How a piece searched for events ended.
enum PieceEnd {
    /// At its end, without an event.
    Whole,
    /// At an event at this time, applied; the sub-step goes on from there.
    At(f64),
    /// At the end of the run (touchdown; with the gear, the centre of mass on the terrain).
    Stopped(f64),
}

/// Which event ended an RK4 piece.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Event {
    Touchdown,
    Exhaustion,
    /// Gear: the first footpad reaches the terrain.
    FootContact,
    /// Gear: the lowest footpad reaches `engine_cutoff_height`.
    CutoffHeight,
    /// Rate-limited thrust (no lag) reaches its target.
    RampEnd(f64),
}

impl Plant {
    /// Validates the parameters and builds the plant and its initial run state; the second
    /// element is a warning worth logging (a noticeably non-unit q0 that was normalised).
    pub fn new(p: &PlantParameters) -> Result<(Self, PlantRun, Option<String>), ParameterError> {
        p.check()?;
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
            gear: p.gear.enabled.then(|| Gear::new(&p.gear)),
            throttle_rate_limit_nps: p.actuators.throttle_rate_limit_nps,
            rcs_valve_delay_s: p.actuators.rcs_valve_delay_s,
            rcs_mass_flow_per_newton: (p.actuators.rcs_isp_s > 0.0)
                .then(|| 1.0 / (p.actuators.rcs_isp_s * p.g0_mps2)),
            slosh: p
                .slosh
                .enabled
                .then(|| Slosh::new(&p.slosh, p.dry_mass_kg, p.m0_kg)),
            mass_properties: super::mass_properties::MassProperties::new(p),
        };
        let translation_state = translation.from_nue(&Nue(p.r0_nue_m), &Nue(p.v0_nue_mps));
        let altitude = translation.altitude(&translation_state);
        if plant.gear.is_none() && altitude.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
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
            omega_body: Body(p.omega0_body_radps),
            mass_kg: p.m0_kg,
            thrust_lag_n: 0.0,
            torque_lag_body_nm: Body::zeros(),
        };
        let run = PlantRun {
            state,
            propellant_exhausted: false,
            touchdown: None,
            rcs_firing_at_step_end: NONE_FIRING,
            gear: GearRun::default(),
            slosh: if p.slosh.enabled {
                Slosh::new(&p.slosh, p.dry_mass_kg, p.m0_kg).initial_state(&p.slosh)
            } else {
                SloshState::default()
            },
            specific_force_integral_body: Vector3::zeros(),
            omega_integral_body: Vector3::zeros(),
            mean_span_s: 0.0,
        };
        Ok((plant, run, warning))
    }

    /// The unit thrust direction, body axes.
    pub fn thrust_direction_body(&self) -> Vector3<f64> {
        self.thrust_direction_body
    }

    /// Mass flow per newton of engine thrust, `1 / (Isp g0)`, s/m.
    pub fn mass_flow_per_newton(&self) -> f64 {
        self.mass_flow_per_newton
    }

    /// The steady-state actuator targets: each command saturated once per evaluation.
    #[inline]
    fn targets(&self, commands: &Commands, exhausted: bool) -> Targets {
        Targets {
            thrust_n: if exhausted {
                0.0
            } else {
                self.engines.saturate(commands.thrust_cmd_n)
            },
            rcs_torque_body_nm: self.rcs.saturate(&commands.torque_cmd_body_nm),
            thrust_ramp_nps: 0.0,
        }
    }

    /// Rate limit without a lag: the rate towards `target` from the delivered `thrust_n`.
    #[inline]
    fn thrust_ramp(&self, target: f64, thrust_n: f64) -> f64 {
        let limit = self.throttle_rate_limit_nps;
        if limit > 0.0 && self.engines.time_constant_s == 0.0 {
            if target > thrust_n {
                limit
            } else if target < thrust_n {
                -limit
            } else {
                0.0
            }
        } else {
            0.0
        }
    }

    /// The targets for a piece starting at `x` (the ramp direction of a rate limit fixed).
    #[inline]
    fn targets_at(&self, commands: &Commands, exhausted: bool, x: &PlantState) -> Targets {
        let mut targets = self.targets(commands, exhausted);
        targets.thrust_ramp_nps = self.thrust_ramp(targets.thrust_n, x.thrust_lag_n);
        targets
    }

    /// Whether the actuator lag states take part in the dynamics (either time constant > 0).
    #[inline]
    pub fn has_actuator_lags(&self) -> bool {
        self.engines.time_constant_s > 0.0
            || self.rcs.time_constant_s > 0.0
            || self.throttle_rate_limit_nps > 0.0
    }

    /// Whether the delivered thrust is the thrust state (a lag or a rate limit).
    pub fn thrust_is_a_state(&self) -> bool {
        self.engines.time_constant_s > 0.0 || self.throttle_rate_limit_nps > 0.0
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
        let mut d = self.delivered_from(x, &self.targets(commands, exhausted), firing, exhausted);
        d.specific_force_body_mps2 = self.specific_force_body(x, &d);
        if let Some(mp) = &self.mass_properties {
            d.engine_torque_body_nm += mp
                .engine_torque_shift_body_nm(x.mass_kg, &(self.thrust_direction_body * d.thrust_n));
        }
        d
    }

    /// [`Plant::delivered_firing`] at the state of `run`; with slosh on, the specific force
    /// is the rigid part's, solved with the pendulums (the accelerometer sits on it).
    pub fn delivered_run(
        &self,
        run: &PlantRun,
        commands: &Commands,
        firing: &Firing,
        exhausted: bool,
    ) -> Delivered {
        let mut d = self.delivered_firing(&run.state, commands, firing, exhausted);
        if let Some(slosh) = &self.slosh {
            let base = self.delivered_from(
                &run.state,
                &self.targets(commands, exhausted),
                firing,
                exhausted,
            );
            d.specific_force_body_mps2 = self
                .coupled_accelerations(slosh, &run.state, &run.slosh, &base)
                .specific_force_body_mps2;
        }
        d
    }

    /// The specific force at `x` with the actuators delivering `d`, body axes, m/s^2 (see
    /// [`Delivered::specific_force_body_mps2`]); the mass as the equations of motion use it.
    #[inline(always)]
    pub fn specific_force_body(&self, x: &PlantState, d: &Delivered) -> Vector3<f64> {
        let mass_kg = x.mass_kg.max(self.dry_mass_kg);
        let actuators = self.thrust_direction_body * d.thrust_n + d.rcs_force_body_n;
        match self.contact(x) {
            None => actuators / mass_kg,
            Some(c) => {
                let gear_body =
                    UnitQuaternion::from_quaternion(x.q_body_to_nue).inverse() * c.force_nue_n;
                (actuators + gear_body) / mass_kg
            }
        }
    }

    /// The landing gear's contact forces at `x` (`None` without the gear).
    #[inline]
    pub fn contact(&self, x: &PlantState) -> Option<super::gear::Contact> {
        self.gear.as_ref().map(|gear| {
            let (r, v) = self.translation.to_nue(&x.translation);
            gear.contact(&r.0, &v.0, &x.q_body_to_nue, &x.omega_body.0)
        })
    }

    /// The landing gear's view of `run`: contact forces and strokes, tipped over (latched),
    /// settled (`None` without the gear).
    pub fn gear_status(&self, run: &PlantRun) -> Option<GearStatus> {
        let contact = self.contact(&run.state)?;
        let feet = contact.stroke_m.iter().filter(|s| **s > 0.0).count();
        let (_, v) = self.translation.to_nue(&run.state.translation);
        let settled = run.touchdown.is_some()
            && !run.gear.tipped_over
            && feet >= 3
            && v.norm() < super::gear::SETTLED_SPEED_MPS
            && run.state.omega_body.norm() < super::gear::SETTLED_RATE_RADPS;
        Some(GearStatus {
            contact,
            tipped_over: run.gear.tipped_over,
            settled,
        })
    }

    /// Whether the engines are off for good: propellant exhausted or cut by the gear.
    pub fn engines_cut(&self, run: &PlantRun) -> bool {
        run.propellant_exhausted || run.gear.engine_cut
    }

    /// When the run stopped for good: touchdown without the gear, the centre of mass on the
    /// terrain with it.
    #[inline]
    pub fn stopped_at(&self, run: &PlantRun) -> Option<f64> {
        match self.gear {
            None => run.touchdown.map(|td| td.time_s),
            Some(_) => run.gear.crashed_at_s,
        }
    }

    /// Gear: height of the centre of mass above the terrain along its normal; the event
    /// function of the end of the run. Without the gear the altitude.
    #[inline]
    fn ground_indicator(&self, x: &PlantState) -> f64 {
        match &self.gear {
            None => self.altitude(x),
            Some(gear) => gear.clearance(&self.translation.to_nue(&x.translation).0 .0),
        }
    }

    /// Gear: clearance of the lowest footpad (unloaded leg), m.
    pub fn lowest_foot_clearance(&self, gear: &Gear, x: &PlantState) -> f64 {
        let (r_nue, _) = self.translation.to_nue(&x.translation);
        gear.lowest_foot_clearance(&r_nue.0, &x.q_body_to_nue)
    }

    #[inline(always)]
    fn delivered_from(
        &self,
        x: &PlantState,
        targets: &Targets,
        firing: &Firing,
        exhausted: bool,
    ) -> Delivered {
        let thrust_n = if exhausted {
            0.0
        } else if self.throttle_rate_limit_nps > 0.0 {
            x.thrust_lag_n
        } else {
            lagged_or_direct(
                targets.thrust_n,
                x.thrust_lag_n,
                self.engines.time_constant_s,
            )
        };
        let mut rcs_thrust_sum_n = 0.0;
        let (rcs_force_body_n, rcs_torque_body_nm) = match &self.thrusters {
            Some(thrusters) => {
                if self.rcs_mass_flow_per_newton.is_some() {
                    rcs_thrust_sum_n =
                        thrusters.force_n * firing.iter().filter(|f| **f).count() as f64;
                }
                thrusters.force_and_torque_body(firing)
            }
            None => {
                let tau = self.rcs.time_constant_s;
                let torque = Vector3::from_fn(|k, _| {
                    lagged_or_direct(
                        targets.rcs_torque_body_nm[k],
                        x.torque_lag_body_nm.0[k],
                        tau,
                    )
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
            specific_force_body_mps2: Vector3::zeros(),
            rcs_thrust_sum_n,
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
        self.derivative_from(
            x,
            &self.targets_at(commands, exhausted, x),
            firing,
            exhausted,
        )
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
        let a_thrust_nue = body_to_nue(&x.q_body_to_nue, &Body(thrust_body));
        let torque_body = Body(d.rcs_torque_body_nm + d.engine_torque_body_nm);
        // Without the gear both pass through untouched.
        let (a_thrust_nue, torque_body) = match self.contact(x) {
            None => (a_thrust_nue, torque_body),
            Some(c) => (
                a_thrust_nue + Nue(c.force_nue_n / mass_kg),
                torque_body + Body(c.torque_body_nm),
            ),
        };
        // Without lags the lag states stay at zero: skip their rates altogether. The torque
        // lag belongs to the torque model; with thrusters it stays at rest.
        let (thrust_lag_n, torque_lag_body_nm) = if self.has_actuator_lags() {
            let tau_rcs = self.rcs.time_constant_s;
            let lag = lag_rate(
                targets.thrust_n,
                x.thrust_lag_n,
                self.engines.time_constant_s,
            );
            let limit = self.throttle_rate_limit_nps;
            (
                if limit == 0.0 {
                    lag
                } else if self.engines.time_constant_s > 0.0 {
                    lag.max(-limit).min(limit)
                } else {
                    targets.thrust_ramp_nps
                },
                match self.thrusters {
                    None => Body(Vector3::from_fn(|k, _| {
                        lag_rate(
                            targets.rcs_torque_body_nm[k],
                            x.torque_lag_body_nm.0[k],
                            tau_rcs,
                        )
                    })),
                    Some(_) => Body::zeros(),
                },
            )
        } else {
            (0.0, Body::zeros())
        };
        PlantState {
            translation: self.translation.derivative(&x.translation, &a_thrust_nue),
            q_body_to_nue: quaternion_rate(&x.q_body_to_nue, &x.omega_body),
            omega_body: match &self.mass_properties {
                None => omega_dot_body(&self.inertia_body_kgm2, &x.omega_body, &torque_body),
                Some(mp) => {
                    let shift = mp.engine_torque_shift_body_nm(
                        x.mass_kg,
                        &(self.thrust_direction_body * d.thrust_n),
                    );
                    omega_dot_body(
                        &mp.inertia_body_kgm2(x.mass_kg),
                        &x.omega_body,
                        &(torque_body + Body(shift)),
                    )
                }
            },
            mass_kg: match self.rcs_mass_flow_per_newton {
                None => -d.thrust_n * self.mass_flow_per_newton,
                Some(per_newton) => {
                    -d.thrust_n * self.mass_flow_per_newton
                        - self.rcs_force_magnitude_n(d) * per_newton
                }
            },
            thrust_lag_n,
            torque_lag_body_nm,
        }
    }

    /// Sum of the force magnitudes of the RCS thrusters `d` fires, N: thruster model, the
    /// firing thrusters' force; torque model, per axis the couple of two thrusters at
    /// `rcs_moment_arm` that gives the delivered torque, `|tau| / arm`.
    pub fn rcs_force_magnitude_n(&self, d: &Delivered) -> f64 {
        match &self.thrusters {
            Some(_) => d.rcs_thrust_sum_n,
            None => {
                let arm = self.rcs.moment_arm_m;
                if arm > 0.0 {
                    d.rcs_torque_body_nm.abs().sum() / arm
                } else {
                    0.0
                }
            }
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

    /// [`Plant::rk4`] of the plant with its slosh pendulums: without slosh exactly `rk4`
    /// (the pendulums untouched: `None`, nothing to copy back). The third element is the integral over the step of the
    /// specific force (body axes, m/s; with slosh the rigid part's, solved with the
    /// pendulums), then of the body rate (rad).
    #[allow(clippy::too_many_arguments)]
    fn rk4_pair(
        &self,
        x: &PlantState,
        pendulums: &SloshState,
        commands: &Commands,
        firing: &Firing,
        exhausted: bool,
        t: f64,
        h: f64,
    ) -> (PlantState, Option<SloshState>, Vector6<f64>) {
        let Some(slosh) = &self.slosh else {
            let (y, integral) = self.rk4(x, commands, firing, exhausted, t, h);
            return (y, None, integral);
        };
        let targets = self.targets_at(commands, exhausted, x);
        let (y, integral) = rk4_step_with_quadrature(
            |_t, y: &Coupled| self.coupled_derivative(slosh, y, &targets, firing, exhausted),
            t,
            &Coupled {
                plant: *x,
                slosh: *pendulums,
            },
            h,
        );
        (
            y.plant.renormalised(),
            Some(y.slosh.renormalised()),
            integral,
        )
    }

    /// The derivative of the plant with its slosh pendulums, body and pendulums solved
    /// together (flat Moon: the translational derivative's velocity rows are the
    /// acceleration in NUE), and the means' integrand (the rigid part's specific force, the
    /// body rate).
    fn coupled_derivative(
        &self,
        slosh: &Slosh,
        y: &Coupled,
        targets: &Targets,
        firing: &Firing,
        exhausted: bool,
    ) -> (Coupled, Vector6<f64>) {
        let x = &y.plant;
        let d = self.delivered_from(x, targets, firing, exhausted);
        let mut dx = self.derivative_delivered(x, &d, targets);
        let c = self.coupled_accelerations(slosh, x, &y.slosh, &d);
        let specific_force_nue = body_to_nue(&x.q_body_to_nue, &Body(c.specific_force_body_mps2));
        dx.translation = self
            .translation
            .derivative(&x.translation, &specific_force_nue);
        dx.omega_body = Body(c.alpha_body_radps2);
        (
            Coupled {
                plant: dx,
                slosh: c.derivative,
            },
            mean_integrand(&c.specific_force_body_mps2, &x.omega_body.0),
        )
    }

    /// Body and pendulums solved together at `x` with the actuators delivering `d` (from
    /// [`Plant::delivered_from`], the moved centre of mass's engine torque not yet in it).
    fn coupled_accelerations(
        &self,
        slosh: &Slosh,
        x: &PlantState,
        pendulums: &SloshState,
        d: &Delivered,
    ) -> slosh_dynamics::Coupled {
        let mass_kg = x.mass_kg.max(self.dry_mass_kg);
        let thrust_body = self.thrust_direction_body * d.thrust_n;
        let mut force_body_n = thrust_body + d.rcs_force_body_n;
        let mut torque_body_nm = d.rcs_torque_body_nm + d.engine_torque_body_nm;
        if let Some(c) = self.contact(x) {
            force_body_n +=
                UnitQuaternion::from_quaternion(x.q_body_to_nue).inverse() * c.force_nue_n;
            torque_body_nm += c.torque_body_nm;
        }
        let inertia_body_kgm2 = match &self.mass_properties {
            None => self.inertia_body_kgm2,
            Some(mp) => {
                torque_body_nm += mp.engine_torque_shift_body_nm(x.mass_kg, &thrust_body);
                mp.inertia_body_kgm2(x.mass_kg)
            }
        };
        let loads = RigidLoads {
            mass_kg,
            inertia_body_kgm2,
            force_body_n,
            torque_body_nm,
            omega_body: x.omega_body.0,
        };
        slosh_dynamics::solve(slosh, &slosh.pendulums_at(mass_kg), pendulums, &loads)
    }

    // Inlined into `rk4_pair`, the step is written where its caller takes it, not copied.
    #[inline(always)]
    fn rk4(
        &self,
        x: &PlantState,
        commands: &Commands,
        firing: &Firing,
        exhausted: bool,
        t: f64,
        h: f64,
    ) -> (PlantState, Vector6<f64>) {
        let targets = self.targets_at(commands, exhausted, x);
        let (y, integral) = if self.has_actuator_lags() {
            rk4_step_with_quadrature(
                |_t, s: &PlantState| {
                    let d = self.delivered_from(s, &targets, firing, exhausted);
                    (
                        self.derivative_delivered(s, &d, &targets),
                        mean_integrand(&self.specific_force_body(s, &d), &s.omega_body.0),
                    )
                },
                t,
                x,
                h,
            )
        } else {
            // Without lags what the actuators deliver is constant over the step.
            let d = self.delivered_from(x, &targets, firing, exhausted);
            if let Some(gravity_mps2) = self.rigid_flat_gravity() {
                return self.rk4_rigid_flat(x, &d, gravity_mps2, h);
            }
            rk4_step_with_quadrature(
                #[inline(always)]
                |_t, s: &PlantState| {
                    (
                        self.derivative_delivered(s, &d, &targets),
                        mean_integrand(&self.specific_force_body(s, &d), &s.omega_body.0),
                    )
                },
                t,
                x,
                h,
            )
        };
        (y.renormalised(), integral)
    }

    /// The surface gravity when the step's dynamics are those of [`Plant::rk4_rigid_flat`]:
    /// flat Moon, no landing gear, fixed mass properties (lags and slosh are the caller's
    /// to exclude).
    #[inline]
    fn rigid_flat_gravity(&self) -> Option<f64> {
        match self.translation {
            Translation::Flat { gravity_mps2 }
                if self.gear.is_none() && self.mass_properties.is_none() =>
            {
                Some(gravity_mps2)
            }
            _ => None,
        }
    }

    /// [`Plant::rk4`] without lags, slosh, gear or moving mass properties over a flat Moon:
    /// the same operations in the same order as the general derivative gives (bit for bit),
    /// with what does not change over the step (the delivered torque and force, the mass
    /// rate, the lag states at rest) taken out of the stages and the branches of the options
    /// that are off gone, so that each stage keeps only the few values it needs.
    #[inline(always)]
    fn rk4_rigid_flat(
        &self,
        x: &PlantState,
        d: &Delivered,
        gravity_mps2: f64,
        h: f64,
    ) -> (PlantState, Vector6<f64>) {
        let direction = self.thrust_direction_body;
        let thrust_n = d.thrust_n;
        // What `derivative_delivered` and `specific_force_body` compute at every stage from
        // `d` alone.
        let torque_body = Body(d.rcs_torque_body_nm + d.engine_torque_body_nm);
        let actuators_body_n = direction * thrust_n + d.rcs_force_body_n;
        let mass_rate_kgps = match self.rcs_mass_flow_per_newton {
            None => -thrust_n * self.mass_flow_per_newton,
            Some(per_newton) => {
                -thrust_n * self.mass_flow_per_newton - self.rcs_force_magnitude_n(d) * per_newton
            }
        };
        let torque_model = self.thrusters.is_none();
        let (y, integral) = rk4_step_with_quadrature(
            #[inline(always)]
            |_t, s: &RigidState| {
                let mass_kg = s.mass_kg.max(self.dry_mass_kg);
                let specific_force_body = actuators_body_n / mass_kg;
                // The thruster model's thrust acceleration is the specific force itself.
                let thrust_body = if torque_model {
                    direction * (thrust_n / mass_kg)
                } else {
                    specific_force_body
                };
                let a_thrust_nue = body_to_nue(&s.q_body_to_nue, &Body(thrust_body));
                (
                    RigidState {
                        translation: translation_flat::derivative(
                            &s.translation,
                            gravity_mps2,
                            &a_thrust_nue,
                        ),
                        q_body_to_nue: quaternion_rate(&s.q_body_to_nue, &s.omega_body),
                        omega_body: omega_dot_body(
                            &self.inertia_body_kgm2,
                            &s.omega_body,
                            &torque_body,
                        ),
                        mass_kg: mass_rate_kgps,
                    },
                    mean_integrand(&specific_force_body, &s.omega_body.0),
                )
            },
            0.0,
            &RigidState {
                translation: x.translation,
                q_body_to_nue: x.q_body_to_nue,
                omega_body: x.omega_body,
                mass_kg: x.mass_kg,
            },
            h,
        );
        // The lag states' rates are zero: RK4's four additions of `0 * (h / 6)`, `0 * (h / 3)`,
        // `0 * (h / 3)` and `0 * (h / 6)`, in its order.
        let at_rest = |lag: f64| {
            let y = lag + 0.0 * (h / 6.0);
            let y = y + 0.0 * (h / 3.0);
            let y = y + 0.0 * (h / 3.0);
            y + 0.0 * (h / 6.0)
        };
        let y = PlantState {
            translation: y.translation,
            q_body_to_nue: y.q_body_to_nue,
            omega_body: y.omega_body,
            mass_kg: y.mass_kg,
            thrust_lag_n: at_rest(x.thrust_lag_n),
            torque_lag_body_nm: Body(x.torque_lag_body_nm.0.map(at_rest)),
        };
        (y.renormalised(), integral)
    }

    pub fn altitude(&self, x: &PlantState) -> f64 {
        self.translation.altitude(&x.translation)
    }

    /// Advances `run` from `t` to `t + h` under constant `commands`, in RK4 sub-steps of at
    /// most `integration_step_s`, stopping at a touchdown. After a touchdown it does not move.
    /// In the thruster model no thruster fires (see [`Plant::advance_with_duty`]).
    #[inline]
    pub fn advance(&self, run: &mut PlantRun, commands: &Commands, t: f64, h: f64) -> Advance {
        if let Some(time) = self.stopped_at(run) {
            return self.stop(time);
        }
        match self.advance_span(run, commands, &NONE_FIRING, t, h, t + h) {
            Some(time) => self.stop(time),
            None => Advance::Reached,
        }
    }

    /// [`Plant::advance_with_duty`] with the RCS valve delay, whose commands in flight
    /// `history` holds (untouched without a delay). `advance_with_duty` itself ignores the
    /// delay: it has no history to take the commands from.
    #[inline]
    pub fn advance_with_history(
        &self,
        run: &mut PlantRun,
        history: &mut RcsHistory,
        commands: &Commands,
        rcs_duty: &[f64; THRUSTER_COUNT],
        t: f64,
        h: f64,
    ) -> Advance {
        if self.rcs_valve_delay_s > 0.0 {
            self.advance_delayed(run, history, commands, rcs_duty, t, h)
        } else {
            self.advance_with_duty(run, commands, rcs_duty, t, h)
        }
    }

    /// [`Plant::advance_with_duty`] with the RCS valve delay `d`: the commands of this step
    /// join the history and act from `t + d` (thruster pulses `[t + d, t + d + on-time]`,
    /// torque commands from `t + d` until the next one; zero before the first), and the step
    /// is integrated in pieces that end at every delayed start and end inside it.
    fn advance_delayed(
        &self,
        run: &mut PlantRun,
        history: &mut RcsHistory,
        commands: &Commands,
        rcs_duty: &[f64; THRUSTER_COUNT],
        t: f64,
        h: f64,
    ) -> Advance {
        if let Some(time) = self.stopped_at(run) {
            return self.stop(time);
        }
        let delay = self.rcs_valve_delay_s;
        let end = t + h;
        let mut cuts: Vec<f64> = Vec::new();
        match &self.thrusters {
            Some(thrusters) => {
                let on_times_s = thrusters.on_times_s(rcs_duty, h, &run.rcs_firing_at_step_end);
                run.rcs_firing_at_step_end = on_times_s.map(|s| s >= h);
                for (k, pulses) in history.pulses.iter_mut().enumerate() {
                    for slot in pulses.iter_mut() {
                        if slot.is_some_and(|(_, e)| e <= t) {
                            *slot = None;
                        }
                    }
                    if on_times_s[k] > 0.0 {
                        if let Some(free) = pulses.iter_mut().find(|p| p.is_none()) {
                            *free = Some((t + delay, t + delay + on_times_s[k]));
                        }
                    }
                    for (s, e) in pulses.iter().flatten() {
                        cuts.extend([*s, *e]);
                    }
                }
            }
            None => {
                // A command is spent once a later one acts from the step's start.
                let latest_active = history
                    .torques
                    .iter()
                    .flatten()
                    .map(|(from, _)| *from)
                    .filter(|from| *from <= t)
                    .fold(f64::NEG_INFINITY, f64::max);
                for slot in history.torques.iter_mut() {
                    if slot.is_some_and(|(from, _)| from < latest_active) {
                        *slot = None;
                    }
                }
                if let Some(free) = history.torques.iter_mut().find(|p| p.is_none()) {
                    *free = Some((t + delay, commands.torque_cmd_body_nm));
                }
                cuts.extend(history.torques.iter().flatten().map(|(from, _)| *from));
            }
        }
        cuts.retain(|c| *c > t && *c < end);
        cuts.sort_by(f64::total_cmp);
        cuts.dedup();
        cuts.push(end);
        let mut start = t;
        for piece_end in cuts {
            let firing: Firing = std::array::from_fn(|k| {
                history.pulses[k]
                    .iter()
                    .flatten()
                    .any(|(s, e)| *s <= start && *e > start)
            });
            let torque = history
                .torques
                .iter()
                .flatten()
                .filter(|(from, _)| *from <= start)
                .max_by(|a, b| a.0.total_cmp(&b.0))
                .map_or(Vector3::zeros(), |(_, torque)| *torque);
            let piece_commands = Commands {
                thrust_cmd_n: commands.thrust_cmd_n,
                torque_cmd_body_nm: torque,
            };
            if let Some(time) = self.advance_span(
                run,
                &piece_commands,
                &firing,
                start,
                piece_end - start,
                piece_end,
            ) {
                return self.stop(time);
            }
            start = piece_end;
        }
        Advance::Reached
    }

    #[inline]
    fn stop(&self, time: f64) -> Advance {
        Advance::Touchdown(time)
    }

    /// [`Plant::advance`] with the RCS duties of the step: in the thruster model thruster `k`
    /// fires from `t` for `rcs_duty[k] h` (see `Thrusters::on_times_s`), and the step is
    /// integrated in pieces that end at every pulse end. The torque model ignores the duties.
    #[inline]
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
        if let Some(time) = self.stopped_at(run) {
            return self.stop(time);
        }
        let on_times_s = thrusters.on_times_s(rcs_duty, h, &run.rcs_firing_at_step_end);
        run.rcs_firing_at_step_end = on_times_s.map(|s| s >= h);
        let mut start = 0.0;
        for (end, firing) in pieces(&on_times_s, h) {
            let span_end = if end >= h { t + h } else { t + end };
            if let Some(time) =
                self.advance_span(run, commands, &firing, t + start, end - start, span_end)
            {
                return self.stop(time);
            }
            start = end;
        }
        Advance::Reached
    }

    /// From `t` over `h` s ending at `end_time` (= t + h, passed so that a whole step ends
    /// exactly at the master's time) with constant firing, in RK4 sub-steps of at most
    /// `integration_step_s`; returns the touchdown time if any.
    #[inline]
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
            let stopped = match &self.gear {
                None => self.advance_piecewise(run, commands, firing, start, end),
                Some(gear) => self.advance_gear(gear, run, commands, firing, start, end),
            };
            if let Some(time) = stopped {
                return Some(time);
            }
        }
        None
    }

    /// One sub-step with the landing gear: the gear's state at `start` (a footpad already on
    /// the terrain records the touchdown), then RK4 in pieces of at most `contact_step_s`
    /// while a footpad is on or near the terrain; the tip-over latch after each piece.
    fn advance_gear(
        &self,
        gear: &Gear,
        run: &mut PlantRun,
        commands: &Commands,
        firing: &Firing,
        start: f64,
        end: f64,
    ) -> Option<f64> {
        let lowest = self.lowest_foot_clearance(gear, &run.state);
        if run.touchdown.is_none() && lowest <= 0.0 {
            self.foot_contact(gear, run, start);
        }
        if let EngineCutoff::Height(height) = gear.cutoff {
            if lowest <= height {
                run.gear.engine_cut = true;
            }
        }
        let (_, v) = self.translation.to_nue(&run.state.translation);
        let speed = v.norm() + run.state.omega_body.norm() * gear.reach_m();
        let near = lowest < 0.05 + 2.0 * (end - start) * speed;
        let pieces = if near {
            ((end - start) / gear.contact_step_s).ceil().max(1.0)
        } else {
            1.0
        };
        let size = (end - start) / pieces;
        let count = pieces as usize;
        for k in 0..count {
            let a = start + k as f64 * size;
            let b = if k + 1 == count { end } else { a + size };
            if let Some(time) = self.advance_piecewise(run, commands, firing, a, b) {
                return Some(time);
            }
            if run.touchdown.is_some() && gear.tipped_over(&run.state.q_body_to_nue) {
                run.gear.tipped_over = true;
            }
        }
        None
    }

    /// The first footpad touches the terrain at `t`: the touchdown record, and the engine
    /// cut-off if it is set to the first contact.
    fn foot_contact(&self, gear: &Gear, run: &mut PlantRun, t: f64) {
        run.touchdown = Some(self.touchdown_at(&run.state, t));
        if gear.cutoff == EngineCutoff::FirstContact {
            run.gear.engine_cut = true;
        }
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
            // Without the gear `off` is `exhausted`.
            let off = run.propellant_exhausted || run.gear.engine_cut;
            let (x1, s1, q1) = self.rk4_pair(&run.state, &run.slosh, commands, firing, off, t, h);
            // Nearly every piece: no event can end it, and it is accepted whole without the
            // event search's set-up.
            if !self.may_end_at_event(run, &x1) {
                run.accept(x1, s1, &q1, h);
                return None;
            }
            match self.piece_with_events(run, commands, firing, off, t, h, end, (x1, s1, q1)) {
                PieceEnd::Whole => return None,
                PieceEnd::Stopped(time) => return Some(time),
                PieceEnd::At(event_time) => t = event_time,
            }
        }
        None
    }

    /// Whether [`Plant::piece_with_events`] may find an event in the piece from `run` to
    /// `x1`: an event function of the plant without the gear changes sign (the test that
    /// search starts with), or a throttle rate limit or the gear, whose events it checks.
    #[inline]
    fn may_end_at_event(&self, run: &PlantRun, x1: &PlantState) -> bool {
        if self.gear.is_some() || self.throttle_rate_limit_nps > 0.0 {
            return true;
        }
        let x0 = &run.state;
        let exhaustion = !run.propellant_exhausted
            && x0.mass_kg - self.dry_mass_kg > 0.0
            && x1.mass_kg - self.dry_mass_kg <= 0.0;
        exhaustion || (self.altitude(x0) > 0.0 && self.altitude(x1) <= 0.0)
    }

    /// The piece from `t` over `h` (ending at `end`) whose RK4 step from `run` is `step`,
    /// searched for events: accepted whole without one, otherwise advanced to the first
    /// event and the event applied. Out of line: most pieces never get here.
    #[allow(clippy::too_many_arguments)]
    #[inline(never)]
    fn piece_with_events(
        &self,
        run: &mut PlantRun,
        commands: &Commands,
        firing: &Firing,
        off: bool,
        t: f64,
        h: f64,
        end: f64,
        step: (PlantState, Option<SloshState>, Vector6<f64>),
    ) -> PieceEnd {
        let (x1, s1, q1) = step;
        let exhausted = run.propellant_exhausted;
        let x0 = &run.state;
        let s0 = &run.slosh;
        let crossing = |g: &dyn Fn(&PlantState) -> f64, g0: f64, g1: f64| {
            find_crossing(
                |s| g(&self.rk4_pair(x0, s0, commands, firing, off, t, s).0),
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
        let (g0, g1) = (self.ground_indicator(x0), self.ground_indicator(&x1));
        if g0 > 0.0 && g1 <= 0.0 {
            let tau = crossing(&|x: &PlantState| self.ground_indicator(x), g0, g1);
            if first.is_none_or(|(best, _)| tau < best) {
                first = Some((tau, Event::Touchdown));
            }
        }
        if self.throttle_rate_limit_nps > 0.0 {
            let target = self.targets(commands, off).thrust_n;
            let ramp = self.thrust_ramp(target, x0.thrust_lag_n);
            if ramp != 0.0 {
                // The thrust is linear over the piece: it reaches the target exactly then.
                let tau = (target - x0.thrust_lag_n) / ramp;
                if tau < h && first.is_none_or(|(best, _)| tau < best) {
                    first = Some((tau, Event::RampEnd(target)));
                }
            }
        }
        if let Some(gear) = &self.gear {
            let lowest = |x: &PlantState| self.lowest_foot_clearance(gear, x);
            let mut candidates: [Option<(Event, f64)>; 2] = [None, None];
            if run.touchdown.is_none() {
                candidates[0] = Some((Event::FootContact, 0.0));
            }
            if let (EngineCutoff::Height(height), false) = (gear.cutoff, run.gear.engine_cut) {
                candidates[1] = Some((Event::CutoffHeight, height));
            }
            for (event, height) in candidates.into_iter().flatten() {
                let (g0, g1) = (lowest(x0) - height, lowest(&x1) - height);
                if g0 > 0.0 && g1 <= 0.0 {
                    let tau = crossing(&|x: &PlantState| lowest(x) - height, g0, g1);
                    if first.is_none_or(|(best, _)| tau < best) {
                        first = Some((tau, event));
                    }
                }
            }
        }
        let Some((tau, event)) = first else {
            run.accept(x1, s1, &q1, h);
            return PieceEnd::Whole;
        };
        let (x, s, q) = if tau >= h {
            (x1, s1, q1)
        } else {
            self.rk4_pair(&run.state, &run.slosh, commands, firing, off, t, tau)
        };
        run.accept(x, s, &q, tau.min(h));
        let t = if tau >= h { end } else { t + tau };
        match event {
            Event::Exhaustion => self.exhaust(run),
            Event::Touchdown => {
                match &self.gear {
                    None => run.touchdown = Some(self.touchdown_at(&run.state, t)),
                    Some(gear) => {
                        if run.touchdown.is_none() {
                            self.foot_contact(gear, run, t);
                        }
                        run.gear.crashed_at_s = Some(t);
                    }
                }
                return PieceEnd::Stopped(t);
            }
            Event::FootContact => {
                if let Some(gear) = &self.gear {
                    self.foot_contact(gear, run, t);
                }
            }
            Event::CutoffHeight => run.gear.engine_cut = true,
            Event::RampEnd(target) => run.state.thrust_lag_n = target,
        }
        PieceEnd::At(t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// SplitMix64: a fixed, dependency-free sequence of test inputs.
    struct Cases(u64);

    impl Cases {
        fn next_u64(&mut self) -> u64 {
            self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            z ^ (z >> 31)
        }

        /// Uniform in `[lo, hi)`.
        fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
            lo + (hi - lo) * ((self.next_u64() >> 11) as f64 / (1u64 << 53) as f64)
        }

        fn one_in(&mut self, n: u64) -> bool {
            self.next_u64().is_multiple_of(n)
        }

        fn vector(&mut self, half_width: f64) -> Vector3<f64> {
            Vector3::from_fn(|_, _| self.uniform(-half_width, half_width))
        }
    }

    /// The general branch of [`Plant::rk4`] without lags (what runs when the plant has gear,
    /// moving mass properties or a spherical Moon), applied to any plant: the reference the
    /// rigid flat-Moon stages must reproduce bit for bit.
    fn rk4_general_without_lags(
        plant: &Plant,
        x: &PlantState,
        commands: &Commands,
        firing: &Firing,
        exhausted: bool,
        t: f64,
        h: f64,
    ) -> (PlantState, Vector6<f64>) {
        assert!(!plant.has_actuator_lags());
        let targets = plant.targets_at(commands, exhausted, x);
        let d = plant.delivered_from(x, &targets, firing, exhausted);
        let (y, integral) = rk4_step_with_quadrature(
            |_t, s: &PlantState| {
                (
                    plant.derivative_delivered(s, &d, &targets),
                    mean_integrand(&plant.specific_force_body(s, &d), &s.omega_body.0),
                )
            },
            t,
            x,
            h,
        );
        (y.renormalised(), integral)
    }

    fn bits(x: &PlantState, integral: &Vector6<f64>) -> Vec<u64> {
        x.translation
            .iter()
            .chain(x.q_body_to_nue.coords.iter())
            .chain(x.omega_body.0.iter())
            .chain([x.mass_kg, x.thrust_lag_n].iter())
            .chain(x.torque_lag_body_nm.0.iter())
            .chain(integral.iter())
            .map(|v| v.to_bits())
            .collect()
    }

    /// The rigid flat-Moon stages of `rk4_pair` give, bit for bit, the state, specific-force
    /// integral and body-rate integral of the general derivative, over random flight states
    /// and actuations of both RCS models, with and without RCS propellant and thrust
    /// misalignment.
    #[test]
    fn rigid_flat_stages_match_the_general_derivative_bit_for_bit() {
        let mut cases = Cases(0x5eed_1a2d_e2f0_0d01);
        let mut compared = 0;
        for rcs_model in [RcsModelKind::Torque, RcsModelKind::Thrusters] {
            for rcs_isp_s in [0.0, 220.0] {
                for misalignment_rad in [0.0, 0.02] {
                    let mut p = PlantParameters {
                        rcs_model: rcs_model as i32,
                        ..PlantParameters::default()
                    };
                    p.actuators.rcs_isp_s = rcs_isp_s;
                    p.thrust_line.misalignment_rad = misalignment_rad;
                    p.thrust_line.misalignment_azimuth_rad = 0.7;
                    let (plant, _, _) = Plant::new(&p).unwrap();
                    assert!(plant.slosh.is_none() && !plant.has_actuator_lags());
                    assert!(plant.rigid_flat_gravity().is_some());
                    let max_thrust_n = 1600.0;
                    let torque_limit_nm = plant.rcs.torque_limit_nm();
                    for _ in 0..250 {
                        let axis = cases.vector(1.0);
                        let tilt_rad = if cases.one_in(8) {
                            0.0
                        } else {
                            cases.uniform(0.0, 3.1)
                        };
                        let q = if axis.norm() > 1e-3 {
                            let (s, c) = libm::sincos(0.5 * tilt_rad);
                            let u = axis.normalize() * s;
                            Quaternion::new(c, u.x, u.y, u.z)
                        } else {
                            Quaternion::identity()
                        };
                        let omega_half_width = if cases.one_in(4) { 3.0 } else { 0.2 };
                        // Slow states too (hover, touchdown), where a rounding difference in
                        // an acceleration is not lost in the velocity's own rounding.
                        let speed_mps = match cases.next_u64() % 3 {
                            0 => 150.0,
                            1 => 1.0,
                            _ => 1e-3,
                        };
                        let x = PlantState {
                            translation: Vector6::new(
                                cases.uniform(-3000.0, 3000.0),
                                cases.uniform(0.01, 3000.0),
                                cases.uniform(-3000.0, 3000.0),
                                cases.uniform(-speed_mps, speed_mps),
                                cases.uniform(-speed_mps, speed_mps),
                                cases.uniform(-speed_mps, speed_mps),
                            ),
                            q_body_to_nue: q,
                            omega_body: Body(cases.vector(omega_half_width)),
                            // Down to just below the dry mass (clamped in the stages).
                            mass_kg: cases.uniform(599.9, 900.0),
                            thrust_lag_n: if cases.one_in(2) { 0.0 } else { -0.0 },
                            torque_lag_body_nm: Body::zeros(),
                        };
                        let thrust_cmd_n = match cases.next_u64() % 6 {
                            0 => 0.0,
                            1 => max_thrust_n,
                            // At and around the off threshold: no or almost no mass rate.
                            2 => cases.uniform(0.0, 2.0),
                            3 => cases.uniform(max_thrust_n, 2.0 * max_thrust_n),
                            _ => cases.uniform(0.0, max_thrust_n),
                        };
                        let commands = Commands {
                            thrust_cmd_n,
                            torque_cmd_body_nm: cases.vector(1.5 * torque_limit_nm),
                        };
                        let firing: Firing = std::array::from_fn(|_| cases.one_in(3));
                        let exhausted = cases.one_in(20);
                        let t = cases.uniform(0.0, 200.0);
                        let h = if cases.one_in(4) {
                            cases.uniform(1e-6, 0.01)
                        } else {
                            0.01
                        };
                        let (y, pendulums, integral) = plant.rk4_pair(
                            &x,
                            &SloshState::default(),
                            &commands,
                            &firing,
                            exhausted,
                            t,
                            h,
                        );
                        assert!(pendulums.is_none());
                        let (y_general, integral_general) = rk4_general_without_lags(
                            &plant, &x, &commands, &firing, exhausted, t, h,
                        );
                        assert_eq!(
                            bits(&y, &integral),
                            bits(&y_general, &integral_general),
                            "{rcs_model:?}, rcs_isp_s {rcs_isp_s}, misalignment \
                             {misalignment_rad}: {x:?} {commands:?} {firing:?} \
                             exhausted {exhausted}, h {h}"
                        );
                        compared += 1;
                    }
                }
            }
        }
        assert_eq!(compared, 2000);
    }
}
