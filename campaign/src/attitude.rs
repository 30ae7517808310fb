//! The few quaternion operations the attitude dispersion needs, scalar first (`[w, x, y, z]`)
//! like `q0_body_to_nue` in the contract, Hamilton product. The harness talks to the FMUs
//! through scalars only, so it does not pull in a linear-algebra crate for four functions.

/// A rotation as a unit quaternion `[w, x, y, z]`.
pub type Quat = [f64; 4];

/// Hamilton product `a ⊗ b` (apply `b` first, then `a`, when rotating vectors).
pub fn multiply(a: Quat, b: Quat) -> Quat {
    let [aw, ax, ay, az] = a;
    let [bw, bx, by, bz] = b;
    [
        aw * bw - ax * bx - ay * by - az * bz,
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
    ]
}

/// Rotation by `angle_rad` (right hand) about the unit vector `axis`.
pub fn from_axis_angle(axis: [f64; 3], angle_rad: f64) -> Quat {
    let (s, c) = (0.5 * angle_rad).sin_cos();
    [c, s * axis[0], s * axis[1], s * axis[2]]
}

/// `q ⊗ [0, v] ⊗ q*`: `v` rotated by `q` (for `q_body_to_nue`, body to NUE).
pub fn rotate(q: Quat, v: [f64; 3]) -> [f64; 3] {
    let conjugate = [q[0], -q[1], -q[2], -q[3]];
    let [_, x, y, z] = multiply(multiply(q, [0.0, v[0], v[1], v[2]]), conjugate);
    [x, y, z]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: [f64; 3], b: [f64; 3]) -> bool {
        a.iter().zip(&b).all(|(x, y)| (x - y).abs() < 1e-12)
    }

    /// Rotation matrix of a unit quaternion, from the textbook formula (independent of
    /// [`multiply`]).
    fn matrix(q: Quat) -> [[f64; 3]; 3] {
        let [w, x, y, z] = q;
        [
            [
                1.0 - 2.0 * (y * y + z * z),
                2.0 * (x * y - w * z),
                2.0 * (x * z + w * y),
            ],
            [
                2.0 * (x * y + w * z),
                1.0 - 2.0 * (x * x + z * z),
                2.0 * (y * z - w * x),
            ],
            [
                2.0 * (x * z - w * y),
                2.0 * (y * z + w * x),
                1.0 - 2.0 * (x * x + y * y),
            ],
        ]
    }

    #[test]
    fn a_quarter_turn_about_north_takes_up_to_east() {
        let q = from_axis_angle([1.0, 0.0, 0.0], std::f64::consts::FRAC_PI_2);
        assert!(close(rotate(q, [0.0, 1.0, 0.0]), [0.0, 0.0, 1.0]));
        assert!(close(rotate(q, [1.0, 0.0, 0.0]), [1.0, 0.0, 0.0]));
    }

    #[test]
    fn rotate_agrees_with_the_rotation_matrix_and_products_compose() {
        let a = from_axis_angle([0.6, 0.0, 0.8], 0.7);
        let b = from_axis_angle([0.0, 0.6, -0.8], -2.1);
        let v = [0.3, -1.2, 2.5];
        for q in [a, b, multiply(a, b)] {
            let m = matrix(q);
            let expected = [0, 1, 2].map(|i| (0..3).map(|j| m[i][j] * v[j]).sum::<f64>());
            assert!(close(rotate(q, v), expected));
        }
        assert!(close(rotate(multiply(a, b), v), rotate(a, rotate(b, v))));
        let ab = multiply(a, b);
        let norm = ab.iter().map(|c| c * c).sum::<f64>().sqrt();
        assert!((norm - 1.0).abs() < 1e-15);
    }
}
