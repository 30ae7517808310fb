//! Dispersions: the ranges a campaign draws from, one run's draw (a pure function of its run
//! seed), and how a draw is applied on top of the scenario's nominal plant.
//!
//! Every quantity is drawn uniformly: a symmetric quantity `x` in `[-a, a]` as
//! `a (2u - 1)`, a magnitude that spreads over a disc or a cone (horizontal position, extra
//! tilt, thrust misalignment) as `a sqrt(u)` with a uniform azimuth, so it is uniform over
//! the disc's area (for small cones, over the solid angle). `u` is one
//! `rng.gen::<f64>()` (53 random bits, in `[0, 1)`). Every draw consumes exactly one `u`,
//! also when its range is zero, so setting one range to zero leaves all other draws of
//! every run unchanged.
use crate::attitude::{self, Quat};
use cosim::system::{ParamValue, SystemDescription};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::f64::consts::TAU;

/// Dispersion ranges, in the units of their names. The defaults are a modest but
/// non-trivial set: navigation-grade initial-state errors at the start of a terminal
/// descent, a few per cent of mass and ten per cent of inertia (the GNC keeps the nominal
/// inertia for its gains, so this exercises the gain margin), and a tenth of a degree of engine
/// alignment tolerance. They describe what a real terminal descent sees, not what the current
/// LanderGnc passes: from the paper scenario's tilted start it does not hold even a 1 m
/// lateral offset (see `a_small_campaign_shows_the_papers_trend` in the tests).
#[derive(Debug, Clone, PartialEq, clap::Args, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DispersionRanges {
    /// Initial horizontal position: uniform over a disc of this radius (m).
    #[arg(long = "disp-horizontal-m", default_value_t = Self::DEFAULT.horizontal_position_m, value_name = "M", allow_negative_numbers = true)]
    pub horizontal_position_m: f64,
    /// Initial altitude: uniform in +- this (m).
    #[arg(long = "disp-vertical-m", default_value_t = Self::DEFAULT.vertical_position_m, value_name = "M", allow_negative_numbers = true)]
    pub vertical_position_m: f64,
    /// Initial velocity: each NUE component uniform in +- this (m/s).
    #[arg(long = "disp-velocity-mps", default_value_t = Self::DEFAULT.velocity_mps, value_name = "M/S", allow_negative_numbers = true)]
    pub velocity_mps: f64,
    /// Extra tilt of the start attitude about a uniformly random horizontal axis: uniform
    /// over the cone of this half-angle (deg).
    #[arg(long = "disp-tilt-deg", default_value_t = Self::DEFAULT.tilt_deg, value_name = "DEG", allow_negative_numbers = true)]
    pub tilt_deg: f64,
    /// Extra rotation of the start attitude about the thrust axis: uniform in +- this (deg).
    #[arg(long = "disp-roll-deg", default_value_t = Self::DEFAULT.roll_deg, value_name = "DEG", allow_negative_numbers = true)]
    pub roll_deg: f64,
    /// Initial body rate: each body component uniform in +- this (deg/s).
    #[arg(long = "disp-rate-degps", default_value_t = Self::DEFAULT.rate_degps, value_name = "DEG/S", allow_negative_numbers = true)]
    pub rate_degps: f64,
    /// Initial mass m0: scaled by 1 + uniform in +- this fraction.
    #[arg(
        long = "disp-mass-frac",
        default_value_t = Self::DEFAULT.mass_fraction,
        value_name = "FRACTION",
        allow_negative_numbers = true
    )]
    pub mass_fraction: f64,
    /// Plant principal inertia: each axis scaled by 1 + uniform in +- this fraction (the GNC
    /// keeps the nominal inertia for its gains).
    #[arg(
        long = "disp-inertia-frac",
        default_value_t = Self::DEFAULT.inertia_fraction,
        value_name = "FRACTION",
        allow_negative_numbers = true
    )]
    pub inertia_fraction: f64,
    /// Thrust misalignment from body +y: uniform over the cone of this half-angle, uniform
    /// azimuth (deg).
    #[arg(
        long = "disp-misalignment-deg",
        default_value_t = Self::DEFAULT.misalignment_deg,
        value_name = "DEG",
        allow_negative_numbers = true
    )]
    pub misalignment_deg: f64,
    /// Main-engine thrust level (the plant's engine_thrust_scale, unknown to the GNC):
    /// scaled by 1 + uniform in +- this fraction. 0 (off) unless asked: an off-nominal case.
    #[arg(
        long = "disp-thrust-frac",
        default_value_t = Self::DEFAULT.thrust_level_fraction,
        value_name = "FRACTION",
        allow_negative_numbers = true
    )]
    #[serde(default)]
    pub thrust_level_fraction: f64,
}

impl Default for DispersionRanges {
    fn default() -> Self {
        Self::DEFAULT
    }
}

impl DispersionRanges {
    /// The defaults of the command line (one place for both): errors of the state the descent
    /// starts from, at the level a navigation filter and a previous guidance phase hand over
    /// (metres, decimetres per second, a degree), plus model uncertainty (mass, inertia,
    /// misalignment). Larger position and velocity errors are legal but dominate the
    /// horizontal-deviation metric: the 130 s cubic descent spreads a velocity error at its
    /// start over the whole time-to-go (roughly 0.25 v0 tgo of excursion), whatever the law.
    pub const DEFAULT: Self = Self {
        horizontal_position_m: 2.0,
        vertical_position_m: 2.0,
        velocity_mps: 0.1,
        tilt_deg: 1.0,
        roll_deg: 2.0,
        rate_degps: 0.2,
        mass_fraction: 0.02,
        inertia_fraction: 0.10,
        misalignment_deg: 0.1,
        thrust_level_fraction: 0.0,
    };

    /// No dispersion at all: every run flies the nominal scenario.
    pub fn none() -> Self {
        Self {
            horizontal_position_m: 0.0,
            vertical_position_m: 0.0,
            velocity_mps: 0.0,
            tilt_deg: 0.0,
            roll_deg: 0.0,
            rate_degps: 0.0,
            mass_fraction: 0.0,
            inertia_fraction: 0.0,
            misalignment_deg: 0.0,
            thrust_level_fraction: 0.0,
        }
    }

    /// Refuses negative, non-finite and physically meaningless ranges, naming the option.
    pub fn validate(&self) -> Result<(), String> {
        let checks: [(&str, f64, f64); 10] = [
            (
                "--disp-horizontal-m",
                self.horizontal_position_m,
                f64::INFINITY,
            ),
            ("--disp-vertical-m", self.vertical_position_m, f64::INFINITY),
            ("--disp-velocity-mps", self.velocity_mps, f64::INFINITY),
            ("--disp-tilt-deg", self.tilt_deg, 90.0),
            ("--disp-roll-deg", self.roll_deg, 180.0),
            ("--disp-rate-degps", self.rate_degps, f64::INFINITY),
            // A scale of zero or less would make a mass or an inertia non-positive.
            ("--disp-mass-frac", self.mass_fraction, 0.5),
            ("--disp-inertia-frac", self.inertia_fraction, 0.5),
            ("--disp-misalignment-deg", self.misalignment_deg, 90.0),
            // The plant accepts a thrust level in (0, 2].
            ("--disp-thrust-frac", self.thrust_level_fraction, 0.5),
        ];
        let problems: Vec<String> = checks
            .iter()
            .filter(|(_, value, max)| !(value.is_finite() && (0.0..=*max).contains(value)))
            .map(|(option, value, max)| {
                if max.is_finite() {
                    format!("{option} {value}: must be in [0, {max}]")
                } else {
                    format!("{option} {value}: must be a finite number >= 0")
                }
            })
            .collect();
        if problems.is_empty() {
            Ok(())
        } else {
            Err(problems.join("; "))
        }
    }
}

/// One run's draw. Deltas are added to the scenario's nominal start, scales multiply its
/// nominal value, the extra attitude is applied as [`Nominal::apply`] describes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dispersion {
    pub delta_r0_nue_m: [f64; 3],
    pub delta_v0_nue_mps: [f64; 3],
    /// Extra tilt angle and the azimuth of its horizontal axis (from North towards East).
    pub tilt_rad: f64,
    pub tilt_axis_azimuth_rad: f64,
    pub roll_about_thrust_rad: f64,
    pub delta_omega0_body_radps: [f64; 3],
    pub m0_scale: f64,
    pub inertia_scale: [f64; 3],
    pub thrust_misalignment_rad: f64,
    pub thrust_misalignment_azimuth_rad: f64,
    /// Main-engine thrust level over nominal.
    pub thrust_scale: f64,
}

/// Values of a draw in the manifest.
pub const FIELD_COUNT: usize = 22;

/// Column names of a draw in the manifest, in [`Dispersion::to_fields`] order.
pub const FIELD_NAMES: [&str; FIELD_COUNT] = [
    "delta_r0_nue_m[1]",
    "delta_r0_nue_m[2]",
    "delta_r0_nue_m[3]",
    "delta_v0_nue_mps[1]",
    "delta_v0_nue_mps[2]",
    "delta_v0_nue_mps[3]",
    "tilt_rad",
    "tilt_axis_azimuth_rad",
    "roll_about_thrust_rad",
    "delta_omega0_body_radps[1]",
    "delta_omega0_body_radps[2]",
    "delta_omega0_body_radps[3]",
    "m0_scale",
    "inertia_scale[1]",
    "inertia_scale[2]",
    "inertia_scale[3]",
    "thrust_misalignment_rad",
    "thrust_misalignment_azimuth_rad",
    "thrust_scale",
    // Derived, not drawn: the horizontal offset's polar form is already in [1] and [3].
    "delta_r0_horizontal_m",
    "tilt_deg",
    "thrust_misalignment_deg",
];

/// The run's generator, one `u` per draw.
struct Draws(ChaCha8Rng);

impl Draws {
    fn unit(&mut self) -> f64 {
        self.0.gen::<f64>()
    }
    /// Uniform in `[-half_width, half_width)`.
    fn symmetric(&mut self, half_width: f64) -> f64 {
        half_width * (2.0 * self.unit() - 1.0)
    }
    /// Uniform over the area of a disc of `radius`: (radius, azimuth in [0, 2 pi)).
    fn polar(&mut self, radius: f64) -> (f64, f64) {
        let r = radius * self.unit().sqrt();
        (r, TAU * self.unit())
    }
}

impl Dispersion {
    /// The draw of the run seeded with `run_seed`. Order of the draws (one `u` each):
    /// horizontal position radius, its azimuth, vertical position; velocity N, U, E; tilt
    /// angle, tilt-axis azimuth; roll about the thrust axis; body rate x, y, z; mass;
    /// inertia x, y, z; misalignment angle, misalignment azimuth; thrust level (last, so the
    /// draws before it are those of a campaign without it).
    pub fn draw(run_seed: u64, ranges: &DispersionRanges) -> Self {
        let mut d = Draws(ChaCha8Rng::seed_from_u64(run_seed));
        let (r_h, az_h) = d.polar(ranges.horizontal_position_m);
        let delta_r0_nue_m = [
            r_h * az_h.cos(),
            d.symmetric(ranges.vertical_position_m),
            r_h * az_h.sin(),
        ];
        let delta_v0_nue_mps = [(); 3].map(|_| d.symmetric(ranges.velocity_mps));
        let (tilt_rad, tilt_axis_azimuth_rad) = d.polar(ranges.tilt_deg.to_radians());
        let roll_about_thrust_rad = d.symmetric(ranges.roll_deg.to_radians());
        let delta_omega0_body_radps = [(); 3].map(|_| d.symmetric(ranges.rate_degps.to_radians()));
        let m0_scale = 1.0 + d.symmetric(ranges.mass_fraction);
        let inertia_scale = [(); 3].map(|_| 1.0 + d.symmetric(ranges.inertia_fraction));
        let (thrust_misalignment_rad, thrust_misalignment_azimuth_rad) =
            d.polar(ranges.misalignment_deg.to_radians());
        let thrust_scale = 1.0 + d.symmetric(ranges.thrust_level_fraction);
        Self {
            delta_r0_nue_m,
            delta_v0_nue_mps,
            tilt_rad,
            tilt_axis_azimuth_rad,
            roll_about_thrust_rad,
            delta_omega0_body_radps,
            m0_scale,
            inertia_scale,
            thrust_misalignment_rad,
            thrust_misalignment_azimuth_rad,
            thrust_scale,
        }
    }

    /// The manifest's values, in [`FIELD_NAMES`] order.
    pub fn to_fields(&self) -> [f64; FIELD_COUNT] {
        let [rn, ru, re] = self.delta_r0_nue_m;
        let [vn, vu, ve] = self.delta_v0_nue_mps;
        let [wx, wy, wz] = self.delta_omega0_body_radps;
        let [ix, iy, iz] = self.inertia_scale;
        [
            rn,
            ru,
            re,
            vn,
            vu,
            ve,
            self.tilt_rad,
            self.tilt_axis_azimuth_rad,
            self.roll_about_thrust_rad,
            wx,
            wy,
            wz,
            self.m0_scale,
            ix,
            iy,
            iz,
            self.thrust_misalignment_rad,
            self.thrust_misalignment_azimuth_rad,
            self.thrust_scale,
            rn.hypot(re),
            self.tilt_rad.to_degrees(),
            self.thrust_misalignment_rad.to_degrees(),
        ]
    }

    /// Inverse of [`Dispersion::to_fields`] (the derived fields are ignored).
    pub fn from_fields(f: &[f64; FIELD_COUNT]) -> Self {
        Self {
            delta_r0_nue_m: [f[0], f[1], f[2]],
            delta_v0_nue_mps: [f[3], f[4], f[5]],
            tilt_rad: f[6],
            tilt_axis_azimuth_rad: f[7],
            roll_about_thrust_rad: f[8],
            delta_omega0_body_radps: [f[9], f[10], f[11]],
            m0_scale: f[12],
            inertia_scale: [f[13], f[14], f[15]],
            thrust_misalignment_rad: f[16],
            thrust_misalignment_azimuth_rad: f[17],
            thrust_scale: f[18],
        }
    }
}

/// The plant's nominal start and mass properties: the scenario's values, else the FMU's
/// start values.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Nominal {
    pub r0_nue_m: [f64; 3],
    pub v0_nue_mps: [f64; 3],
    pub q0_body_to_nue: Quat,
    pub omega0_body_radps: [f64; 3],
    pub m0_kg: f64,
    pub inertia_body_kgm2: [f64; 3],
    /// The plant's engine_thrust_scale; `None` for a plant without one (then no thrust level
    /// can be dispersed).
    pub thrust_scale: Option<f64>,
}

impl Nominal {
    /// Reads the nominal values of `plant` from the scenario, falling back to the
    /// model description's start values (`start_of`).
    pub fn from_scenario(
        system: &SystemDescription,
        plant: &str,
        start_of: impl Fn(&str) -> Option<f64>,
    ) -> Result<Self, String> {
        let desc = system
            .instance(plant)
            .ok_or_else(|| format!("scenario '{}' has no instance '{plant}'", system.name))?;
        let value = |name: &str| -> Result<f64, String> {
            match desc.parameters.iter().find(|(n, _)| n == name) {
                Some((_, ParamValue::Real(x))) => Ok(*x),
                Some((_, ParamValue::Integer(i))) => Ok(*i as f64),
                Some((_, other)) => Err(format!("{plant}.{name} = {other:?} is not a number")),
                None => start_of(name)
                    .ok_or_else(|| format!("{plant}.{name} has no value and no start value")),
            }
        };
        let vector = |name: &str| -> Result<[f64; 3], String> {
            Ok([
                value(&format!("{name}[1]"))?,
                value(&format!("{name}[2]"))?,
                value(&format!("{name}[3]"))?,
            ])
        };
        Ok(Self {
            r0_nue_m: vector("r0_nue")?,
            v0_nue_mps: vector("v0_nue")?,
            q0_body_to_nue: [
                value("q0_body_to_nue[1]")?,
                value("q0_body_to_nue[2]")?,
                value("q0_body_to_nue[3]")?,
                value("q0_body_to_nue[4]")?,
            ],
            omega0_body_radps: vector("omega0_body")?,
            m0_kg: value("m0")?,
            inertia_body_kgm2: vector("inertia_body")?,
            thrust_scale: value("engine_thrust_scale").ok(),
        })
    }

    /// The start attitude of a draw: the nominal attitude turned about the body thrust axis
    /// (+y) by the roll, then tilted about the horizontal NUE axis at the drawn azimuth:
    /// `q_tilt ⊗ q0 ⊗ q_roll`. The roll leaves the thrust axis where the scenario put it; the
    /// tilt moves it by at most the tilt angle.
    pub fn start_attitude(&self, draw: &Dispersion) -> Quat {
        let (sin_az, cos_az) = draw.tilt_axis_azimuth_rad.sin_cos();
        let tilt = attitude::from_axis_angle([cos_az, 0.0, sin_az], draw.tilt_rad);
        let roll = attitude::from_axis_angle([0.0, 1.0, 0.0], draw.roll_about_thrust_rad);
        attitude::multiply(tilt, attitude::multiply(self.q0_body_to_nue, roll))
    }

    /// The plant parameters of a draw (name, value). The misalignment replaces any the
    /// scenario sets: an angle and an azimuth do not add.
    pub fn apply(&self, draw: &Dispersion) -> Vec<(&'static str, f64)> {
        const R0: [&str; 3] = ["r0_nue[1]", "r0_nue[2]", "r0_nue[3]"];
        const V0: [&str; 3] = ["v0_nue[1]", "v0_nue[2]", "v0_nue[3]"];
        const Q0: [&str; 4] = [
            "q0_body_to_nue[1]",
            "q0_body_to_nue[2]",
            "q0_body_to_nue[3]",
            "q0_body_to_nue[4]",
        ];
        const OMEGA0: [&str; 3] = ["omega0_body[1]", "omega0_body[2]", "omega0_body[3]"];
        const INERTIA: [&str; 3] = ["inertia_body[1]", "inertia_body[2]", "inertia_body[3]"];
        let mut values = Vec::with_capacity(19);
        for i in 0..3 {
            values.push((R0[i], self.r0_nue_m[i] + draw.delta_r0_nue_m[i]));
            values.push((V0[i], self.v0_nue_mps[i] + draw.delta_v0_nue_mps[i]));
            values.push((
                OMEGA0[i],
                self.omega0_body_radps[i] + draw.delta_omega0_body_radps[i],
            ));
            values.push((
                INERTIA[i],
                self.inertia_body_kgm2[i] * draw.inertia_scale[i],
            ));
        }
        values.extend(Q0.into_iter().zip(self.start_attitude(draw)));
        values.push(("m0", self.m0_kg * draw.m0_scale));
        values.push(("thrust_misalignment", draw.thrust_misalignment_rad));
        values.push((
            "thrust_misalignment_azimuth",
            draw.thrust_misalignment_azimuth_rad,
        ));
        if let Some(nominal) = self.thrust_scale {
            values.push(("engine_thrust_scale", nominal * draw.thrust_scale));
        }
        values
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// atan2(|a x b|, a . b): accurate also for nearly parallel vectors, unlike acos.
    fn angle_between(a: [f64; 3], b: [f64; 3]) -> f64 {
        let dot: f64 = a.iter().zip(&b).map(|(x, y)| x * y).sum();
        let cross = [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ];
        cross.iter().map(|c| c * c).sum::<f64>().sqrt().atan2(dot)
    }

    /// The paper scenario's start: 15 deg toward North about East.
    fn nominal() -> Nominal {
        let half = (-15f64).to_radians() / 2.0;
        Nominal {
            r0_nue_m: [0.0, 800.0, 0.0],
            v0_nue_mps: [0.0; 3],
            q0_body_to_nue: [half.cos(), 0.0, 0.0, half.sin()],
            omega0_body_radps: [0.0; 3],
            m0_kg: 900.0,
            inertia_body_kgm2: [400.0, 300.0, 450.0],
            thrust_scale: Some(1.0),
        }
    }

    #[test]
    fn the_draw_is_a_function_of_the_seed_alone() {
        let ranges = DispersionRanges::default();
        assert_eq!(Dispersion::draw(11, &ranges), Dispersion::draw(11, &ranges));
        assert_ne!(Dispersion::draw(11, &ranges), Dispersion::draw(12, &ranges));
    }

    #[test]
    fn zeroing_one_range_leaves_every_other_draw_unchanged() {
        let all = DispersionRanges::default();
        let mut no_mass = all.clone();
        no_mass.mass_fraction = 0.0;
        for seed in 0..50 {
            let a = Dispersion::draw(seed, &all).to_fields();
            let b = Dispersion::draw(seed, &no_mass).to_fields();
            for (k, name) in FIELD_NAMES.iter().enumerate() {
                if *name == "m0_scale" {
                    assert_eq!(b[k], 1.0);
                } else {
                    assert_eq!(a[k].to_bits(), b[k].to_bits(), "{name}");
                }
            }
        }
    }

    #[test]
    fn no_dispersion_gives_the_nominal_plant() {
        let n = nominal();
        let draw = Dispersion::draw(3, &DispersionRanges::none());
        let q = n.start_attitude(&draw);
        for (a, b) in q.iter().zip(&n.q0_body_to_nue) {
            assert!((a - b).abs() < 1e-15);
        }
        let values = n.apply(&draw);
        let get = |name: &str| values.iter().find(|(n, _)| *n == name).unwrap().1;
        assert_eq!(get("r0_nue[2]"), 800.0);
        assert_eq!(get("m0"), 900.0);
        assert_eq!(get("inertia_body[3]"), 450.0);
        assert_eq!(get("thrust_misalignment"), 0.0);
    }

    #[test]
    fn the_roll_keeps_the_thrust_axis_and_the_tilt_moves_it_by_the_tilt_angle() {
        let n = nominal();
        let thrust = |q: Quat| attitude::rotate(q, [0.0, 1.0, 0.0]);
        let nominal_axis = thrust(n.q0_body_to_nue);
        let mut roll_only = DispersionRanges::none();
        roll_only.roll_deg = 90.0;
        let mut tilt_only = DispersionRanges::none();
        tilt_only.tilt_deg = 10.0;
        for seed in 0..200 {
            let draw = Dispersion::draw(seed, &roll_only);
            let q = n.start_attitude(&draw);
            assert!(angle_between(thrust(q), nominal_axis) < 1e-12);
            // The pitch axis (body z) turns about the thrust axis by the roll angle.
            let pitch = |q: Quat| attitude::rotate(q, [0.0, 0.0, 1.0]);
            let turned = angle_between(pitch(q), pitch(n.q0_body_to_nue));
            assert!((turned - draw.roll_about_thrust_rad.abs()).abs() < 1e-9);

            let draw = Dispersion::draw(seed, &tilt_only);
            let axis = thrust(n.start_attitude(&draw));
            // Tilting about a horizontal axis moves the 15-deg-tilted thrust axis by at most
            // the tilt angle (exactly it only when the axes are perpendicular).
            assert!(angle_between(axis, nominal_axis) <= draw.tilt_rad + 1e-12);
            let vertical_change = angle_between(axis, [0.0, 1.0, 0.0]) - 15f64.to_radians();
            assert!(vertical_change.abs() <= draw.tilt_rad + 1e-12);
        }
    }

    #[test]
    fn out_of_range_options_are_refused_by_name() {
        let r = DispersionRanges {
            tilt_deg: f64::NAN,
            ..Default::default()
        };
        assert!(r.validate().unwrap_err().contains("--disp-tilt-deg"));
        let r = DispersionRanges {
            inertia_fraction: 1.0,
            ..Default::default()
        };
        assert!(r.validate().unwrap_err().contains("--disp-inertia-frac"));
        assert!(DispersionRanges::default().validate().is_ok());
    }
}
