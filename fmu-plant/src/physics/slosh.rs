//! Propellant slosh: the first lateral sloshing mode of each upright circular cylindrical
//! tank as a spherical pendulum (the equivalent mechanical model), its length, mass and
//! hinge following the fill level as the propellant burns. Optional
//! (`SloshParameters::enabled`, off by default); off, the plant builds no [`Slosh`] and
//! integrates exactly as without it. The pendulums' motion together with the rigid body's
//! is `slosh_dynamics`; docs/plant-slosh.md derives both.
//!
//! Equivalent mechanical model of a flat-bottomed upright cylinder of radius `R` filled to
//! depth `h` with liquid of mass `m_F`, `xi = 1.8412` (first root of `J1'`),
//! `lambda = xi h / R` (Abramson, NASA SP-106, 1966, ch. 6 and table 6.1; Dodge, "The New
//! Dynamic Behavior of Liquids in Moving Containers", SwRI 2000, ch. 3):
//! * pendulum length `L = R / (xi tanh(lambda))`, so `omega^2 = g_eff / L`;
//! * sloshing mass `m_1 = m_F 2 tanh(lambda) / (xi (xi^2 - 1) h / R)`;
//! * hinge `h - (R / xi) (cosh(lambda) - 2) / sinh(lambda)` above the tank bottom: the
//!   height at which the first mode's wall and bottom pressures act (their moment about
//!   the bottom over their lateral force); the sloshing mass hangs `L` below it, at Dodge's
//!   `h - (2 R / xi) tanh(lambda / 2)`.
use nalgebra::{Vector2, Vector3};
use serde::{Deserialize, Serialize};

pub const TANK_COUNT: usize = 2;

/// First root of the derivative of the Bessel function J1.
pub const XI_1: f64 = 1.841_183_8;

/// Shallowest depth the equivalent model is evaluated at, as a fraction of the radius: its
/// length grows as `R^2 / (xi^2 h)` without bound towards an empty tank, while the mass
/// it carries (the remaining liquid) vanishes.
pub const MIN_DEPTH_FRACTION: f64 = 0.05;

/// Angle from straight down the thrust axis beyond which the pendulum swings outside the
/// range of the linear sloshing theory its length and mass come from: 30 deg.
pub const LINEAR_RANGE_RAD: f64 = std::f64::consts::FRAC_PI_6;

/// The slosh model as the user sets it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SloshParameters {
    pub enabled: bool,
    /// Radius of each (upright cylindrical) tank, m.
    pub tank_radius_m: [f64; TANK_COUNT],
    /// Liquid depth in each tank at the initial mass `m0`, m.
    pub fill_height_m: [f64; TANK_COUNT],
    /// Liquid mass in each tank at the initial mass `m0`, kg (0: no slosh in that tank).
    pub liquid_mass_kg: [f64; TANK_COUNT],
    /// Hinge of each pendulum at the initial fill, relative to the (rigid part's) centre of
    /// mass, body axes, m; it places the tank, whose bottom lies below it on body -y.
    pub hinge_body_m: [f64; 3 * TANK_COUNT],
    /// Damping ratio of the sloshing mode.
    pub damping_ratio: f64,
    /// Initial displacement of each sloshing mass (tank k: body x, body z at 2k, 2k + 1), m.
    pub delta0_m: [f64; 2 * TANK_COUNT],
}

/// The default tank layout: the bottoms of the two tanks at the centre of mass's height,
/// 0.6 m either side of it on body x; the hinges of their initial fill above.
const DEFAULT_TANK_OFFSET_M: f64 = 0.6;

impl Default for SloshParameters {
    fn default() -> Self {
        let (radius, depth) = (0.4, 0.4);
        let up = hinge_height_m(radius, depth);
        Self {
            enabled: false,
            tank_radius_m: [radius; TANK_COUNT],
            fill_height_m: [depth; TANK_COUNT],
            // The default 300 kg of propellant (m0 - dry_mass) in two tanks.
            liquid_mass_kg: [150.0; TANK_COUNT],
            hinge_body_m: [
                DEFAULT_TANK_OFFSET_M,
                up,
                0.0,
                -DEFAULT_TANK_OFFSET_M,
                up,
                0.0,
            ],
            damping_ratio: 0.005,
            delta0_m: [0.0; 2 * TANK_COUNT],
        }
    }
}

/// One tank's pendulum at a fill level.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Pendulum {
    pub length_m: f64,
    pub mass_kg: f64,
    pub hinge_body_m: Vector3<f64>,
}

impl Pendulum {
    /// Whether the pendulum takes part in the motion (a tank with liquid in it).
    pub fn is_active(&self) -> bool {
        self.mass_kg > 0.0 && self.length_m.is_finite()
    }
}

/// Pendulum length and sloshing mass of a cylindrical tank (radius, depth, liquid mass).
pub fn pendulum(radius_m: f64, depth_m: f64, liquid_kg: f64) -> (f64, f64) {
    let t = libm::tanh(XI_1 * depth_m / radius_m);
    let length = radius_m / (XI_1 * t);
    let mass = liquid_kg * 2.0 * t / (XI_1 * (XI_1 * XI_1 - 1.0) * depth_m / radius_m);
    (length, mass)
}

/// Height of the pendulum's hinge above the tank bottom, m.
pub fn hinge_height_m(radius_m: f64, depth_m: f64) -> f64 {
    let lambda = XI_1 * depth_m / radius_m;
    depth_m - radius_m / XI_1 * (libm::cosh(lambda) - 2.0) / libm::sinh(lambda)
}

/// One tank as built: its geometry and its load at the initial mass.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Tank {
    pub radius_m: f64,
    pub full_depth_m: f64,
    pub full_liquid_kg: f64,
    /// Centre of the tank bottom relative to the centre of mass, body axes, m.
    pub bottom_body_m: Vector3<f64>,
}

impl Tank {
    /// The pendulum of this tank holding `fraction` of its initial liquid (a flat bottom and
    /// straight walls: the depth goes with the mass).
    pub fn pendulum_at(&self, fraction: f64) -> Pendulum {
        let liquid_kg = self.full_liquid_kg * fraction;
        let depth_m = (self.full_depth_m * fraction).max(MIN_DEPTH_FRACTION * self.radius_m);
        let (length_m, mass_kg) = pendulum(self.radius_m, depth_m, liquid_kg);
        Pendulum {
            length_m,
            mass_kg,
            hinge_body_m: self.bottom_body_m
                + Vector3::new(0.0, hinge_height_m(self.radius_m, depth_m), 0.0),
        }
    }
}

/// The validated slosh model.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Slosh {
    pub tanks: [Tank; TANK_COUNT],
    /// The pendulums at the initial fill.
    pub pendulums: [Pendulum; TANK_COUNT],
    pub damping_ratio: f64,
    /// The sloshing masses at the initial fill (the most there is), kg.
    pub total_mass_kg: f64,
    pub dry_mass_kg: f64,
    /// `m0 - dry_mass`, kg: the propellant whose remaining fraction sets the fill.
    pub propellant_kg: f64,
}

/// The pendulum states, tank k at `6k..6k + 6`: the direction from its hinge to its mass
/// (a unit vector, body axes; straight down the thrust axis at rest), then that direction's
/// rate (1/s). A direction rather than two angles: the pendulum has no chart edge, and a
/// tumbling lander may swing the liquid anywhere.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SloshState(pub [f64; 6 * TANK_COUNT]);

impl Default for SloshState {
    fn default() -> Self {
        Self([0.0; 6 * TANK_COUNT])
    }
}

impl SloshState {
    pub fn direction(&self, k: usize) -> Vector3<f64> {
        Vector3::from_column_slice(&self.0[6 * k..6 * k + 3])
    }

    pub fn direction_rate(&self, k: usize) -> Vector3<f64> {
        Vector3::from_column_slice(&self.0[6 * k + 3..6 * k + 6])
    }

    /// Tank k's sloshing mass across the thrust axis from its hinge (body x, z), m.
    pub fn displacement_m(&self, k: usize, length_m: f64) -> Vector2<f64> {
        Vector2::new(self.0[6 * k], self.0[6 * k + 2]) * length_m
    }

    pub fn add_scaled(&self, h: f64, d: &Self) -> Self {
        Self(std::array::from_fn(|i| self.0[i] + d.0[i] * h))
    }

    /// Each direction back on the unit sphere and its rate in its tangent plane: RK4 keeps
    /// them there only to its order (as the attitude quaternion, renormalised per sub-step).
    pub fn renormalised(mut self) -> Self {
        for k in 0..TANK_COUNT {
            let e = self.direction(k);
            let norm = e.norm();
            if norm > 0.0 {
                let e = e / norm;
                let rate = self.direction_rate(k);
                let rate = rate - e * e.dot(&rate);
                self.0[6 * k..6 * k + 3].copy_from_slice(e.as_slice());
                self.0[6 * k + 3..6 * k + 6].copy_from_slice(rate.as_slice());
            }
        }
        self
    }
}

impl Slosh {
    /// The tanks of `p` on a vehicle of this dry and initial mass.
    pub fn new(p: &SloshParameters, dry_mass_kg: f64, m0_kg: f64) -> Self {
        let tanks: [Tank; TANK_COUNT] = std::array::from_fn(|k| {
            let (radius_m, full_depth_m) = (p.tank_radius_m[k], p.fill_height_m[k]);
            let hinge = Vector3::from_column_slice(&p.hinge_body_m[3 * k..3 * k + 3]);
            Tank {
                radius_m,
                full_depth_m,
                full_liquid_kg: p.liquid_mass_kg[k],
                bottom_body_m: hinge
                    - Vector3::new(0.0, hinge_height_m(radius_m, full_depth_m), 0.0),
            }
        });
        let pendulums = tanks.map(|t| {
            let mut at_full = t.pendulum_at(1.0);
            // Exactly as set, not through the bottom and back.
            at_full.hinge_body_m = t.bottom_body_m
                + Vector3::new(0.0, hinge_height_m(t.radius_m, t.full_depth_m), 0.0);
            at_full
        });
        let total_mass_kg = pendulums.iter().map(|p| p.mass_kg).sum();
        Self {
            tanks,
            pendulums,
            damping_ratio: p.damping_ratio,
            total_mass_kg,
            dry_mass_kg,
            propellant_kg: m0_kg - dry_mass_kg,
        }
    }

    /// The pendulums at rest, each mass displaced `delta0` across the thrust axis (shorter
    /// than its pendulum: `PlantParameters::check` refuses the rest).
    pub fn initial_state(&self, p: &SloshParameters) -> SloshState {
        let mut s = SloshState::default();
        for (k, pendulum) in self.pendulums.iter().enumerate() {
            let across = Vector2::new(p.delta0_m[2 * k], p.delta0_m[2 * k + 1]) / pendulum.length_m;
            let down = libm::sqrt((1.0 - across.norm_squared()).max(0.0));
            s.0[6 * k..6 * k + 3].copy_from_slice(&[across.x, -down, across.y]);
        }
        s
    }

    /// The fraction of the initial propellant left at `mass_kg`, in [0, 1].
    pub fn fill_fraction(&self, mass_kg: f64) -> f64 {
        if self.propellant_kg > 0.0 {
            ((mass_kg - self.dry_mass_kg) / self.propellant_kg).clamp(0.0, 1.0)
        } else {
            1.0
        }
    }

    /// The pendulums at the vehicle's mass `mass_kg`.
    pub fn pendulums_at(&self, mass_kg: f64) -> [Pendulum; TANK_COUNT] {
        let f = self.fill_fraction(mass_kg);
        if f == 1.0 {
            return self.pendulums;
        }
        self.tanks.map(|t| t.pendulum_at(f))
    }

    /// The largest angle of an active tank's pendulum from straight down the thrust axis,
    /// rad.
    pub fn largest_swing(&self, s: &SloshState, mass_kg: f64) -> f64 {
        self.pendulums_at(mass_kg)
            .iter()
            .enumerate()
            .filter(|(_, p)| p.is_active())
            .map(|(k, _)| {
                let e = s.direction(k);
                libm::acos((-e.y / e.norm()).clamp(-1.0, 1.0))
            })
            .fold(0.0, f64::max)
    }

    /// Tank k's sloshing mass across the thrust axis from its hinge at `mass_kg` (body x,
    /// z), m.
    pub fn displacement_m(&self, s: &SloshState, mass_kg: f64, k: usize) -> Vector2<f64> {
        s.displacement_m(k, self.pendulums_at(mass_kg)[k].length_m)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_tank_filled_to_its_radius_has_the_closed_form_pendulum() {
        // h / R = 1: tanh(1.8412) = 0.9509; L = R / 1.7508; m_1 / m_F = 0.4322.
        let (l, m) = pendulum(0.4, 0.4, 100.0);
        assert!((l - 0.4 / (XI_1 * libm::tanh(XI_1))).abs() < 1e-15);
        assert!((l - 0.22846).abs() < 1e-4, "{l}");
        assert!((m - 43.22).abs() < 0.005, "{m}");
    }

    #[test]
    fn the_hinge_sits_at_the_pressure_centre_and_the_mass_at_dodges_height() {
        // h / R = 1: cosh 1.8412 = 3.2313, sinh = 3.0727: hinge at 0.78235 R.
        let (r, h) = (0.4, 0.4);
        assert!((hinge_height_m(r, h) / r - 0.78235).abs() < 1e-5);
        let (l, _) = pendulum(r, h, 1.0);
        let lambda = XI_1 * h / r;
        let dodge = h - 2.0 * r / XI_1 * libm::tanh(lambda / 2.0);
        assert!((hinge_height_m(r, h) - l - dodge).abs() < 1e-15);
        // Deep liquid: the hinge rises to R / xi below the free surface.
        let deep = 20.0 * r;
        assert!((deep - hinge_height_m(r, deep) - r / XI_1).abs() < 1e-12);
    }

    #[test]
    fn the_pendulum_follows_the_fill_level() {
        let slosh = Slosh::new(
            &SloshParameters {
                enabled: true,
                ..SloshParameters::default()
            },
            600.0,
            900.0,
        );
        let full = slosh.pendulums_at(900.0);
        assert_eq!(full, slosh.pendulums);
        assert!(
            (full[0].hinge_body_m.y - SloshParameters::default().hinge_body_m[1]).abs() < 1e-15
        );
        // 60 % of the propellant left: depth 0.24 m, so tanh(1.105) = 0.802 and L grows by
        // 0.9509 / 0.8020, the frequency drops by 8 %.
        let sixty = slosh.pendulums_at(600.0 + 0.6 * 300.0);
        let ratio = (full[0].length_m / sixty[0].length_m).sqrt();
        assert!((ratio - 0.918).abs() < 1e-3, "{ratio}");
        let (_, m1) = pendulum(0.4, 0.24, 90.0);
        assert!((sixty[0].mass_kg - m1).abs() < 1e-12);
        // Dry: no sloshing mass, a finite pendulum.
        let dry = slosh.pendulums_at(600.0);
        assert!(dry
            .iter()
            .all(|p| p.mass_kg == 0.0 && !p.is_active() && p.length_m.is_finite()));
    }
}
