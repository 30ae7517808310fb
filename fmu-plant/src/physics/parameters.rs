//! Plant parameters as the user sets them, their defaults and their validation.
//!
//! Each error names the field of [`PlantParameters`] to fix (and the element of a vector);
//! an interface layer names it as its users know it.
use super::actuators::{Engines, Rcs, ThrustLine};
use super::gear::{GearParameters, LEG_COUNT};
use super::slosh::SloshParameters;
use super::thrusters::{ThrusterLayout, THRUSTER_COUNT};
use nalgebra::{Quaternion, Vector3};
use serde::{Deserialize, Serialize};

/// Moon mean radius (IAU), m.
pub const MOON_RADIUS_M: f64 = 1_737_400.0;
/// Sidereal rotation rate of the Moon, 2 pi / 27.321661 d, rad/s.
pub const MOON_ROTATION_RATE_RADPS: f64 = 2.661_699_5e-6;
/// Chandrayaan-3 landing site (Shiv Shakti point), 69.373 S 32.319 E, the paper's mission.
pub const SITE_LATITUDE_RAD: f64 = -69.373 * std::f64::consts::PI / 180.0;
pub const SITE_LONGITUDE_RAD: f64 = 32.319 * std::f64::consts::PI / 180.0;
/// Highest |site latitude|: eq. 1 divides by cos(latitude).
pub const MAX_SITE_LATITUDE_RAD: f64 = 85.0 * std::f64::consts::PI / 180.0;

/// |q0| may differ from 1 by this much and is normalised silently (round-off of a unit
/// quaternion computed elsewhere).
const Q0_SILENT_NORM_TOLERANCE: f64 = 1e-6;
/// Up to this deviation q0 is normalised with a warning (four printed digits per component);
/// beyond it the value is most likely not meant as an attitude and is refused.
const Q0_WARN_NORM_TOLERANCE: f64 = 1e-3;

/// Translation model selector (FMI Enumeration `TranslationModel`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum TranslationModelKind {
    /// Paper eq. 2: flat, non-rotating Moon, uniform gravity.
    Flat = 1,
    /// Paper eq. 1 (corrected): spherical, rotating Moon, central gravity.
    Spherical = 2,
}

/// How the RCS is modelled (FMI Enumeration `RcsModel`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum RcsModelKind {
    /// A continuous torque per axis, saturated at the couple limit (the paper's model).
    Torque = 1,
    /// Eight on/off thrusters driven by duty cycles (`physics::thrusters`).
    Thrusters = 2,
}

/// Every parameter of the plant, in SI units.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PlantParameters {
    pub r0_nue_m: Vector3<f64>,
    pub v0_nue_mps: Vector3<f64>,
    /// Scalar first, as set by the user (normalised by `validated_q0`).
    pub q0_body_to_nue: [f64; 4],
    pub omega0_body_radps: Vector3<f64>,
    pub m0_kg: f64,
    pub gravity_mps2: f64,
    pub isp_s: f64,
    pub g0_mps2: f64,
    pub dry_mass_kg: f64,
    /// Principal moments `[Ixx, Iyy, Izz]`, kg m^2.
    pub inertia_body_kgm2: Vector3<f64>,
    pub engines: Engines,
    pub rcs: Rcs,
    pub thrust_line: ThrustLine,
    /// Raw Enumeration value (1 torque, 2 thrusters), checked in `validate`.
    pub rcs_model: i32,
    pub thrusters: ThrusterLayout,
    /// Raw Enumeration value (1 flat, 2 spherical), checked in `validate`.
    pub translation_model: i32,
    pub moon_radius_m: f64,
    pub moon_rotation_rate_radps: f64,
    pub site_latitude_rad: f64,
    pub site_longitude_rad: f64,
    /// Maximum RK4 sub-step, s.
    pub integration_step_s: f64,
    /// Landing gear and terrain (off by default).
    #[serde(default)]
    pub gear: GearParameters,
    /// Actuator effects beyond saturation and lag (each off by default).
    #[serde(default)]
    pub actuators: ActuatorRealism,
    /// Propellant slosh (off by default).
    #[serde(default)]
    pub slosh: SloshParameters,
    /// Principal inertia at the dry mass, kg m^2; all zero (the default): the inertia stays
    /// `inertia_body_kgm2` whatever the mass.
    #[serde(default)]
    pub inertia_dry_body_kgm2: Vector3<f64>,
    /// Centre of mass at the dry mass relative to where it is at m0, body axes, m (used with
    /// `inertia_dry_body_kgm2`).
    #[serde(default)]
    pub com_offset_dry_body_m: Vector3<f64>,
    /// An RCS thruster stuck off or on (`physics::faults`; thruster model only).
    #[serde(default)]
    pub rcs_stuck: super::faults::RcsStuck,
}

/// Optional actuator effects (`docs/plant-actuators.md`); 0 switches each off.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct ActuatorRealism {
    /// Fastest change of the delivered engine thrust, N/s; 0 = none.
    pub throttle_rate_limit_nps: f64,
    /// Delay between an RCS command and the valves acting on it, s; 0 = none.
    pub rcs_valve_delay_s: f64,
    /// Specific impulse of the RCS thrusters, s; 0 = their propellant is not booked.
    pub rcs_isp_s: f64,
}

impl Default for PlantParameters {
    fn default() -> Self {
        Self {
            r0_nue_m: Vector3::new(0.0, 800.0, 0.0),
            v0_nue_mps: Vector3::zeros(),
            q0_body_to_nue: [1.0, 0.0, 0.0, 0.0],
            omega0_body_radps: Vector3::zeros(),
            m0_kg: 900.0,
            gravity_mps2: 1.62,
            isp_s: 300.0,
            g0_mps2: 9.81,
            // 600 kg: one third of m0 is propellant, ~3.7x what the 172 s reference mission
            // burns (~81 kg), and every mass in [600, 900] kg hovers inside the throttle
            // range (m g = 972..1458 N within 720..1600 N), so a long hover or a Monte Carlo
            // excursion ends in flight rather than by an artefact of the default.
            dry_mass_kg: 600.0,
            inertia_body_kgm2: Vector3::new(400.0, 300.0, 450.0),
            engines: Engines {
                count: 2,
                min_thrust_per_engine_n: 360.0,
                max_thrust_per_engine_n: 800.0,
                off_threshold_n: 1.0,
                time_constant_s: 0.0,
                thrust_scale: 1.0,
                health: 1.0,
            },
            rcs: Rcs {
                thruster_force_n: 58.0,
                moment_arm_m: 1.0,
                time_constant_s: 0.0,
            },
            thrust_line: ThrustLine {
                misalignment_rad: 0.0,
                misalignment_azimuth_rad: 0.0,
                // Nozzle exit plane 1 m below the centre of mass on the thrust axis: with a
                // misalignment angle this lever arm turns it into a disturbance torque.
                point_body_m: Vector3::new(0.0, -1.0, 0.0),
            },
            rcs_model: RcsModelKind::Torque as i32,
            thrusters: ThrusterLayout::default(),
            translation_model: TranslationModelKind::Flat as i32,
            moon_radius_m: MOON_RADIUS_M,
            moon_rotation_rate_radps: MOON_ROTATION_RATE_RADPS,
            site_latitude_rad: SITE_LATITUDE_RAD,
            site_longitude_rad: SITE_LONGITUDE_RAD,
            integration_step_s: 0.01,
            gear: GearParameters::default(),
            actuators: ActuatorRealism::default(),
            slosh: SloshParameters::default(),
            inertia_dry_body_kgm2: Vector3::zeros(),
            com_offset_dry_body_m: Vector3::zeros(),
            rcs_stuck: Default::default(),
        }
    }
}

pub use fmi_model::parameter::ParameterError;

/// One field (or one element of a vector field, `index`).
type Field = (&'static str, Option<usize>);

fn refuse(
    (field, index): Field,
    value: impl ToString,
    reason: impl Into<String>,
) -> ParameterError {
    ParameterError::new(field, index, value, reason)
}

fn require(
    ok: bool,
    (field, index): Field,
    value: f64,
    reason: &str,
) -> Result<(), ParameterError> {
    ParameterError::require(ok, field, index, value, reason)
}

impl PlantParameters {
    pub fn translation_model_kind(&self) -> Result<TranslationModelKind, ParameterError> {
        match self.translation_model {
            1 => Ok(TranslationModelKind::Flat),
            2 => Ok(TranslationModelKind::Spherical),
            other => Err(refuse(
                ("translation_model", None),
                other,
                "must be 1 (flat) or 2 (spherical)",
            )),
        }
    }

    pub fn rcs_model_kind(&self) -> Result<RcsModelKind, ParameterError> {
        match self.rcs_model {
            1 => Ok(RcsModelKind::Torque),
            2 => Ok(RcsModelKind::Thrusters),
            other => Err(refuse(
                ("rcs_model", None),
                other,
                "must be 1 (torque) or 2 (thrusters)",
            )),
        }
    }

    /// The thruster layout's directions are unit vectors (within 1e-6). Checked in either
    /// RCS model.
    fn validate_thrusters(&self) -> Result<(), ParameterError> {
        let layout = &self.thrusters;
        for k in 0..THRUSTER_COUNT {
            let norm = layout.direction(k).norm();
            require(
                (norm - 1.0).abs() <= 1e-6,
                ("thrusters.direction_body", Some(3 * k)),
                layout.direction_body[3 * k],
                &format!(
                    "thruster {}'s direction has norm {norm}; it must be a unit vector",
                    k + 1
                ),
            )?;
        }
        Ok(())
    }

    /// The initial attitude as a unit quaternion, and a warning when it had to be normalised
    /// noticeably.
    pub fn validated_q0(&self) -> Result<(Quaternion<f64>, Option<String>), ParameterError> {
        let [w, x, y, z] = self.q0_body_to_nue;
        let q = lander_math::quaternion::to_nalgebra(&self.q0_body_to_nue);
        let norm = q.norm();
        let shown = format!("[{w}, {x}, {y}, {z}]");
        if !norm.is_finite() {
            return Err(refuse(("q0_body_to_nue", None), shown, "must be finite"));
        }
        let deviation = (norm - 1.0).abs();
        if deviation <= Q0_SILENT_NORM_TOLERANCE {
            Ok((q / norm, None))
        } else if deviation <= Q0_WARN_NORM_TOLERANCE {
            Ok((
                q / norm,
                Some(format!(
                    "q0_body_to_nue = {shown} has norm {norm}; normalised"
                )),
            ))
        } else {
            Err(refuse(
                ("q0_body_to_nue", None),
                shown,
                format!("norm {norm} is not 1 (|norm - 1| must be <= {Q0_WARN_NORM_TOLERANCE})"),
            ))
        }
    }

    /// Checks what the declarations cannot say: relations between parameters, the norm of a
    /// vector, whatever overflows in combination; each value on its own is checked against
    /// its declaration first ([`PlantParameters::check`]). The first offending one is named.
    pub fn validate(&self) -> Result<(), ParameterError> {
        // A rigid body's principal moments obey the triangle inequality (equality for a
        // flat plate); a violation means a typo, not a vehicle.
        let i = self.inertia_body_kgm2;
        for k in 0..3 {
            let others = i[(k + 1) % 3] + i[(k + 2) % 3];
            require(
                i[k] <= others * (1.0 + 1e-12),
                ("inertia_body_kgm2", Some(k)),
                i[k],
                "exceeds the sum of the other two principal moments: no rigid body has it",
            )?;
        }
        require(
            self.m0_kg > self.dry_mass_kg,
            ("m0_kg", None),
            self.m0_kg,
            &format!("must exceed dry_mass = {}", self.dry_mass_kg),
        )?;
        let e = &self.engines;
        require(
            e.min_thrust_per_engine_n <= e.max_thrust_per_engine_n,
            ("engines.min_thrust_per_engine_n", None),
            e.min_thrust_per_engine_n,
            &format!(
                "must not exceed engine_thrust_max = {}",
                e.max_thrust_per_engine_n
            ),
        )?;
        // An overflowing maximum itself is refused below, naming the maximum.
        let total_max_n = f64::from(e.count) * e.max_thrust_per_engine_n;
        require(
            !total_max_n.is_finite() || (total_max_n * e.thrust_scale).is_finite(),
            ("engines.thrust_scale", None),
            e.thrust_scale,
            "times the maximum total thrust overflows",
        )?;
        require(
            (0.0..=1.0).contains(&e.health),
            ("engines.health", None),
            e.health,
            "must be within [0, 1]",
        )?;
        if let Err((field, reason)) = self.rcs_stuck.check() {
            return Err(refuse((field, None), "", reason));
        }
        self.validate_thrusters()?;
        let kind = self.translation_model_kind()?;
        self.validated_q0()?;
        self.validate_gear(kind)?;
        self.validate_slosh(kind)?;
        self.validate_mass_properties()?;
        let a = &self.actuators;
        require(
            a.rcs_isp_s == 0.0 || (1.0 / (a.rcs_isp_s * self.g0_mps2)).is_finite(),
            ("actuators.rcs_isp_s", None),
            a.rcs_isp_s,
            "1 / (rcs_isp x g0) (RCS mass flow per newton) overflows",
        )?;
        if kind == TranslationModelKind::Flat && !self.gear.enabled {
            require(
                self.r0_nue_m.y > 0.0,
                ("r0_nue_m", Some(1)),
                self.r0_nue_m.y,
                "the altitude must be > 0: the plant starts in flight (ground contact is not modelled)",
            )?;
        }
        self.validate_products()
    }
}

/// Steepest terrain the gear model takes, rad (60 deg).
pub const MAX_TERRAIN_SLOPE_RAD: f64 = std::f64::consts::PI / 3.0;

impl PlantParameters {
    /// The gear: the footpads below the centre of mass always (a gear switched on later finds
    /// them valid), the start above the terrain and the flat Moon only with the gear on.
    fn validate_gear(&self, kind: TranslationModelKind) -> Result<(), ParameterError> {
        let g = &self.gear;
        for k in 0..LEG_COUNT {
            require(
                g.footpad_body_m[3 * k + 1] < 0.0,
                ("gear.footpad_body_m", Some(3 * k + 1)),
                g.footpad_body_m[3 * k + 1],
                "a footpad must lie below the centre of mass (body y < 0)",
            )?;
        }
        if !g.enabled {
            return Ok(());
        }
        if kind != TranslationModelKind::Flat {
            return Err(refuse(
                ("gear.enabled", None),
                "true",
                "the landing gear is modelled over the flat Moon only (translation_model = 1)",
            ));
        }
        let n = super::gear::terrain_normal(g.terrain_slope_rad, g.terrain_slope_azimuth_rad);
        let com_clearance = n.dot(&(self.r0_nue_m - Vector3::new(0.0, g.terrain_height_m, 0.0)));
        require(
            com_clearance > 0.0,
            ("r0_nue_m", Some(1)),
            self.r0_nue_m.y,
            "the centre of mass must start above the terrain plane",
        )
    }
}

impl PlantParameters {
    /// The dry inertia: all zero (off) or all > 0 obeying the triangle inequality.
    fn validate_mass_properties(&self) -> Result<(), ParameterError> {
        let i = self.inertia_dry_body_kgm2;
        if i == Vector3::zeros() {
            return Ok(());
        }
        for k in 0..3 {
            require(
                i[k] > 0.0,
                ("inertia_dry_body_kgm2", Some(k)),
                i[k],
                "all three dry moments must be > 0 (or all 0: inertia fixed)",
            )?;
            let others = i[(k + 1) % 3] + i[(k + 2) % 3];
            require(
                i[k] <= others * (1.0 + 1e-12),
                ("inertia_dry_body_kgm2", Some(k)),
                i[k],
                "exceeds the sum of the other two principal moments: no rigid body has it",
            )?;
        }
        Ok(())
    }

    /// The slosh tanks: the flat Moon and the sloshing masses below the dry mass, with slosh
    /// on.
    fn validate_slosh(&self, kind: TranslationModelKind) -> Result<(), ParameterError> {
        let s = &self.slosh;
        if !s.enabled {
            return Ok(());
        }
        if kind != TranslationModelKind::Flat {
            return Err(refuse(
                ("slosh.enabled", None),
                "true",
                "slosh is modelled over the flat Moon only (translation_model = 1)",
            ));
        }
        let slosh = super::slosh::Slosh::new(s, self.dry_mass_kg, self.m0_kg);
        for (k, p) in slosh.pendulums.iter().enumerate() {
            let delta = libm::hypot(s.delta0_m[2 * k], s.delta0_m[2 * k + 1]);
            require(
                delta < p.length_m,
                ("slosh.delta0_m", Some(2 * k)),
                delta,
                &format!(
                    "tank {}'s sloshing mass cannot start {delta} m across the thrust axis: its \
                     pendulum is {} m long",
                    k + 1,
                    p.length_m
                ),
            )?;
        }
        let sloshing = slosh.total_mass_kg;
        require(
            sloshing < self.dry_mass_kg,
            ("slosh.liquid_mass_kg", None),
            s.liquid_mass_kg[0],
            &format!(
                "the sloshing masses ({sloshing} kg) must stay below dry_mass = {} kg",
                self.dry_mass_kg
            ),
        )
    }
}

/// A product or sum of two parameters, and what it is.
struct Combined {
    what: &'static str,
    value: f64,
    /// The parameters it combines, with their values.
    of: [(Field, f64); 2],
}

impl PlantParameters {
    /// Products and sums of parameters the plant computes with stay finite, so any set that
    /// passes yields finite derived quantities and outputs; and the engines can fire. Called
    /// after every single parameter has passed its own check. An overflowing combination
    /// names the parameter furthest from its default (relative to it): the one at fault.
    fn validate_products(&self) -> Result<(), ParameterError> {
        let e = &self.engines;
        let total_max_n = f64::from(e.count) * e.max_thrust_per_engine_n;
        let point = &self.thrust_line.point_body_m;
        let lever_m = point.x.abs().max(point.y.abs()).max(point.z.abs());
        let mut combined = vec![
            Combined {
                what: "engine_count x engine_thrust_max",
                value: total_max_n,
                of: [
                    (
                        ("engines.max_thrust_per_engine_n", None),
                        e.max_thrust_per_engine_n,
                    ),
                    (("engines.count", None), f64::from(e.count)),
                ],
            },
            Combined {
                what: "|omega0_body|^2 x largest inertia (gyroscopic torque)",
                value: self.omega0_body_radps.norm_squared() * self.inertia_body_kgm2.max(),
                of: [
                    (("omega0_body_radps", None), self.omega0_body_radps.amax()),
                    (("inertia_body_kgm2", None), self.inertia_body_kgm2.max()),
                ],
            },
            Combined {
                what: "isp x g0 (exhaust velocity)",
                value: self.isp_s * self.g0_mps2,
                of: [
                    (("isp_s", None), self.isp_s),
                    (("g0_mps2", None), self.g0_mps2),
                ],
            },
            Combined {
                // The limit itself (two thrusters on each arm), which a master reads as
                // rcs_torque_limit: the product alone can be finite while twice it is not.
                what: "2 x rcs_thruster_force x rcs_moment_arm (torque limit)",
                value: self.rcs.torque_limit_nm(),
                of: [
                    (("rcs.thruster_force_n", None), self.rcs.thruster_force_n),
                    (("rcs.moment_arm_m", None), self.rcs.moment_arm_m),
                ],
            },
            Combined {
                what: "thrust_point_body x maximum thrust (engine torque)",
                value: 2.0 * lever_m * total_max_n,
                of: [
                    (("thrust_line.point_body_m", None), lever_m),
                    (
                        ("engines.max_thrust_per_engine_n", None),
                        e.max_thrust_per_engine_n,
                    ),
                ],
            },
        ];
        if self.translation_model_kind()? == TranslationModelKind::Spherical {
            let distance_m = self.moon_radius_m + self.r0_nue_m.norm();
            combined.extend([
                Combined {
                    what: "(moon_radius + |r0|)^2 (distance from the centre, squared)",
                    value: distance_m * distance_m,
                    of: [
                        (("moon_radius_m", None), self.moon_radius_m),
                        (("r0_nue_m", None), self.r0_nue_m.norm()),
                    ],
                },
                Combined {
                    what: "g x moon_radius^2 (gravitational parameter)",
                    value: self.gravity_mps2 * self.moon_radius_m * self.moon_radius_m,
                    of: [
                        (("gravity_mps2", None), self.gravity_mps2),
                        (("moon_radius_m", None), self.moon_radius_m),
                    ],
                },
                Combined {
                    what: "moon_rotation_rate^2 x distance (centrifugal acceleration)",
                    value: self.moon_rotation_rate_radps
                        * self.moon_rotation_rate_radps
                        * distance_m,
                    of: [
                        (
                            ("moon_rotation_rate_radps", None),
                            self.moon_rotation_rate_radps,
                        ),
                        (("moon_radius_m", None), self.moon_radius_m),
                    ],
                },
                Combined {
                    what: "2 moon_rotation_rate x |v0| (Coriolis acceleration)",
                    value: 2.0 * self.moon_rotation_rate_radps * self.v0_nue_mps.norm(),
                    of: [
                        (
                            ("moon_rotation_rate_radps", None),
                            self.moon_rotation_rate_radps,
                        ),
                        (("v0_nue_mps", None), self.v0_nue_mps.norm()),
                    ],
                },
            ]);
        }
        for c in &combined {
            if !c.value.is_finite() {
                let default = PlantParameters::default();
                let [a, b] = c.of;
                let far = |(field, v): (Field, f64)| (v / default.magnitude_of(field)).abs();
                let (field, value) = if far(a) >= far(b) { a } else { b };
                return Err(refuse(
                    field,
                    value,
                    format!("{} = {} overflows", c.what, c.value),
                ));
            }
        }
        // A lag's rate is (target - state) / time constant, with |target - state| up to the
        // maximum thrust (torque limit): a subnormal time constant overflows it.
        let lags = [
            (
                ("engines.time_constant_s", None),
                e.time_constant_s,
                total_max_n,
                "maximum thrust",
            ),
            (
                ("rcs.time_constant_s", None),
                self.rcs.time_constant_s,
                2.0 * self.rcs.torque_limit_nm(),
                "2 x RCS torque limit",
            ),
        ];
        for (field, tau, span, what) in lags {
            if tau > 0.0 && !(span / tau).is_finite() {
                return Err(refuse(
                    field,
                    tau,
                    format!("{what} / time constant (lag rate) = {span} / {tau:e} overflows"),
                ));
            }
        }
        // The mass flow per newton of thrust, 1 / (isp g0), overflows when the exhaust
        // velocity is below ~5.6e-309 m/s (a subnormal isp or g0 passes "positive"); the
        // factor smaller relative to its default is at fault.
        let exhaust_mps = self.isp_s * self.g0_mps2;
        if !(1.0 / exhaust_mps).is_finite() {
            let default = PlantParameters::default();
            let isp = (("isp_s", None), self.isp_s);
            let g0 = (("g0_mps2", None), self.g0_mps2);
            let near = |(field, v): (Field, f64)| (v / default.magnitude_of(field)).abs();
            let (field, value) = if near(isp) <= near(g0) { isp } else { g0 };
            return Err(refuse(
                field,
                value,
                format!(
                    "1 / (isp x g0) (mass flow per newton of thrust) = 1 / {exhaust_mps:e} overflows"
                ),
            ));
        }
        require(
            e.off_threshold_n < total_max_n,
            ("engines.off_threshold_n", None),
            e.off_threshold_n,
            &format!(
                "must be below the maximum total thrust {total_max_n} N: the engines would never fire"
            ),
        )
    }

    /// The default's magnitude of a combined parameter (1 where the default is 0).
    fn magnitude_of(&self, (field, _): Field) -> f64 {
        let value = match field {
            "engines.max_thrust_per_engine_n" => self.engines.max_thrust_per_engine_n,
            "engines.count" => f64::from(self.engines.count),
            "isp_s" => self.isp_s,
            "g0_mps2" => self.g0_mps2,
            "rcs.thruster_force_n" => self.rcs.thruster_force_n,
            "rcs.moment_arm_m" => self.rcs.moment_arm_m,
            "thrust_line.point_body_m" => self.thrust_line.point_body_m.abs().max(),
            "moon_radius_m" => self.moon_radius_m,
            "r0_nue_m" => self.r0_nue_m.norm(),
            "gravity_mps2" => self.gravity_mps2,
            "moon_rotation_rate_radps" => self.moon_rotation_rate_radps,
            "v0_nue_mps" => self.v0_nue_mps.norm(),
            _ => 1.0,
        };
        if value == 0.0 {
            1.0
        } else {
            value
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_valid() {
        assert_eq!(PlantParameters::default().check(), Ok(()));
    }

    /// The refused field, with its element if any (`inertia_body_kgm2[1]`).
    fn refused_name(p: PlantParameters) -> String {
        let e = p.check().expect_err("must be refused");
        match e.index {
            Some(k) => format!("{}[{k}]", e.field),
            None => e.field.to_string(),
        }
    }

    #[test]
    fn each_bad_value_is_refused_under_its_own_name() {
        let d = PlantParameters::default;
        assert_eq!(
            refused_name(PlantParameters { m0_kg: -1.0, ..d() }),
            "m0_kg"
        );
        assert_eq!(
            refused_name(PlantParameters {
                m0_kg: 600.0,
                ..d()
            }),
            "m0_kg"
        );
        assert_eq!(
            refused_name(PlantParameters {
                dry_mass_kg: 0.0,
                ..d()
            }),
            "dry_mass_kg"
        );
        let mut p = d();
        p.inertia_body_kgm2.y = -300.0;
        assert_eq!(refused_name(p), "inertia_body_kgm2[1]");
        let mut p = d();
        p.inertia_body_kgm2.z = 900.0;
        assert_eq!(refused_name(p), "inertia_body_kgm2[2]");
        let mut p = d();
        p.engines.min_thrust_per_engine_n = 900.0;
        assert_eq!(refused_name(p), "engines.min_thrust_per_engine_n");
        assert_eq!(
            refused_name(PlantParameters {
                integration_step_s: 0.0,
                ..d()
            }),
            "integration_step_s"
        );
        assert_eq!(
            refused_name(PlantParameters {
                integration_step_s: f64::NAN,
                ..d()
            }),
            "integration_step_s"
        );
        assert_eq!(
            refused_name(PlantParameters {
                translation_model: 3,
                ..d()
            }),
            "translation_model"
        );
        assert_eq!(
            refused_name(PlantParameters {
                q0_body_to_nue: [0.0; 4],
                ..d()
            }),
            "q0_body_to_nue"
        );
        assert_eq!(
            refused_name(PlantParameters {
                q0_body_to_nue: [1.0, 0.5, 0.0, 0.0],
                ..d()
            }),
            "q0_body_to_nue"
        );
        let mut p = d();
        p.r0_nue_m.y = 0.0;
        assert_eq!(refused_name(p), "r0_nue_m[1]");
        assert_eq!(
            refused_name(PlantParameters {
                site_latitude_rad: 1.5,
                ..d()
            }),
            "site_latitude_rad"
        );
    }

    #[test]
    fn nearly_unit_q0_is_normalised_silently_and_a_rounded_one_with_a_warning() {
        let tiny = PlantParameters {
            q0_body_to_nue: [1.0 + 5e-7, 0.0, 0.0, 0.0],
            ..Default::default()
        };
        let (q, warning) = tiny.validated_q0().unwrap();
        assert!((q.norm() - 1.0).abs() < 1e-15 && warning.is_none());
        // [cos 45 deg, 0, 0, sin 45 deg] printed with four digits.
        let c = (std::f64::consts::FRAC_1_SQRT_2 * 1e4).round() / 1e4;
        let rounded = PlantParameters {
            q0_body_to_nue: [c, 0.0, 0.0, c],
            ..Default::default()
        };
        let (q, warning) = rounded.validated_q0().unwrap();
        assert!((q.norm() - 1.0).abs() < 1e-15 && warning.is_some());
    }

    #[test]
    fn an_initial_body_rate_whose_gyroscopic_torque_overflows_is_refused() {
        // Found by the fuzzer: omega0_body[3] = -2.35e307 rad/s passed "finite", and
        // omega x (I omega) overflowed to a NaN derivative.
        for omega in [-2.35e307, 1e154, 1e153] {
            let p = PlantParameters {
                omega0_body_radps: Vector3::new(0.0, 0.0, omega),
                ..Default::default()
            };
            let e = p.validate().expect_err("overflowing rate");
            assert_eq!(e.field, "omega0_body_radps", "{e:?}");
            assert!(e.reason.contains("gyroscopic torque"), "{e:?}");
        }
        // A fast but representable spin passes.
        let p = PlantParameters {
            omega0_body_radps: Vector3::new(0.0, 0.0, 1e100),
            ..Default::default()
        };
        assert_eq!(p.validate(), Ok(()));
    }

    #[test]
    fn a_time_constant_whose_lag_rate_overflows_is_refused() {
        // Found by the fuzzer: engine_time_constant = 6e-315 s passed "min 0", and the
        // thrust lag's rate (1600 N - 0) / 6e-315 s was infinite.
        let engine = PlantParameters {
            engines: Engines {
                time_constant_s: 5.991517526e-315,
                ..PlantParameters::default().engines
            },
            ..Default::default()
        };
        let rcs = PlantParameters {
            rcs: Rcs {
                time_constant_s: 1e-320,
                ..PlantParameters::default().rcs
            },
            ..Default::default()
        };
        for (p, field) in [
            (engine, "engines.time_constant_s"),
            (rcs, "rcs.time_constant_s"),
        ] {
            let e = p.validate().expect_err(field);
            assert_eq!(e.field, field, "{e:?}");
            assert!(e.reason.contains("lag rate"), "{e:?}");
        }
    }

    #[test]
    fn an_exhaust_velocity_whose_reciprocal_overflows_is_refused_naming_the_tiny_factor() {
        // Found by the fuzzer: isp = 1.6e-318 s passed "positive", and the mass flow of a
        // zero thrust became 0 x inf = NaN.
        for (params, field) in [
            (
                PlantParameters {
                    isp_s: 1.59747e-318,
                    ..Default::default()
                },
                "isp_s",
            ),
            (
                PlantParameters {
                    g0_mps2: 1e-320,
                    ..Default::default()
                },
                "g0_mps2",
            ),
        ] {
            let e = params.validate().expect_err(field);
            assert_eq!(e.field, field, "{e:?}");
            assert!(e.reason.contains("overflows"), "{e:?}");
        }
    }

    #[test]
    fn overflowing_products_are_refused_naming_the_parameter_at_fault() {
        let d = PlantParameters::default;
        let spherical = || PlantParameters {
            translation_model: TranslationModelKind::Spherical as i32,
            ..d()
        };
        let cases = [
            (
                PlantParameters {
                    isp_s: 1e308,
                    ..d()
                },
                "isp_s",
            ),
            (
                PlantParameters {
                    g0_mps2: 1e307,
                    ..d()
                },
                "g0_mps2",
            ),
            (
                PlantParameters {
                    rcs: Rcs {
                        thruster_force_n: 1e308,
                        moment_arm_m: 4.0,
                        ..d().rcs
                    },
                    ..d()
                },
                "rcs.thruster_force_n",
            ),
            (
                PlantParameters {
                    rcs: Rcs {
                        moment_arm_m: 1e307,
                        ..d().rcs
                    },
                    ..d()
                },
                "rcs.moment_arm_m",
            ),
            (
                PlantParameters {
                    thrust_line: ThrustLine {
                        point_body_m: Vector3::new(0.0, -1e306, 0.0),
                        ..d().thrust_line
                    },
                    ..d()
                },
                "thrust_line.point_body_m",
            ),
            (
                PlantParameters {
                    engines: Engines {
                        max_thrust_per_engine_n: 1e308,
                        ..d().engines
                    },
                    ..d()
                },
                "engines.max_thrust_per_engine_n",
            ),
            (
                PlantParameters {
                    moon_radius_m: 1e160,
                    ..spherical()
                },
                "moon_radius_m",
            ),
            (
                PlantParameters {
                    r0_nue_m: Vector3::new(0.0, 1e160, 0.0),
                    ..spherical()
                },
                "r0_nue_m",
            ),
            (
                PlantParameters {
                    moon_rotation_rate_radps: 1e160,
                    ..spherical()
                },
                "moon_rotation_rate_radps",
            ),
        ];
        for (p, field) in cases {
            let e = p.validate().expect_err(field);
            assert_eq!(e.field, field, "{e:?}");
            assert!(e.reason.contains("overflows"), "{e:?}");
        }
        // The same values in the flat model, which never squares the radius, pass.
        assert_eq!(
            PlantParameters {
                moon_radius_m: 1e160,
                ..d()
            }
            .validate(),
            Ok(())
        );
    }

    #[test]
    fn an_engine_off_threshold_at_or_above_the_maximum_thrust_is_refused() {
        let d = PlantParameters::default;
        let max_total = 2.0 * 800.0;
        for (threshold, ok) in [(max_total - 1.0, true), (max_total, false), (1e9, false)] {
            let p = PlantParameters {
                engines: Engines {
                    off_threshold_n: threshold,
                    ..d().engines
                },
                ..d()
            };
            match p.validate() {
                Ok(()) => assert!(ok, "{threshold} accepted"),
                Err(e) => {
                    assert!(!ok, "{threshold}: {e:?}");
                    assert_eq!(e.field, "engines.off_threshold_n");
                }
            }
        }
    }
}
