//! Propellant slosh: one spherical pendulum per tank (the first lateral sloshing mode of an
//! upright circular cylindrical tank), linearised, coupled to the rigid body by the force
//! and torque at its hinge. Optional (`SloshParameters::enabled`, off by default); off, the
//! plant builds no [`Slosh`] and integrates exactly as without it.
//!
//! Equivalent mechanical model (Abramson, NASA SP-106, 1966, ch. 6; Dodge, "The New Dynamic
//! Behavior of Liquids in Moving Containers", SwRI 2000, ch. 3), for a tank of radius `R`
//! filled to depth `h` with liquid of mass `m_F`, `xi = 1.8412` (first root of `J1'`):
//! * pendulum length `L = R / (xi tanh(xi h / R))`, so `omega^2 = g_eff / L`;
//! * sloshing mass `m_1 = m_F 2 tanh(xi h / R) / (xi (xi^2 - 1) h / R)`.
//!
//! Coupling (body axes, thrust along +y, small displacements `delta` of each sloshing mass
//! in the body x-z plane; the Coriolis term of the pendulum's own motion neglected):
//! * axial specific force `s_y = F_y / m` (engine and RCS forces over the total mass);
//! * the rigid part (mass `m - sum m_1`) feels `s_lat = (F_lat + sum f_i) / (m - sum m_1)`
//!   with `f_i = m_1 (omega_i^2 delta_i + 2 zeta omega_i delta_i')`, `omega_i^2 = s_y / L_i`;
//! * each pendulum: `delta_i'' = -omega_i^2 delta_i - 2 zeta omega_i delta_i' - s_lat - a_i`,
//!   where `a_i` is the lateral part of the hinge's acceleration relative to the centre of
//!   mass, `alpha x r_i + omega x (omega x r_i)`, with the body's angular acceleration
//!   `alpha` from the torques other than the slosh's own: a turn about the thrust axis swings
//!   the propellant (tangentially with `alpha`, outward with `omega^2`);
//! * torque on the rigid body `sum hinge_i x f_i`.
use nalgebra::{Vector2, Vector3};
use serde::{Deserialize, Serialize};

pub const TANK_COUNT: usize = 2;

/// First root of the derivative of the Bessel function J1.
pub const XI_1: f64 = 1.841_183_8;

/// The slosh model as the user sets it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SloshParameters {
    pub enabled: bool,
    /// Radius of each (upright cylindrical) tank, m.
    pub tank_radius_m: [f64; TANK_COUNT],
    /// Liquid depth in each tank, m.
    pub fill_height_m: [f64; TANK_COUNT],
    /// Liquid mass in each tank, kg (0: no slosh in that tank).
    pub liquid_mass_kg: [f64; TANK_COUNT],
    /// Hinge of each pendulum relative to the centre of mass, body axes, m.
    pub hinge_body_m: [f64; 3 * TANK_COUNT],
    /// Damping ratio of the sloshing mode.
    pub damping_ratio: f64,
    /// Initial displacement of each sloshing mass (tank k: body x, body z at 2k, 2k + 1), m.
    pub delta0_m: [f64; 2 * TANK_COUNT],
}

impl Default for SloshParameters {
    fn default() -> Self {
        Self {
            enabled: false,
            tank_radius_m: [0.4; TANK_COUNT],
            fill_height_m: [0.4; TANK_COUNT],
            // The default 300 kg of propellant (m0 - dry_mass) in two tanks.
            liquid_mass_kg: [150.0; TANK_COUNT],
            hinge_body_m: [0.6, 0.0, 0.0, -0.6, 0.0, 0.0],
            damping_ratio: 0.005,
            delta0_m: [0.0; 2 * TANK_COUNT],
        }
    }
}

/// One tank's pendulum.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Pendulum {
    pub length_m: f64,
    pub mass_kg: f64,
    pub hinge_body_m: Vector3<f64>,
}

/// Pendulum length and sloshing mass of a cylindrical tank (radius, depth, liquid mass).
pub fn pendulum(radius_m: f64, depth_m: f64, liquid_kg: f64) -> (f64, f64) {
    let t = libm::tanh(XI_1 * depth_m / radius_m);
    let length = radius_m / (XI_1 * t);
    let mass = liquid_kg * 2.0 * t / (XI_1 * (XI_1 * XI_1 - 1.0) * depth_m / radius_m);
    (length, mass)
}

/// The validated slosh model.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Slosh {
    pub pendulums: [Pendulum; TANK_COUNT],
    pub damping_ratio: f64,
    pub total_mass_kg: f64,
}

/// The pendulum states: tank k's displacement (x, z) at `4k, 4k + 1`, its rate at
/// `4k + 2, 4k + 3`; m and m/s, body axes.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct SloshState(pub [f64; 4 * TANK_COUNT]);

impl SloshState {
    pub fn displacement(&self, k: usize) -> Vector2<f64> {
        Vector2::new(self.0[4 * k], self.0[4 * k + 1])
    }

    pub fn rate(&self, k: usize) -> Vector2<f64> {
        Vector2::new(self.0[4 * k + 2], self.0[4 * k + 3])
    }

    pub fn add_scaled(&self, h: f64, d: &Self) -> Self {
        Self(std::array::from_fn(|i| self.0[i] + d.0[i] * h))
    }
}

/// What the slosh does to the rigid body at a state, and its own derivative.
pub struct SloshEffect {
    /// Lateral (body x, z) acceleration of the rigid part minus what `F_lat / m` gives, m/s^2.
    pub extra_acceleration_body: Vector3<f64>,
    pub torque_body_nm: Vector3<f64>,
    pub derivative: SloshState,
}

impl Slosh {
    pub fn new(p: &SloshParameters) -> Self {
        let pendulums = std::array::from_fn(|k| {
            let (length_m, mass_kg) =
                pendulum(p.tank_radius_m[k], p.fill_height_m[k], p.liquid_mass_kg[k]);
            Pendulum {
                length_m,
                mass_kg,
                hinge_body_m: Vector3::from_column_slice(&p.hinge_body_m[3 * k..3 * k + 3]),
            }
        });
        let total_mass_kg = pendulums.iter().map(|p: &Pendulum| p.mass_kg).sum();
        Self {
            pendulums,
            damping_ratio: p.damping_ratio,
            total_mass_kg,
        }
    }

    pub fn initial_state(p: &SloshParameters) -> SloshState {
        let mut s = SloshState::default();
        for k in 0..TANK_COUNT {
            s.0[4 * k] = p.delta0_m[2 * k];
            s.0[4 * k + 1] = p.delta0_m[2 * k + 1];
        }
        s
    }

    /// The coupling at a state: `force_body_n` the engine and RCS force (body axes), `mass_kg`
    /// the total mass, `omega_body` the body rate and `alpha_body` the body's angular
    /// acceleration from the other torques (rad/s, rad/s^2).
    pub fn effect(
        &self,
        s: &SloshState,
        force_body_n: &Vector3<f64>,
        mass_kg: f64,
        omega_body: &Vector3<f64>,
        alpha_body: &Vector3<f64>,
    ) -> SloshEffect {
        let s_y = force_body_n.y / mass_kg;
        let rigid_kg = mass_kg - self.total_mass_kg;
        let mut hinge_forces = [Vector2::zeros(); TANK_COUNT];
        let mut omegas = [(0.0, 0.0); TANK_COUNT];
        let mut sum = Vector2::zeros();
        for (k, p) in self.pendulums.iter().enumerate() {
            if p.mass_kg <= 0.0 {
                continue;
            }
            let omega2 = s_y.max(0.0) / p.length_m;
            let two_zeta_omega = 2.0 * self.damping_ratio * libm::sqrt(omega2);
            omegas[k] = (omega2, two_zeta_omega);
            hinge_forces[k] = (s.displacement(k) * omega2 + s.rate(k) * two_zeta_omega) * p.mass_kg;
            sum += hinge_forces[k];
        }
        let lateral = Vector2::new(force_body_n.x, force_body_n.z);
        let s_lat = (lateral + sum) / rigid_kg;
        let extra = s_lat - lateral / mass_kg;
        let mut derivative = SloshState::default();
        let mut torque = Vector3::zeros();
        for (k, p) in self.pendulums.iter().enumerate() {
            if p.mass_kg <= 0.0 {
                continue;
            }
            let (omega2, two_zeta_omega) = omegas[k];
            let r = &p.hinge_body_m;
            let hinge_rel = alpha_body.cross(r) + omega_body.cross(&omega_body.cross(r));
            let acc = -s.displacement(k) * omega2
                - s.rate(k) * two_zeta_omega
                - s_lat
                - Vector2::new(hinge_rel.x, hinge_rel.z);
            derivative.0[4 * k] = s.0[4 * k + 2];
            derivative.0[4 * k + 1] = s.0[4 * k + 3];
            derivative.0[4 * k + 2] = acc.x;
            derivative.0[4 * k + 3] = acc.y;
            let f = Vector3::new(hinge_forces[k].x, 0.0, hinge_forces[k].y);
            torque += p.hinge_body_m.cross(&f);
        }
        SloshEffect {
            extra_acceleration_body: Vector3::new(extra.x, 0.0, extra.y),
            torque_body_nm: torque,
            derivative,
        }
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
    fn a_turn_about_the_thrust_axis_swings_the_propellant() {
        // GIVEN the default tanks (hinges at +-0.6 m on body x) at rest, hovering at 1458 N
        let slosh = Slosh::new(&SloshParameters {
            enabled: true,
            ..SloshParameters::default()
        });
        let at_rest = Slosh::initial_state(&SloshParameters::default());
        let force = Vector3::new(0.0, 1458.0, 0.0);
        let zero = Vector3::zeros();
        let still = slosh.effect(&at_rest, &force, 900.0, &zero, &zero);
        assert!(still.derivative.0.iter().all(|&d| d == 0.0));
        // WHEN the body accelerates about its thrust axis (y) at 0.1 rad/s^2
        let (a, w) = (0.1, 0.3);
        let spun_up = slosh.effect(&at_rest, &force, 900.0, &zero, &Vector3::new(0.0, a, 0.0));
        // THEN each sloshing mass lags tangentially: the hinge moves at alpha x r = (0, 0,
        // -a r_x), so the pendulum accelerates by +a r_x along z relative to its tank
        let d = &spun_up.derivative.0;
        assert!(
            (d[3] - a * 0.6).abs() < 1e-15 && (d[7] + a * 0.6).abs() < 1e-15,
            "{d:?}"
        );
        assert!(d[2] == 0.0 && d[6] == 0.0);
        // AND turning at 0.3 rad/s flings it outward: omega x (omega x r) = -w^2 r
        let turning = slosh.effect(&at_rest, &force, 900.0, &Vector3::new(0.0, w, 0.0), &zero);
        let d = &turning.derivative.0;
        assert!((d[2] - w * w * 0.6).abs() < 1e-15 && (d[6] + w * w * 0.6).abs() < 1e-15);
    }
}
