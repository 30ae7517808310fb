//! The attitude quaternion of every FMU interface (docs/interface.md): Hamilton product,
//! scalar first, `q_body_to_nue = [q0, q1, q2, q3]` rotating body vectors into NUE,
//! `v_nue = q ⊗ v_body ⊗ q*`; identity = upright (body x North, y Up, z East). Kinematics
//! `q' = ½ q ⊗ [0, omega_body]`, rates in body axes.
//!
//! nalgebra stores a quaternion with the scalar *last* (`coords = [i, j, k, w]`) although
//! `Quaternion::new(w, i, j, k)` takes it first: [`to_nalgebra`] and [`from_nalgebra`] are
//! where a scalar-first array meets a nalgebra quaternion.
use nalgebra::{Matrix3, Vector3};

/// `[q0, q1, q2, q3]`, scalar first, as the FMUs exchange an attitude.
pub type Quaternion = [f64; 4];

/// A scalar-first array as a nalgebra quaternion, not normalised.
#[inline]
pub fn to_nalgebra(q: &Quaternion) -> nalgebra::Quaternion<f64> {
    nalgebra::Quaternion::new(q[0], q[1], q[2], q[3])
}

/// A nalgebra quaternion as a scalar-first array.
#[inline]
pub fn from_nalgebra(q: &nalgebra::Quaternion<f64>) -> Quaternion {
    [q.w, q.i, q.j, q.k]
}

/// The direction cosine matrix of the unit `q`: `v_nue = R v_body`.
#[inline]
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
#[inline]
pub fn mul(a: &Quaternion, b: &Quaternion) -> Quaternion {
    [
        a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
        a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
        a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
        a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0],
    ]
}

/// The unit quaternion of the rotation vector `phi` (angle `|phi|` about `phi / |phi|`).
#[inline]
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

#[inline]
pub fn norm(q: &Quaternion) -> f64 {
    libm::sqrt(q.iter().map(|x| x * x).sum::<f64>())
}

#[inline]
pub fn normalized(q: &Quaternion) -> Quaternion {
    let n = norm(q);
    q.map(|x| x / n)
}

/// `[v]x`: `skew(v) u = v x u`.
#[inline]
pub fn skew(v: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -v[2], v[1], v[2], 0.0, -v[0], -v[1], v[0], 0.0)
}

/// `v` divided by its length, for a finite `v` of non-zero length. A vector whose squared
/// length overflows (a component above about 1e154) is scaled by its largest component
/// first, so that its direction is kept rather than divided by infinity to zero.
#[inline]
pub fn unit(v: &Vector3<f64>) -> Vector3<f64> {
    let n = v.norm();
    if n.is_finite() {
        return v / n;
    }
    let scaled = v / v.amax();
    scaled / scaled.norm()
}

/// As [`unit`] for any `v`: `None` for a vector too short to have a direction (norm at or
/// below 1e-9) or not finite.
#[inline]
pub fn direction(v: &[f64; 3]) -> Option<Vector3<f64>> {
    let v = Vector3::from(*v);
    if !v.iter().all(|x| x.is_finite()) {
        return None;
    }
    let n = v.norm();
    if n.is_finite() {
        return (n > 1e-9).then(|| v / n);
    }
    let scaled = v / v.amax();
    Some(scaled / scaled.norm())
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

    #[test]
    fn a_quarter_turn_about_north_takes_body_y_to_east() {
        let h = libm::sqrt(0.5);
        let v = matrix(&[h, h, 0.0, 0.0]) * Vector3::new(0.0, 1.0, 0.0);
        assert!((v - Vector3::new(0.0, 0.0, 1.0)).norm() < 1e-15, "{v}");
    }

    #[test]
    fn the_matrix_is_the_sandwich_product_and_the_scalar_stays_first() {
        let q = normalized(&[0.9, 0.1, -0.3, 0.2]);
        let v = Vector3::new(0.3, -1.2, 2.0);
        let nq = to_nalgebra(&q);
        assert_eq!(nq.w, q[0]);
        assert_eq!(nq.coords[3], q[0], "nalgebra stores w last");
        assert_eq!(from_nalgebra(&nq), q);
        let sandwich = nq * nalgebra::Quaternion::from_imag(v) * nq.conjugate();
        assert!((matrix(&q) * v - sandwich.imag()).norm() < 1e-14);
        let product = from_nalgebra(&(nq * nq));
        for (a, b) in product.iter().zip(mul(&q, &q)) {
            assert!((a - b).abs() < 1e-15, "{product:?}");
        }
    }

    /// Found by the robustness suite's review of the parameter validation: a beam of
    /// (1e200, -1e200, 0) has a direction, but its squared length overflowed and it was
    /// refused as "below 1e-9".
    #[test]
    fn a_vector_whose_squared_length_overflows_has_a_direction() {
        let u = direction(&[1e200, -1e200, 0.0]).expect("a direction");
        let h = libm::sqrt(0.5);
        assert!((u - Vector3::new(h, -h, 0.0)).norm() < 1e-15, "{u}");
        let u = direction(&[0.0, f64::MAX, f64::MAX]).expect("a direction");
        assert!((u - Vector3::new(0.0, h, h)).norm() < 1e-15, "{u}");
        assert_eq!(unit(&Vector3::new(0.0, 1e300, 1e300)), u);
        assert_eq!(direction(&[1e-10, 0.0, 0.0]), None);
        assert_eq!(direction(&[f64::INFINITY, 0.0, 0.0]), None);
    }
}
