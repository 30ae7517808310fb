//! The measurement models of the filter and their Jacobians with respect to the error state
//! (attitude error `dtheta` in body axes: `R_true = R (I + [dtheta]x)`), each a scalar.
//!
//! - Altimeter: `rho = n . (r - p0) / (-n . R d)`, the slant range along the body beam `d` to
//!   the terrain plane through `p0 = (0, terrain_height, 0)` with the upward unit normal `n`.
//!   `d rho / d dr = n^T / c` and `d rho / d dtheta = -(h / c^2) n^T R [d]x` with `h` the
//!   numerator and `c` the denominator.
//! - Velocimeter beam `b`: `y = v . R b`. `d y / d dv = (R b)^T`, `d y / d dtheta = -v^T R [b]x`.
use super::covariance::{Row, N, R as IR, THETA, V as IV};
use super::rotation::skew;
use nalgebra::{Matrix3, Vector3};

/// A scalar measurement's prediction from the nominal state and its Jacobian row.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Prediction {
    pub value: f64,
    pub jacobian: Row,
}

/// The terrain plane: a point and its upward unit normal (NUE).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Plane {
    pub point_nue: Vector3<f64>,
    pub normal_nue: Vector3<f64>,
}

impl Plane {
    pub fn new(height_m: f64, normal_nue: &[f64; 3]) -> Plane {
        Plane {
            point_nue: Vector3::new(0.0, height_m, 0.0),
            normal_nue: super::rotation::unit(&Vector3::from(*normal_nue)),
        }
    }
}

fn put(row: &mut Row, at: usize, v: &Vector3<f64>) {
    row[at..at + 3].copy_from_slice(v.as_slice());
}

/// The predicted slant range, or `None` when the predicted beam misses the plane (the
/// lander estimated on or below it, or the beam at or above its horizon): then the
/// measurement cannot be used.
pub fn altimeter(
    plane: &Plane,
    r: &Vector3<f64>,
    rotation: &Matrix3<f64>,
    beam_body: &Vector3<f64>,
) -> Option<Prediction> {
    let n = plane.normal_nue;
    let h = n.dot(&(r - plane.point_nue));
    let c = -n.dot(&(rotation * beam_body));
    if h <= 0.0 || c <= 0.0 {
        return None;
    }
    let mut jacobian = [0.0; N];
    put(&mut jacobian, IR, &(n / c));
    let d_theta = -(h / (c * c)) * (rotation.transpose() * n).transpose() * skew(beam_body);
    put(&mut jacobian, THETA, &d_theta.transpose());
    Some(Prediction {
        value: h / c,
        jacobian,
    })
}

/// The predicted line-of-sight velocity along the body beam `b`.
pub fn velocimeter(
    v: &Vector3<f64>,
    rotation: &Matrix3<f64>,
    beam_body: &Vector3<f64>,
) -> Prediction {
    let d = rotation * beam_body;
    let mut jacobian = [0.0; N];
    put(&mut jacobian, IV, &d);
    let d_theta = -(rotation.transpose() * v).transpose() * skew(beam_body);
    put(&mut jacobian, THETA, &d_theta.transpose());
    Prediction {
        value: v.dot(&d),
        jacobian,
    }
}

#[cfg(test)]
mod tests {
    use super::super::rotation::{exp, matrix};
    use super::*;

    /// The Jacobians against central differences of the models themselves.
    #[test]
    fn the_jacobians_are_the_derivatives_of_the_models() {
        let plane = Plane::new(20.0, &[0.1, 1.0, -0.05]);
        let q = exp(&Vector3::new(0.1, 0.2, -0.15));
        let r = Vector3::new(30.0, 500.0, -10.0);
        let v = Vector3::new(2.0, -8.0, 1.0);
        let beam = Vector3::new(0.3, -0.9, 0.1).normalize();
        let alt = altimeter(&plane, &r, &matrix(&q), &beam).unwrap();
        let vel = velocimeter(&v, &matrix(&q), &beam);
        let eps = 1e-6;
        for k in 0..3 {
            let mut e = Vector3::zeros();
            e[k] = eps;
            let up = |d: Vector3<f64>| matrix(&super::super::rotation::mul(&q, &exp(&d)));
            let d_alt_r = (altimeter(&plane, &(r + e), &matrix(&q), &beam)
                .unwrap()
                .value
                - altimeter(&plane, &(r - e), &matrix(&q), &beam)
                    .unwrap()
                    .value)
                / (2.0 * eps);
            let d_alt_t = (altimeter(&plane, &r, &up(e), &beam).unwrap().value
                - altimeter(&plane, &r, &up(-e), &beam).unwrap().value)
                / (2.0 * eps);
            let d_vel_v = (velocimeter(&(v + e), &matrix(&q), &beam).value
                - velocimeter(&(v - e), &matrix(&q), &beam).value)
                / (2.0 * eps);
            let d_vel_t = (velocimeter(&v, &up(e), &beam).value
                - velocimeter(&v, &up(-e), &beam).value)
                / (2.0 * eps);
            assert!((d_alt_r - alt.jacobian[IR + k]).abs() < 1e-6, "alt r {k}");
            assert!(
                (d_alt_t - alt.jacobian[THETA + k]).abs() < 1e-4,
                "alt theta {k}: {d_alt_t} vs {}",
                alt.jacobian[THETA + k]
            );
            assert!((d_vel_v - vel.jacobian[IV + k]).abs() < 1e-8, "vel v {k}");
            assert!(
                (d_vel_t - vel.jacobian[THETA + k]).abs() < 1e-6,
                "vel theta {k}"
            );
        }
    }
}
