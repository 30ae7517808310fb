//! Quaternions `q_body_to_nue` = (w, x, y, z), scalar first, Hamilton (`v_nue = q v_body q*`,
//! docs/interface.md), their rotation matrices and the exponential of a rotation vector.
use nalgebra::{Matrix3, Vector3};

pub type Quaternion = [f64; 4];

/// The direction cosine matrix of the unit `q`: `v_nue = R v_body`.
pub fn matrix(q: &Quaternion) -> Matrix3<f64> {
    let [w, x, y, z] = *q;
    Matrix3::new(
        1.0 - 2.0 * (y * y + z * z),
        2.0 * (x * y - w * z),
        2.0 * (x * z + w * y),
        2.0 * (x * y + w * z),
        1.0 - 2.0 * (x * x + z * z),
        2.0 * (y * z - w * x),
        2.0 * (x * z - w * y),
        2.0 * (y * z + w * x),
        1.0 - 2.0 * (x * x + y * y),
    )
}

/// The Hamilton product `a b`.
pub fn mul(a: &Quaternion, b: &Quaternion) -> Quaternion {
    [
        a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
        a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
        a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
        a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0],
    ]
}

/// The unit quaternion of the rotation vector `phi` (angle `|phi|` about `phi / |phi|`).
pub fn exp(phi: &Vector3<f64>) -> Quaternion {
    let angle = phi.norm();
    // Below 1e-8 rad, sin(a/2)/a = 1/2 - a^2/48 is 1/2 to the last bit.
    let (half_sin_over_angle, cos) = if angle < 1e-8 {
        (0.5, 1.0 - angle * angle / 8.0)
    } else {
        let (s, c) = libm::sincos(angle / 2.0);
        (s / angle, c)
    };
    [
        cos,
        half_sin_over_angle * phi[0],
        half_sin_over_angle * phi[1],
        half_sin_over_angle * phi[2],
    ]
}

pub fn normalized(q: &Quaternion) -> Quaternion {
    let n = libm::sqrt(q.iter().map(|x| x * x).sum::<f64>());
    q.map(|x| x / n)
}

/// `v` divided by its length, for a finite `v` of non-zero length (validated parameters). A
/// vector whose squared length overflows (a component above about 1e154) is scaled by its
/// largest component first, so that its direction is kept rather than divided by infinity
/// to zero.
pub fn unit(v: &Vector3<f64>) -> Vector3<f64> {
    let n = v.norm();
    if n.is_finite() {
        return v / n;
    }
    let scaled = v / v.amax();
    scaled / scaled.norm()
}

pub fn norm(q: &Quaternion) -> f64 {
    libm::sqrt(q.iter().map(|x| x * x).sum::<f64>())
}

/// `[v]x`: `skew(v) u = v x u`.
pub fn skew(v: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -v[2], v[1], v[2], 0.0, -v[0], -v[1], v[0], 0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_exponential_rotates_as_its_matrix() {
        let phi = Vector3::new(0.3, -0.2, 0.5);
        let q = exp(&phi);
        assert!((norm(&q) - 1.0).abs() < 1e-15);
        // R(exp(phi)) phi = phi, and a small rotation is I + [phi]x to first order.
        assert!((matrix(&q) * phi - phi).norm() < 1e-15);
        let small = Vector3::new(1e-5, 2e-5, -1e-5);
        let d = matrix(&exp(&small)) - (Matrix3::identity() + skew(&small));
        assert!(d.norm() < 1e-9, "{d}");
    }
}
