//! Torque allocation to eight on/off thrusters by the redistributed pseudo-inverse.
//!
//! The minimum-norm thrusts `f = B^T (B B^T)^+ tau` (B: one column `r_k x d_k F` per
//! thruster) may be negative, which no thruster can deliver. Those thrusters are set to zero
//! and the same minimum-norm problem is solved over the others; at most eight rounds. On the
//! default layout (docs/rcs-layout.md) this fires exactly one couple per torque direction
//! with no net force: the pairs that the layout was designed around. On that layout the
//! reachable set about x and y is a diamond, |tau_x| + |tau_y| <= 116 N m (the lateral
//! nozzles serve both axes), z is independent: each axis alone reaches the torque model's
//! 116 N m.
//!
//! A torque beyond reach is reduced in one of two ways:
//! * [`Allocator::allocate`], direction kept: every thrust is scaled down together;
//! * [`Allocator::allocate_tilt_first`]: the torque about the tilt axes (body x and z, which
//!   turn the thrust axis and so steer the lander) is served first, and the roll torque
//!   about the thrust axis (body y) gets what is left. This is what the torque model's
//!   per-axis saturation does for a roll manoeuvre: a saturated roll does not eat the tilt
//!   correction.
use nalgebra::{Matrix3, Vector3};

pub const THRUSTER_COUNT: usize = 8;

/// The thruster geometry the allocation believes in.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Allocator {
    /// Torque of each thruster at full force, body axes, N m.
    torque_at_full_body_nm: [Vector3<f64>; THRUSTER_COUNT],
}

impl Allocator {
    /// From positions (m) and unit force directions (body axes, thruster `k` at `3k..3k+3`)
    /// and the force of one thruster (N).
    pub fn new(position_body_m: &[f64; 24], direction_body: &[f64; 24], force_n: f64) -> Self {
        let column = |a: &[f64; 24], k: usize| Vector3::from_column_slice(&a[3 * k..3 * k + 3]);
        Self {
            torque_at_full_body_nm: std::array::from_fn(|k| {
                column(position_body_m, k).cross(&column(direction_body, k)) * force_n
            }),
        }
    }

    /// The fraction of full force each thruster should deliver, in [0, 1]; a torque beyond
    /// reach keeps its direction.
    pub fn allocate(&self, torque_cmd_body_nm: &Vector3<f64>) -> [f64; THRUSTER_COUNT] {
        scaled_into_range(self.unbounded(torque_cmd_body_nm))
    }

    /// The fraction of full force each thruster should deliver, in [0, 1]; beyond reach the
    /// tilt torque (body x, z) is kept and the roll torque (body y) reduced, and when the
    /// tilt torque alone is beyond reach it keeps its direction and no roll is commanded.
    pub fn allocate_tilt_first(&self, torque_cmd_body_nm: &Vector3<f64>) -> [f64; THRUSTER_COUNT] {
        let full = self.unbounded(torque_cmd_body_nm);
        if largest(&full) <= 1.0 {
            return full;
        }
        let tilt = Vector3::new(torque_cmd_body_nm.x, 0.0, torque_cmd_body_nm.z);
        let roll = Vector3::new(0.0, torque_cmd_body_nm.y, 0.0);
        let tilt_only = self.unbounded(&tilt);
        if largest(&tilt_only) >= 1.0 {
            return scaled_into_range(tilt_only);
        }
        // The largest share of the roll torque that still fits: bisection (the thrusts grow
        // with the share); 2^-30 of the roll torque is far below a thruster's resolution.
        let (mut fits, mut too_much) = (0.0, 1.0);
        for _ in 0..30 {
            let share = 0.5 * (fits + too_much);
            if largest(&self.unbounded(&(tilt + roll * share))) <= 1.0 {
                fits = share;
            } else {
                too_much = share;
            }
        }
        scaled_into_range(self.unbounded(&(tilt + roll * fits)))
    }

    /// The non-negative thrust fractions for a torque, not limited to 1.
    fn unbounded(&self, torque_cmd_body_nm: &Vector3<f64>) -> [f64; THRUSTER_COUNT] {
        let mut free = [true; THRUSTER_COUNT];
        let mut fraction = [0.0; THRUSTER_COUNT];
        for _ in 0..THRUSTER_COUNT {
            let gram: Matrix3<f64> = (0..THRUSTER_COUNT)
                .filter(|&k| free[k])
                .map(|k| {
                    self.torque_at_full_body_nm[k] * self.torque_at_full_body_nm[k].transpose()
                })
                .sum();
            // Thrusters whose torque is out of reach (a zero row) are skipped by the
            // pseudo-inverse; the tolerance is relative to the largest singular value.
            let scale = gram.norm().max(f64::MIN_POSITIVE);
            let Ok(inverse) = gram.pseudo_inverse(1e-12 * scale) else {
                return [0.0; THRUSTER_COUNT];
            };
            let lambda = inverse * torque_cmd_body_nm;
            let mut negative = false;
            for k in 0..THRUSTER_COUNT {
                fraction[k] = if free[k] {
                    self.torque_at_full_body_nm[k].dot(&lambda)
                } else {
                    0.0
                };
                if fraction[k] < 0.0 {
                    free[k] = false;
                    negative = true;
                }
            }
            if !negative {
                break;
            }
        }
        // A last round may still have left negatives (no non-negative solution on the free
        // set): they cannot fire.
        fraction.map(|f| if f.is_finite() { f.max(0.0) } else { 0.0 })
    }

    /// The torque a set of thrust fractions produces, N m.
    pub fn torque_body_nm(&self, fraction: &[f64; THRUSTER_COUNT]) -> Vector3<f64> {
        (0..THRUSTER_COUNT)
            .map(|k| self.torque_at_full_body_nm[k] * fraction[k])
            .sum()
    }
}

fn largest(fraction: &[f64; THRUSTER_COUNT]) -> f64 {
    fraction.iter().copied().fold(0.0, f64::max)
}

/// Scales all fractions down together so that none exceeds 1.
fn scaled_into_range(fraction: [f64; THRUSTER_COUNT]) -> [f64; THRUSTER_COUNT] {
    let top = largest(&fraction);
    if top > 1.0 {
        fraction.map(|f| f / top)
    } else {
        fraction
    }
}

/// The plant's default thruster layout (docs/rcs-layout.md): position (m) and force
/// direction of each thruster, body axes.
const DEFAULT_RCS_LAYOUT: [([f64; 3], [f64; 3]); THRUSTER_COUNT] = [
    ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
    ([-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]),
    ([1.0, 0.0, 0.0], [0.0, -1.0, 0.0]),
    ([-1.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
    ([-1.0, 1.0, 0.0], [0.0, 0.0, 1.0]),
    ([-1.0, -1.0, 0.0], [0.0, 0.0, -1.0]),
    ([1.0, 1.0, 0.0], [0.0, 0.0, -1.0]),
    ([1.0, -1.0, 0.0], [0.0, 0.0, 1.0]),
];

pub fn default_layout_column(direction: bool) -> [f64; 3 * THRUSTER_COUNT] {
    let mut out = [0.0; 3 * THRUSTER_COUNT];
    for (k, (r, d)) in DEFAULT_RCS_LAYOUT.iter().enumerate() {
        out[3 * k..3 * k + 3].copy_from_slice(if direction { d } else { r });
    }
    out
}

/// The plant's default force of one thruster (docs/rcs-layout.md), N.
pub const DEFAULT_THRUSTER_FORCE_N: f64 = 58.0;

#[cfg(test)]
mod tests {
    use super::*;

    fn default_allocator() -> Allocator {
        Allocator::new(
            &default_layout_column(false),
            &default_layout_column(true),
            DEFAULT_THRUSTER_FORCE_N,
        )
    }

    #[test]
    fn a_torque_about_one_axis_fires_its_couple_only() {
        let a = default_allocator();
        for (torque, pair) in [
            (Vector3::new(58.0, 0.0, 0.0), [4, 5]),
            (Vector3::new(-58.0, 0.0, 0.0), [6, 7]),
            (Vector3::new(0.0, 58.0, 0.0), [4, 6]),
            (Vector3::new(0.0, -58.0, 0.0), [5, 7]),
            (Vector3::new(0.0, 0.0, 58.0), [0, 1]),
            (Vector3::new(0.0, 0.0, -58.0), [2, 3]),
        ] {
            let f = a.allocate(&torque);
            for (k, fk) in f.iter().enumerate() {
                let expected = if pair.contains(&k) { 0.5 } else { 0.0 };
                assert!((fk - expected).abs() < 1e-12, "{torque}: {f:?}");
            }
        }
    }

    #[test]
    fn a_reachable_torque_is_delivered_exactly_with_non_negative_thrusts() {
        let a = default_allocator();
        for torque in [
            Vector3::new(30.0, -50.0, 80.0),
            Vector3::new(-70.0, 40.0, -116.0),
            Vector3::new(0.0, 116.0, 116.0),
            Vector3::new(-58.0, -58.0, 1.0),
        ] {
            let f = a.allocate(&torque);
            assert!(f.iter().all(|&x| (0.0..=1.0).contains(&x)), "{f:?}");
            assert!(
                (a.torque_body_nm(&f) - torque).norm() < 1e-9,
                "{torque}: {f:?}"
            );
        }
    }

    #[test]
    fn an_unreachable_torque_keeps_its_direction() {
        let a = default_allocator();
        let torque = Vector3::new(300.0, 100.0, -50.0);
        let f = a.allocate(&torque);
        let delivered = a.torque_body_nm(&f);
        assert!(f.contains(&1.0), "{f:?}");
        assert!(
            delivered.normalize().dot(&torque.normalize()) > 1.0 - 1e-12,
            "{delivered}"
        );
        // |tau_x| + |tau_y| is what the shared lateral nozzles can give.
        assert!(
            (delivered.x.abs() + delivered.y.abs() - 116.0).abs() < 1e-9,
            "{delivered}"
        );
    }

    #[test]
    fn tilt_first_keeps_the_tilt_torque_and_gives_roll_the_rest() {
        let a = default_allocator();
        // Roll saturated at 116 N m with a 40 N m yaw correction: the diamond leaves 76 N m.
        let f = a.allocate_tilt_first(&Vector3::new(40.0, 116.0, -30.0));
        let delivered = a.torque_body_nm(&f);
        assert!(
            (delivered - Vector3::new(40.0, 76.0, -30.0)).norm() < 1e-6,
            "{delivered}"
        );
        // Keeping the direction instead cuts the yaw correction too.
        let kept = a.torque_body_nm(&a.allocate(&Vector3::new(40.0, 116.0, -30.0)));
        assert!(kept.x < 30.0, "{kept}");
        // A reachable torque is the same either way.
        let t = Vector3::new(20.0, 50.0, -30.0);
        assert_eq!(a.allocate_tilt_first(&t), a.allocate(&t));
        // A tilt torque beyond reach keeps its direction and leaves no roll.
        let f = a.allocate_tilt_first(&Vector3::new(200.0, 50.0, 100.0));
        let delivered = a.torque_body_nm(&f);
        assert!(delivered.y.abs() < 1e-9, "{delivered}");
        assert!((delivered.x - 116.0).abs() < 1e-9 && (delivered.z - 58.0).abs() < 1e-9);
    }
}
