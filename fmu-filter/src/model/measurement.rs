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
use lander_math::frames::{Body, BodyToNue, Nue};
use nalgebra::{Matrix3, Matrix6, Vector3};

/// A scalar measurement's prediction from the nominal state and its Jacobian row.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Prediction {
    pub value: f64,
    pub jacobian: Row,
}

/// The terrain plane: a point and its upward unit normal (NUE).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Plane {
    pub point_nue: Nue,
    pub normal_nue: Nue,
}

impl Plane {
    pub fn new(height_m: f64, normal_nue: &[f64; 3]) -> Plane {
        Plane {
            point_nue: Nue::new(0.0, height_m, 0.0),
            normal_nue: Nue(super::rotation::unit(&Vector3::from(*normal_nue))),
        }
    }
}

fn put(row: &mut Row, at: usize, v: &Vector3<f64>) {
    row[at..at + 3].copy_from_slice(v.as_slice());
}

/// The predicted slant range, or `None` when the predicted beam misses the plane (the
/// lander estimated on or below it, or the beam at or above its horizon): then the
/// measurement cannot be used.
pub fn altimeter(plane: &Plane, r: &Nue, attitude: &BodyToNue, beam: &Body) -> Option<Prediction> {
    let n = plane.normal_nue;
    let h = n.dot(&(*r - plane.point_nue));
    let c = -n.dot(&attitude.to_nue(beam));
    if h <= 0.0 || c <= 0.0 {
        return None;
    }
    let mut jacobian = [0.0; N];
    put(&mut jacobian, IR, &(n.0 / c));
    let d_theta = -(h / (c * c)) * attitude.to_body(&n).0.transpose() * skew(&beam.0);
    put(&mut jacobian, THETA, &d_theta.transpose());
    Some(Prediction {
        value: h / c,
        jacobian,
    })
}

/// The mean and variance of the slant range's second-order part when the position and
/// attitude errors `z = (dr, dtheta)` have the covariance `p_z`. With `u = R^T n` and
/// `c0 = -u . d`, the attitude error turns the beam's cosine into
/// `c0 + w . dtheta - dtheta^T M dtheta / 2` (`w = u x d`, `M = (u d^T + d u^T) / 2 + c0 I`),
/// so the range's quadratic part is `z^T Q z / 2`, `Q = [[0, B], [B^T, A]]` with
/// `A = (h / c0^2) M + (2 h / c0^3) w w^T` and `B = -n w^T / c0^2`: mean `tr(Q P) / 2`,
/// variance `tr(Q P Q P) / 2` (Gaussian errors). Hundreds of metres up with centiradians of
/// attitude uncertainty the mean is centimetres, a bias of the linearised prediction that
/// a hundred updates a second would otherwise read as attitude information.
pub fn altimeter_second_order(
    plane: &Plane,
    r: &Nue,
    attitude: &BodyToNue,
    beam: &Body,
    p_z: &Matrix6<f64>,
) -> (f64, f64) {
    let n = plane.normal_nue;
    let h = n.dot(&(*r - plane.point_nue));
    let u = attitude.to_body(&n).0;
    let beam_body = &beam.0;
    let c0 = -u.dot(beam_body);
    let w = u.cross(beam_body);
    let m =
        (u * beam_body.transpose() + beam_body * u.transpose()) * 0.5 + Matrix3::identity() * c0;
    let a = m * (h / (c0 * c0)) + w * w.transpose() * (2.0 * h / (c0 * c0 * c0));
    let b = -(n.0 * w.transpose()) / (c0 * c0);
    let mut q = Matrix6::zeros();
    q.fixed_view_mut::<3, 3>(0, 3).copy_from(&b);
    q.fixed_view_mut::<3, 3>(3, 0).copy_from(&b.transpose());
    q.fixed_view_mut::<3, 3>(3, 3).copy_from(&a);
    let qp = q * p_z;
    (0.5 * qp.trace(), 0.5 * (qp * qp).trace())
}

/// The predicted line-of-sight velocity along the body beam `b`.
pub fn velocimeter(v: &Nue, attitude: &BodyToNue, beam: &Body) -> Prediction {
    let d = attitude.to_nue(beam);
    let mut jacobian = [0.0; N];
    put(&mut jacobian, IV, &d.0);
    let d_theta = -attitude.to_body(v).0.transpose() * skew(&beam.0);
    put(&mut jacobian, THETA, &d_theta.transpose());
    Prediction {
        value: v.dot(&d),
        jacobian,
    }
}

#[cfg(test)]
mod tests {
    use super::super::rotation::exp;
    use super::*;
    use rand::SeedableRng;
    use rand_distr::{Distribution, StandardNormal};

    /// The second-order mean and variance against the exact range of 200,000 error draws:
    /// what the exact model adds to the linear prediction, averaged.
    #[test]
    fn the_altimeter_second_order_terms_are_the_exact_range_s_mean_and_variance() {
        let plane = Plane::new(20.0, &[0.1, 1.0, -0.05]);
        let q = exp(&Vector3::new(0.05, 0.2, -0.1));
        let r = Nue::new(30.0, 800.0, -10.0);
        let beam = Body(Vector3::new(0.05, -1.0, 0.02).normalize());
        // Errors of 10 m and 0.01 rad per axis, position and attitude correlated.
        let mut l = Matrix6::<f64>::zeros();
        for i in 0..3 {
            l[(i, i)] = 10.0;
            l[(3 + i, 3 + i)] = 0.01;
            l[(3 + i, i)] = 0.004;
        }
        let p_z = l * l.transpose();
        let (mean, variance) = altimeter_second_order(&plane, &r, &BodyToNue::of(&q), &beam, &p_z);
        let linear = altimeter(&plane, &r, &BodyToNue::of(&q), &beam).unwrap();
        let mut rng = rand_chacha::ChaCha12Rng::seed_from_u64(7);
        let draws = 200_000;
        let (mut sum, mut sum2) = (0.0, 0.0);
        for _ in 0..draws {
            let e: [f64; 6] = std::array::from_fn(|_| StandardNormal.sample(&mut rng));
            let z = l * nalgebra::Vector6::from_column_slice(&e);
            let dr = Vector3::new(z[0], z[1], z[2]);
            let dt = Vector3::new(z[3], z[4], z[5]);
            let turned = BodyToNue::of(&super::super::rotation::mul(&q, &exp(&dt)));
            let exact = altimeter(&plane, &(r + Nue(dr)), &turned, &beam)
                .unwrap()
                .value;
            let first: f64 = (0..3)
                .map(|k| linear.jacobian[IR + k] * dr[k] + linear.jacobian[THETA + k] * dt[k])
                .sum();
            let rest = exact - linear.value - first;
            sum += rest;
            sum2 += rest * rest;
        }
        let sample_mean = sum / draws as f64;
        let sample_variance = sum2 / draws as f64 - sample_mean * sample_mean;
        // Standard error of the mean: sqrt(variance / draws), about 0.2 % of the mean here.
        assert!(mean > 0.05, "{mean}");
        assert!(
            (sample_mean - mean).abs() < 0.01 * mean,
            "{sample_mean} vs {mean}"
        );
        assert!(
            (sample_variance - variance).abs() < 0.05 * variance,
            "{sample_variance} vs {variance}"
        );
    }

    /// The Jacobians against central differences of the models themselves.
    #[test]
    fn the_jacobians_are_the_derivatives_of_the_models() {
        let plane = Plane::new(20.0, &[0.1, 1.0, -0.05]);
        let q = exp(&Vector3::new(0.1, 0.2, -0.15));
        let r = Nue::new(30.0, 500.0, -10.0);
        let v = Nue::new(2.0, -8.0, 1.0);
        let beam = Body(Vector3::new(0.3, -0.9, 0.1).normalize());
        let alt = altimeter(&plane, &r, &BodyToNue::of(&q), &beam).unwrap();
        let vel = velocimeter(&v, &BodyToNue::of(&q), &beam);
        let eps = 1e-6;
        for k in 0..3 {
            let mut e = Vector3::zeros();
            e[k] = eps;
            let up = |d: Vector3<f64>| BodyToNue::of(&super::super::rotation::mul(&q, &exp(&d)));
            let d_alt_r = (altimeter(&plane, &(r + Nue(e)), &BodyToNue::of(&q), &beam)
                .unwrap()
                .value
                - altimeter(&plane, &(r - Nue(e)), &BodyToNue::of(&q), &beam)
                    .unwrap()
                    .value)
                / (2.0 * eps);
            let d_alt_t = (altimeter(&plane, &r, &up(e), &beam).unwrap().value
                - altimeter(&plane, &r, &up(-e), &beam).unwrap().value)
                / (2.0 * eps);
            let d_vel_v = (velocimeter(&(v + Nue(e)), &BodyToNue::of(&q), &beam).value
                - velocimeter(&(v - Nue(e)), &BodyToNue::of(&q), &beam).value)
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
