//! Landing gear and terrain: four legs ending in footpads, each a spring-damper against a
//! terrain plane with regularised Coulomb friction, the engine cut-off they trigger, and the
//! static tip-over criterion. Optional (`GearParameters::enabled`, off by default); off, the
//! plant never builds a [`Gear`] and its arithmetic is exactly the gearless one.
//!
//! The model (equations and sources in `docs/plant-gear.md`):
//! * terrain: the plane through `(0, terrain_height, 0)` NUE with the unit normal
//!   `n = (sin s cos a, cos s, sin s sin a)` (slope `s`, downhill azimuth `a` from North
//!   towards East);
//! * footpad `k` at body position `b_k` sits at `p_k = r + R(q) b_k`, moves at
//!   `v_k = v + R(q) (omega x b_k)`; its penetration is `delta_k = max(0, -n . (p_k - p0))`;
//! * normal force (the leg's spring-damper, lumped with the soil along the normal):
//!   `N_k = max(0, k delta_k + c min(1, delta_k / 1 mm) delta_k')` with `delta_k' = -n . v_k`
//!   (the damping grows in over the first millimetre of stroke), and beyond the
//!   stroke limit the leg bottoms out: `k s_max + BOTTOMING_STIFFNESS_FACTOR k (delta - s_max)`;
//! * friction: `f_k = -mu N_k v_t / sqrt(|v_t|^2 + v_reg^2)` with `v_t` the tangential
//!   footpad velocity (Coulomb for `|v_t| >> v_reg`, viscous below);
//! * force on the lander `sum(N_k n + f_k)` in NUE, torque `sum(b_k x R^T (N_k n + f_k))`.
use super::frames::{body_to_nue, Body};
use nalgebra::{Quaternion, UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

/// Number of legs.
pub const LEG_COUNT: usize = 4;

/// Past the stroke limit the leg's stiffness is this many times the spring's: the strut has
/// bottomed out against its stop (rigid in comparison, still integrable).
pub const BOTTOMING_STIFFNESS_FACTOR: f64 = 100.0;

/// Stroke over which a leg's damping grows from 0 to `damping_nspm`, m: a damper at full
/// strength from zero stroke would strike the lander with `c v` at the instant of contact.
pub const DAMPING_RAMP_DEPTH_M: f64 = 1e-3;

/// `settled`: slower than this (m/s, and rad/s for the body rate) with three or more feet
/// on the ground and not tipped over.
pub const SETTLED_SPEED_MPS: f64 = 0.01;
pub const SETTLED_RATE_RADPS: f64 = 0.01;

/// Tilt from the terrain normal beyond which the lander lies on its side, rad (80 deg),
/// whatever the footprint.
pub const ON_ITS_SIDE_RAD: f64 = 80.0 * std::f64::consts::PI / 180.0;

/// When the engines are cut (`engine_cutoff_mode`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum EngineCutoff {
    /// 0: never by the gear.
    None,
    /// 1: at the first footpad contact (the touchdown sensor).
    FirstContact,
    /// 2: when the lowest footpad is this high above the terrain, m.
    Height(f64),
}

/// The gear and terrain as the user sets them.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct GearParameters {
    pub enabled: bool,
    /// Footpad `k` (elements `3k..3k+3`) relative to the centre of mass, body axes, m, with
    /// the leg unloaded.
    pub footpad_body_m: [f64; 3 * LEG_COUNT],
    /// Spring stiffness of one leg, N/m.
    pub stiffness_npm: f64,
    /// Damping of one leg, N s/m.
    pub damping_nspm: f64,
    /// Stroke at which the leg bottoms out, m.
    pub max_stroke_m: f64,
    /// Coulomb friction coefficient footpad/soil.
    pub friction_coefficient: f64,
    /// Regularisation velocity of the friction, m/s.
    pub friction_velocity_mps: f64,
    pub terrain_height_m: f64,
    /// Terrain slope, rad (from the horizontal), below 60 deg.
    pub terrain_slope_rad: f64,
    /// Direction the terrain falls towards, from North towards East, rad.
    pub terrain_slope_azimuth_rad: f64,
    /// Raw value: 0 none, 1 first contact, 2 at `engine_cutoff_height_m`.
    pub engine_cutoff_mode: i32,
    pub engine_cutoff_height_m: f64,
    /// Largest RK4 sub-step while a footpad is in or near contact, s.
    pub contact_step_s: f64,
}

/// Footpads at radius 1.2 m in the body x-z plane at azimuths 45, 135, 225, 315 deg, 1 m
/// below the centre of mass.
const DEFAULT_FOOTPADS: [f64; 3 * LEG_COUNT] = {
    const C: f64 = 1.2 * std::f64::consts::FRAC_1_SQRT_2;
    [C, -1.0, C, -C, -1.0, C, -C, -1.0, -C, C, -1.0, -C]
};

impl Default for GearParameters {
    fn default() -> Self {
        Self {
            enabled: false,
            footpad_body_m: DEFAULT_FOOTPADS,
            // 4 legs x 40 kN/m carry the 900 kg lander's 1458 N lunar weight at 9.1 mm.
            stiffness_npm: 40_000.0,
            // About 0.5 of critical damping of the four legs in heave at 900 kg.
            damping_nspm: 3_000.0,
            max_stroke_m: 0.3,
            friction_coefficient: 0.6,
            friction_velocity_mps: 1e-3,
            terrain_height_m: 0.0,
            terrain_slope_rad: 0.0,
            terrain_slope_azimuth_rad: 0.0,
            engine_cutoff_mode: 0,
            engine_cutoff_height_m: 0.0,
            contact_step_s: 2e-4,
        }
    }
}

/// The validated gear.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Gear {
    pub footpad_body_m: [Vector3<f64>; LEG_COUNT],
    pub stiffness_npm: f64,
    pub damping_nspm: f64,
    pub max_stroke_m: f64,
    pub friction_coefficient: f64,
    pub friction_velocity_mps: f64,
    pub terrain_point_nue_m: Vector3<f64>,
    pub terrain_normal_nue: Vector3<f64>,
    pub cutoff: EngineCutoff,
    pub contact_step_s: f64,
    /// See [`static_stability_angle_rad`].
    pub static_stability_angle_rad: f64,
}

/// What the gear does at one state.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Contact {
    pub force_nue_n: Vector3<f64>,
    pub torque_body_nm: Vector3<f64>,
    /// Penetration of each footpad along the normal (the leg's stroke), m.
    pub stroke_m: [f64; LEG_COUNT],
}

/// Unit normal of a plane of slope `slope` falling towards `azimuth` (from North to East).
pub fn terrain_normal(slope_rad: f64, azimuth_rad: f64) -> Vector3<f64> {
    let (s, c) = libm::sincos(slope_rad);
    let (sa, ca) = libm::sincos(azimuth_rad);
    Vector3::new(s * ca, c, s * sa)
}

/// The static stability angle, rad: `atan(d / h)` with `d` the shortest distance from the
/// centre of mass to an edge of the footprint (consecutive footpads by azimuth in the body
/// x-z plane) and `h` the mean height of the centre of mass above the footpads (body y).
/// Tilted by more than this about the worst edge, the centre of mass lies beyond it.
pub fn static_stability_angle_rad(footpads: &[Vector3<f64>; LEG_COUNT]) -> f64 {
    let mut order: [usize; LEG_COUNT] = std::array::from_fn(|k| k);
    order.sort_by(|&a, &b| {
        libm::atan2(footpads[a].z, footpads[a].x)
            .total_cmp(&libm::atan2(footpads[b].z, footpads[b].x))
    });
    let mut d = f64::INFINITY;
    for i in 0..LEG_COUNT {
        let (a, b) = (footpads[order[i]], footpads[order[(i + 1) % LEG_COUNT]]);
        let (ax, az, ex, ez) = (a.x, a.z, b.x - a.x, b.z - a.z);
        let length = libm::sqrt(ex * ex + ez * ez);
        if length > 0.0 {
            d = d.min((ax * ez - az * ex).abs() / length);
        }
    }
    let h = -footpads.iter().map(|p| p.y).sum::<f64>() / LEG_COUNT as f64;
    libm::atan2(d, h)
}

impl Gear {
    pub fn new(p: &GearParameters) -> Self {
        let footpad_body_m = std::array::from_fn(|k| {
            Vector3::from_column_slice(&p.footpad_body_m[3 * k..3 * k + 3])
        });
        Self {
            footpad_body_m,
            stiffness_npm: p.stiffness_npm,
            damping_nspm: p.damping_nspm,
            max_stroke_m: p.max_stroke_m,
            friction_coefficient: p.friction_coefficient,
            friction_velocity_mps: p.friction_velocity_mps,
            terrain_point_nue_m: Vector3::new(0.0, p.terrain_height_m, 0.0),
            terrain_normal_nue: terrain_normal(p.terrain_slope_rad, p.terrain_slope_azimuth_rad),
            cutoff: match p.engine_cutoff_mode {
                1 => EngineCutoff::FirstContact,
                2 => EngineCutoff::Height(p.engine_cutoff_height_m),
                _ => EngineCutoff::None,
            },
            contact_step_s: p.contact_step_s,
            static_stability_angle_rad: static_stability_angle_rad(&footpad_body_m),
        }
    }

    /// Height of a point above the terrain along its normal, m.
    pub fn clearance(&self, p_nue: &Vector3<f64>) -> f64 {
        self.terrain_normal_nue
            .dot(&(p_nue - self.terrain_point_nue_m))
    }

    /// Clearance of the lowest footpad (unloaded leg), m.
    pub fn lowest_foot_clearance(&self, r_nue: &Vector3<f64>, q: &Quaternion<f64>) -> f64 {
        let rot = UnitQuaternion::from_quaternion(*q);
        self.footpad_body_m
            .iter()
            .map(|b| self.clearance(&(r_nue + rot * b)))
            .fold(f64::INFINITY, f64::min)
    }

    /// Farthest footpad from the centre of mass, m.
    pub fn reach_m(&self) -> f64 {
        self.footpad_body_m
            .iter()
            .map(|b| b.norm())
            .fold(0.0, f64::max)
    }

    /// The contact forces at a state (position, velocity NUE; attitude; body rate).
    pub fn contact(
        &self,
        r_nue: &Vector3<f64>,
        v_nue: &Vector3<f64>,
        q: &Quaternion<f64>,
        omega_body: &Vector3<f64>,
    ) -> Contact {
        let rot = UnitQuaternion::from_quaternion(*q);
        let n = self.terrain_normal_nue;
        let mut c = Contact::default();
        for (k, b) in self.footpad_body_m.iter().enumerate() {
            let p = r_nue + rot * b;
            let depth = -self.clearance(&p);
            if depth <= 0.0 {
                continue;
            }
            c.stroke_m[k] = depth;
            let v_foot = v_nue + rot * omega_body.cross(b);
            let v_n = n.dot(&v_foot);
            let spring = if depth <= self.max_stroke_m {
                self.stiffness_npm * depth
            } else {
                self.stiffness_npm
                    * (self.max_stroke_m + BOTTOMING_STIFFNESS_FACTOR * (depth - self.max_stroke_m))
            };
            // The damping grows in over the first DAMPING_RAMP_DEPTH_M of stroke: the force
            // is continuous at the touch (no impulse from the damper at zero stroke).
            let damping = self.damping_nspm * (depth / DAMPING_RAMP_DEPTH_M).min(1.0);
            let normal = (spring - damping * v_n).max(0.0);
            let v_t = v_foot - n * v_n;
            let reg = self.friction_velocity_mps;
            let friction = -v_t
                * (self.friction_coefficient * normal / libm::sqrt(v_t.norm_squared() + reg * reg));
            let f = n * normal + friction;
            c.force_nue_n += f;
            c.torque_body_nm += b.cross(&(rot.inverse() * f));
        }
        c
    }

    /// Angle between body +y and the terrain normal, rad.
    pub fn tilt_from_normal(&self, q: &Quaternion<f64>) -> f64 {
        let axis = body_to_nue(q, &Body(Vector3::y()));
        libm::acos(axis.0.dot(&self.terrain_normal_nue).clamp(-1.0, 1.0))
    }

    /// Whether the lander has tipped over: its centre of mass, seen along gravity (-Up),
    /// lies outside the footprint of its footpads (the static criterion, which on flat ground
    /// is a tilt beyond the static stability angle about an edge), or it lies on its side.
    pub fn tipped_over(&self, q: &Quaternion<f64>) -> bool {
        if self.tilt_from_normal(q) > ON_ITS_SIDE_RAD {
            return true;
        }
        let rot = UnitQuaternion::from_quaternion(*q);
        // Footpads ordered by azimuth in the body x-z plane: consecutive ones span an edge.
        let mut order: [usize; LEG_COUNT] = std::array::from_fn(|k| k);
        let b = &self.footpad_body_m;
        order.sort_by(|&i, &j| libm::atan2(b[i].z, b[i].x).total_cmp(&libm::atan2(b[j].z, b[j].x)));
        // Horizontal (North, East) coordinates relative to the centre of mass.
        let horizontal = |k: usize| {
            let p = rot * b[k];
            (p.x, p.z)
        };
        let mut sign = 0.0;
        for i in 0..LEG_COUNT {
            let (ax, az) = horizontal(order[i]);
            let (bx, bz) = horizontal(order[(i + 1) % LEG_COUNT]);
            // Cross product of the edge with the vector from its start to the centre of mass
            // (at the origin): the same sign on every edge iff the centre is inside.
            let cross = (bx - ax) * (-az) - (bz - az) * (-ax);
            if sign == 0.0 {
                sign = cross.signum();
            } else if cross * sign < 0.0 {
                return true;
            }
        }
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_footprint_is_stable_to_atan_0_8485() {
        let gear = Gear::new(&GearParameters::default());
        let expected = libm::atan2(1.2 * std::f64::consts::FRAC_1_SQRT_2, 1.0);
        assert!((gear.static_stability_angle_rad - expected).abs() < 1e-15);
        assert!((expected.to_degrees() - 40.3).abs() < 0.05);
    }

    #[test]
    fn the_normal_points_up_and_leans_downhill() {
        let n = terrain_normal(0.3, std::f64::consts::FRAC_PI_2);
        assert!((n.norm() - 1.0).abs() < 1e-15);
        // Falls towards East: the normal leans East.
        assert!(n.z > 0.0 && n.x.abs() < 1e-15 && n.y > 0.0);
    }
}
