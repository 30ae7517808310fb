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

/// `v` divided by its length, or `None` for a vector too short to have a direction.
pub fn unit(v: &[f64; 3]) -> Option<Vector3<f64>> {
    let v = Vector3::from(*v);
    let n = v.norm();
    (n.is_finite() && n > 1e-9).then(|| v / n)
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
}
