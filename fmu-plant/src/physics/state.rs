//! The integrated state of the plant.
use super::frames::Body;
use super::integrator::OdeState;
use nalgebra::{Quaternion, Vector6};
use serde::{Deserialize, Serialize};

/// Everything RK4 integrates. The same type holds its own time derivative.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PlantState {
    /// Translational state; its layout belongs to the selected translation model
    /// (`translation_flat`: r_nue, v_nue; `translation_spherical`: r, lon, lat, u, v, w).
    pub translation: Vector6<f64>,
    /// Attitude, body to NUE (renormalised after every sub-step, not inside RK4 stages).
    pub q_body_to_nue: Quaternion<f64>,
    /// Body angular rate, rad/s.
    pub omega_body: Body,
    /// Total mass, kg.
    pub mass_kg: f64,
    /// First-order-lag state of the delivered engine thrust, N (unused when the lag is off).
    pub thrust_lag_n: f64,
    /// First-order-lag state of the delivered RCS torque, N m (unused when the lag is off).
    pub torque_lag_body_nm: Body,
}

impl OdeState for PlantState {
    #[inline]
    fn add_scaled(&self, h: f64, d: &Self) -> Self {
        Self {
            translation: self.translation + d.translation * h,
            q_body_to_nue: self.q_body_to_nue + d.q_body_to_nue * h,
            omega_body: self.omega_body + d.omega_body * h,
            mass_kg: self.mass_kg + d.mass_kg * h,
            thrust_lag_n: self.thrust_lag_n + d.thrust_lag_n * h,
            torque_lag_body_nm: self.torque_lag_body_nm + d.torque_lag_body_nm * h,
        }
    }
}

impl PlantState {
    /// Normalises the attitude quaternion; RK4 preserves |q| only to O(h^5) per step.
    #[inline]
    pub fn renormalised(mut self) -> Self {
        self.q_body_to_nue = normalised(&self.q_body_to_nue);
        self
    }

    /// Whether every component is finite: `x * 0` is 0 for finite `x` and NaN otherwise,
    /// so one branch-free sum tells (checked after every step). The sum runs in two lanes
    /// over pairs of components, which the compiler keeps in one vector register: its order
    /// does not change the answer (a NaN or an infinity anywhere makes it NaN, and finite
    /// components only ever add zeros).
    #[inline]
    pub fn is_finite(&self) -> bool {
        let (r, q) = (&self.translation, &self.q_body_to_nue.coords);
        let (w, l) = (&self.omega_body.0, &self.torque_lag_body_nm.0);
        let pairs = [
            [r[0], r[1]],
            [r[2], r[3]],
            [r[4], r[5]],
            [q[0], q[1]],
            [q[2], q[3]],
            [w[0], w[1]],
            [w[2], self.mass_kg],
            [self.thrust_lag_n, l[0]],
            [l[1], l[2]],
        ];
        let mut probe = [0.0; 2];
        for [a, b] in pairs {
            probe[0] += a * 0.0;
            probe[1] += b * 0.0;
        }
        probe[0] + probe[1] == 0.0
    }
}

/// `q / |q|`, also when `|q|` overflows: a body rate far beyond anything physical (a
/// crafted state, say 1e77 rad/s) grows RK4's q to 1e200 and more, whose squared norm is
/// infinite; dividing by it would give a zero quaternion, and normalising that NaN.
/// Scaling by the largest component first keeps every finite, nonzero q finite and unit.
#[inline]
pub fn normalised(q: &Quaternion<f64>) -> Quaternion<f64> {
    let largest = q.coords.amax();
    if largest.is_finite() && largest > 1e150 {
        let scaled = q / largest;
        scaled / scaled.norm()
    } else {
        q.normalize()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every one of the 18 components, made NaN or infinite, is found.
    #[test]
    fn a_non_finite_component_anywhere_is_found() {
        let base = PlantState {
            translation: Vector6::repeat(1e300),
            q_body_to_nue: Quaternion::new(1.0, 0.0, 0.0, 0.0),
            omega_body: Body::new(-1e300, -1e300, -1e300),
            mass_kg: 900.0,
            thrust_lag_n: 0.0,
            torque_lag_body_nm: Body::zeros(),
        };
        assert!(base.is_finite());
        for k in 0..18 {
            for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
                let mut x = base;
                let slot = match k {
                    0..=5 => &mut x.translation[k],
                    6..=9 => &mut x.q_body_to_nue.coords[k - 6],
                    10..=12 => &mut x.omega_body.0[k - 10],
                    13 => &mut x.mass_kg,
                    14 => &mut x.thrust_lag_n,
                    _ => &mut x.torque_lag_body_nm.0[k - 15],
                };
                *slot = bad;
                assert!(!x.is_finite(), "component {k} = {bad}");
            }
        }
    }
}
