//! Rotation by a unit quaternion `q_body_to_nue` = (w, x, y, z), scalar first, Hamilton:
//! `v_nue = q v_body q*` (docs/interface.md).
use nalgebra::{Matrix3, Vector3};

/// The direction cosine matrix of `q`: `v_nue = R v_body`. `q` must be unit.
pub fn body_to_nue(q: &[f64; 4]) -> Matrix3<f64> {
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

/// `v` divided by its length, or `None` for a vector too short to have a direction (or not
/// finite). A finite vector whose squared length overflows (a component above about 1e154)
/// is scaled by its largest component first: it has a direction like any other.
pub fn unit(v: &[f64; 3]) -> Option<Vector3<f64>> {
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
    fn a_quarter_turn_about_north_takes_body_y_to_east() {
        let h = libm::sqrt(0.5);
        let r = body_to_nue(&[h, h, 0.0, 0.0]);
        let v = r * Vector3::new(0.0, 1.0, 0.0);
        assert!((v - Vector3::new(0.0, 0.0, 1.0)).norm() < 1e-15, "{v}");
    }

    /// Found by the robustness suite's review of the parameter validation: a beam of
    /// (1e200, -1e200, 0) has a direction, but its squared length overflowed and it was
    /// refused as "below 1e-9".
    #[test]
    fn a_vector_whose_squared_length_overflows_has_a_direction() {
        let u = unit(&[1e200, -1e200, 0.0]).expect("a direction");
        let h = libm::sqrt(0.5);
        assert!((u - Vector3::new(h, -h, 0.0)).norm() < 1e-15, "{u}");
        let u = unit(&[0.0, f64::MAX, f64::MAX]).expect("a direction");
        assert!((u - Vector3::new(0.0, h, h)).norm() < 1e-15, "{u}");
        assert_eq!(unit(&[1e-10, 0.0, 0.0]), None);
        assert_eq!(unit(&[f64::INFINITY, 0.0, 0.0]), None);
    }
}
