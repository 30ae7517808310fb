//! Torque allocation to eight on/off thrusters by the redistributed pseudo-inverse.
//!
//! The minimum-norm thrusts `f = B^T (B B^T)^+ tau` (B: one column `r_k x d_k F` per
//! thruster) may be negative, which no thruster can deliver. Those thrusters are set to zero
//! and the same minimum-norm problem is solved over the others; at most eight rounds. On the
//! default layout (docs/rcs-layout.md) this fires exactly one couple per torque direction
//! with no net force: the pairs that the layout was designed around. When a thruster would
//! need more than its full force, all thrusts are scaled down together: the torque keeps its
//! direction and loses magnitude. On the default layout the reachable set about x and y is a
//! diamond, |tau_x| + |tau_y| <= 116 N m (the lateral nozzles serve both axes), z is
//! independent: each axis alone reaches the torque model's 116 N m.
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

    /// The fraction of full force each thruster should deliver, in [0, 1].
    pub fn allocate(&self, torque_cmd_body_nm: &Vector3<f64>) -> [f64; THRUSTER_COUNT] {
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
        let fraction = fraction.map(|f| if f.is_finite() { f.max(0.0) } else { 0.0 });
        let largest = fraction.iter().copied().fold(0.0, f64::max);
        if largest > 1.0 {
            fraction.map(|f| f / largest)
        } else {
            fraction
        }
    }

    /// The torque a set of thrust fractions produces, N m.
    pub fn torque_body_nm(&self, fraction: &[f64; THRUSTER_COUNT]) -> Vector3<f64> {
        (0..THRUSTER_COUNT)
            .map(|k| self.torque_at_full_body_nm[k] * fraction[k])
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::GncParameters;

    fn default_allocator() -> Allocator {
        let p = GncParameters::default();
        Allocator::new(
            &p.rcs_position_body_m,
            &p.rcs_direction_body,
            p.rcs_thruster_force_n,
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
}
