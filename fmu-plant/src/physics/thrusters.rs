//! Eight on/off RCS thrusters driven by duty cycles: their layout, the pulses a duty asks for
//! (with the minimum impulse bit) and the force and torque of those that fire.
//!
//! A duty `d` in [0, 1] fires its thruster from the start of the communication step for
//! `d h` seconds. The plant integrates such a step in pieces split at every pulse end, so a
//! pulse is integrated exactly (no smearing over an RK4 sub-step). The default layout is
//! drawn in `docs/rcs-layout.md`: two pods of four nozzles at body x = +-1 m, one couple of two
//! 58 N thrusters per torque direction at a 1 m arm, i.e. 116 N m about each axis, the limit
//! of the torque mode. The propellant of the RCS is not booked against the mass.
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

pub const THRUSTER_COUNT: usize = 8;

/// Which thrusters fire during a piece of a step.
pub type Firing = [bool; THRUSTER_COUNT];

pub const NONE_FIRING: Firing = [false; THRUSTER_COUNT];

/// The thruster geometry as the user sets it: thruster `k` uses elements `3k..3k+3`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ThrusterLayout {
    /// Nozzle positions relative to the centre of mass, body axes, m.
    pub position_body_m: [f64; 3 * THRUSTER_COUNT],
    /// Direction of the force each thruster applies to the lander (opposite to its plume),
    /// body axes, unit vectors.
    pub direction_body: [f64; 3 * THRUSTER_COUNT],
    /// Pulses of a smaller impulse than this are not fired (the valve cannot open and close
    /// that fast), N s; a pulse that continues one still firing at the end of the previous
    /// step is always fired. 0 = every pulse fires.
    pub min_impulse_bit_ns: f64,
}

/// Position (m) and force direction of each thruster of the default layout, body axes.
/// Body x is yaw, y the thrust (roll) axis, z pitch; the moment arm about each axis is 1 m.
const DEFAULT_LAYOUT: [([f64; 3], [f64; 3]); THRUSTER_COUNT] = [
    // Axial nozzles at centre-of-mass height: couples about z (pitch).
    ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]),   // 0: +z with 1
    ([-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]), // 1: +z with 0
    ([1.0, 0.0, 0.0], [0.0, -1.0, 0.0]),  // 2: -z with 3
    ([-1.0, 0.0, 0.0], [0.0, 1.0, 0.0]),  // 3: -z with 2
    // Lateral nozzles 1 m above and below: each serves a couple about x and one about y.
    ([-1.0, 1.0, 0.0], [0.0, 0.0, 1.0]), // 4: +x with 5, +y with 6
    ([-1.0, -1.0, 0.0], [0.0, 0.0, -1.0]), // 5: +x with 4, -y with 7
    ([1.0, 1.0, 0.0], [0.0, 0.0, -1.0]), // 6: -x with 7, +y with 4
    ([1.0, -1.0, 0.0], [0.0, 0.0, 1.0]), // 7: -x with 6, -y with 5
];

impl Default for ThrusterLayout {
    fn default() -> Self {
        let mut position_body_m = [0.0; 3 * THRUSTER_COUNT];
        let mut direction_body = [0.0; 3 * THRUSTER_COUNT];
        for (k, (r, d)) in DEFAULT_LAYOUT.iter().enumerate() {
            position_body_m[3 * k..3 * k + 3].copy_from_slice(r);
            direction_body[3 * k..3 * k + 3].copy_from_slice(d);
        }
        Self {
            position_body_m,
            direction_body,
            // 5 ms at 58 N: an assumption for a 58 N bipropellant thruster (catalogue values
            // for that class are a few tenths of a N s); see docs/rcs-layout.md.
            min_impulse_bit_ns: 0.29,
        }
    }
}

impl ThrusterLayout {
    pub fn position(&self, k: usize) -> Vector3<f64> {
        Vector3::from_column_slice(&self.position_body_m[3 * k..3 * k + 3])
    }

    pub fn direction(&self, k: usize) -> Vector3<f64> {
        Vector3::from_column_slice(&self.direction_body[3 * k..3 * k + 3])
    }
}

/// The validated thrusters: unit directions and the force of one thruster.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Thrusters {
    pub position_body_m: [Vector3<f64>; THRUSTER_COUNT],
    pub direction_body: [Vector3<f64>; THRUSTER_COUNT],
    pub force_n: f64,
    pub min_impulse_bit_ns: f64,
}

impl Thrusters {
    pub fn new(layout: &ThrusterLayout, force_n: f64) -> Self {
        Self {
            position_body_m: std::array::from_fn(|k| layout.position(k)),
            direction_body: std::array::from_fn(|k| layout.direction(k)),
            force_n,
            min_impulse_bit_ns: layout.min_impulse_bit_ns,
        }
    }

    /// Torque of thruster `k` about the centre of mass per newton, m (body axes).
    pub fn moment_arm_body_m(&self, k: usize) -> Vector3<f64> {
        self.position_body_m[k].cross(&self.direction_body[k])
    }

    /// Force (N) and torque about the centre of mass (N m) of the firing thrusters, body axes.
    pub fn force_and_torque_body(&self, firing: &Firing) -> (Vector3<f64>, Vector3<f64>) {
        let mut force = Vector3::zeros();
        let mut torque = Vector3::zeros();
        for k in (0..THRUSTER_COUNT).filter(|&k| firing[k]) {
            let f = self.direction_body[k] * self.force_n;
            force += f;
            torque += self.position_body_m[k].cross(&f);
        }
        (force, torque)
    }

    /// How long each thruster fires from the start of a step of `h` seconds, s. Duties are
    /// clamped to [0, 1] (NaN counts as 0); a pulse below the minimum impulse bit is dropped
    /// unless it continues a firing thruster (`continuing`).
    pub fn on_times_s(
        &self,
        duty: &[f64; THRUSTER_COUNT],
        h: f64,
        continuing: &Firing,
    ) -> [f64; THRUSTER_COUNT] {
        std::array::from_fn(|k| {
            let on_s = if duty[k].is_nan() {
                0.0
            } else {
                duty[k].clamp(0.0, 1.0) * h
            };
            let below_bit = self.force_n * on_s < self.min_impulse_bit_ns;
            if below_bit && !continuing[k] {
                0.0
            } else {
                on_s
            }
        })
    }
}

/// The pieces of a step of `h` s with constant firing: their end offsets (increasing, the
/// last one `h`) and which thrusters fire in each.
pub fn pieces(on_times_s: &[f64; THRUSTER_COUNT], h: f64) -> Vec<(f64, Firing)> {
    let mut ends: Vec<f64> = on_times_s
        .iter()
        .copied()
        .filter(|&s| s > 0.0 && s < h)
        .collect();
    ends.sort_by(f64::total_cmp);
    ends.dedup();
    ends.push(h);
    let mut start = 0.0;
    ends.into_iter()
        .map(|end| {
            // A thruster fires through [start, end) iff its pulse lasts past `start`: every
            // pulse end is a piece end.
            let firing = std::array::from_fn(|k| on_times_s[k] > start);
            start = end;
            (end, firing)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn default_thrusters() -> Thrusters {
        Thrusters::new(&ThrusterLayout::default(), 58.0)
    }

    fn only(ks: &[usize]) -> Firing {
        std::array::from_fn(|k| ks.contains(&k))
    }

    #[test]
    fn each_default_couple_gives_116_nm_about_its_axis_and_no_force() {
        let t = default_thrusters();
        for (pair, expected) in [
            ([4, 5], Vector3::new(116.0, 0.0, 0.0)),
            ([6, 7], Vector3::new(-116.0, 0.0, 0.0)),
            ([4, 6], Vector3::new(0.0, 116.0, 0.0)),
            ([5, 7], Vector3::new(0.0, -116.0, 0.0)),
            ([0, 1], Vector3::new(0.0, 0.0, 116.0)),
            ([2, 3], Vector3::new(0.0, 0.0, -116.0)),
        ] {
            let (force, torque) = t.force_and_torque_body(&only(&pair));
            assert_eq!(force, Vector3::zeros(), "{pair:?}");
            assert_eq!(torque, expected, "{pair:?}");
        }
    }

    #[test]
    fn a_single_thruster_pushes_with_its_force_along_its_direction() {
        let t = default_thrusters();
        let (force, torque) = t.force_and_torque_body(&only(&[4]));
        assert_eq!(force, Vector3::new(0.0, 0.0, 58.0));
        // (-1, 1, 0) x (0, 0, 58) = (58, 58, 0).
        assert_eq!(torque, Vector3::new(58.0, 58.0, 0.0));
    }

    #[test]
    fn short_pulses_are_dropped_unless_they_continue_a_firing_thruster() {
        let t = default_thrusters();
        let h = 0.01;
        // 0.29 N s at 58 N is 5 ms: 40 % of a 10 ms step is below it, 60 % above.
        let duty = [0.4, 0.6, 1.0, 0.0, -0.5, 1.5, f64::NAN, 0.4];
        let mut continuing = NONE_FIRING;
        continuing[7] = true;
        let on = t.on_times_s(&duty, h, &continuing);
        assert_eq!(on[0], 0.0);
        assert_eq!(on[1], 0.6 * h);
        assert_eq!(on[2], h);
        assert_eq!(on[3..7], [0.0, 0.0, h, 0.0]);
        assert_eq!(on[7], 0.4 * h, "continues the previous step's pulse");
    }

    #[test]
    fn pieces_split_the_step_at_every_pulse_end() {
        let on = [0.004, 0.0, 0.01, 0.004, 0.007, 0.0, 0.0, 0.0];
        let p = pieces(&on, 0.01);
        let ends: Vec<f64> = p.iter().map(|(e, _)| *e).collect();
        assert_eq!(ends, [0.004, 0.007, 0.01]);
        assert_eq!(p[0].1, only(&[0, 2, 3, 4]));
        assert_eq!(p[1].1, only(&[2, 4]));
        assert_eq!(p[2].1, only(&[2]));
        assert_eq!(pieces(&[0.0; 8], 0.01), vec![(0.01, NONE_FIRING)]);
    }
}
