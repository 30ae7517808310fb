//! The 27 x 27 covariance and the two operations the filter does on it, written for its
//! structure so that a debug build stays fast: the propagation `F P F^T + Q` with a sparse
//! `F`, and the Joseph-form update for one scalar measurement in O(n^2).
//!
//! Error-state order: `dr` (0..3, m, NUE), `dv` (3..6, m/s, NUE), `dtheta` (6..9, rad, body
//! axes), `db_a` (9..12, m/s2), `db_g` (12..15, rad/s); then the IMU's calibration errors,
//! `ds_a` (15..18, accelerometer scale factor), `ds_g` (18..21, gyro scale factor), `dmu_a`
//! (21..24, rad, accelerometer misalignment), `dmu_g` (24..27, rad, gyro misalignment).
// Matrix formulas read best with their indices.
#![allow(clippy::needless_range_loop)]
pub const N: usize = 27;
pub const R: usize = 0;
pub const V: usize = 3;
pub const THETA: usize = 6;
pub const BA: usize = 9;
pub const BG: usize = 12;
pub const SA: usize = 15;
pub const SG: usize = 18;
pub const MA: usize = 21;
pub const MG: usize = 24;
/// The navigation states and biases: `covariance_diag` (the calibration states follow).
pub const NAVIGATION: usize = 15;

pub type Matrix = [[f64; N]; N];
pub type Row = [f64; N];

/// A sparse `F`: its non-zero entries `(i, j, value)`.
pub type Sparse = Vec<(usize, usize, f64)>;

/// `F P F^T + Q`.
pub fn propagate(p: &Matrix, f: &Sparse, q: &Matrix) -> Matrix {
    let mut fp = [[0.0; N]; N];
    for &(i, k, v) in f {
        for j in 0..N {
            fp[i][j] += v * p[k][j];
        }
    }
    let mut out = *q;
    for &(j, k, v) in f {
        for (i, row) in out.iter_mut().enumerate() {
            row[j] += fp[i][k] * v;
        }
    }
    symmetrize(&mut out);
    out
}

pub fn symmetrize(p: &mut Matrix) {
    for i in 0..N {
        for j in 0..i {
            let m = 0.5 * (p[i][j] + p[j][i]);
            p[i][j] = m;
            p[j][i] = m;
        }
    }
}

/// The innovation variance `h P h^T + r` and the gain `K = P h^T / s` of one scalar
/// measurement with the Jacobian row `h` and noise variance `r`.
pub fn gain(p: &Matrix, h: &Row, r: f64) -> (f64, Row) {
    let mut ph = [0.0; N];
    for i in 0..N {
        ph[i] = (0..N).map(|j| p[i][j] * h[j]).sum();
    }
    let s = (0..N).map(|i| h[i] * ph[i]).sum::<f64>() + r;
    (s, ph.map(|x| x / s))
}

/// Joseph form `(I - K h) P (I - K h)^T + K r K^T`, which stays symmetric positive
/// semi-definite under rounding, expanded for a scalar: with `u = P h^T`,
/// `P - K u^T - u K^T + (h P h^T + r) K K^T`.
pub fn joseph(p: &Matrix, h: &Row, k: &Row, r: f64) -> Matrix {
    let mut u = [0.0; N];
    for i in 0..N {
        u[i] = (0..N).map(|j| p[i][j] * h[j]).sum();
    }
    let hph: f64 = (0..N).map(|i| h[i] * u[i]).sum();
    let s = hph + r;
    let mut out = *p;
    for i in 0..N {
        for j in 0..N {
            out[i][j] += -k[i] * u[j] - u[i] * k[j] + s * k[i] * k[j];
        }
    }
    symmetrize(&mut out);
    out
}

/// `G P G^T` for a `G` that is the identity except for a 3 x 3 block at (`at`, `at`).
pub fn transform_block(p: &Matrix, at: usize, g: &nalgebra::Matrix3<f64>) -> Matrix {
    let mut f: Sparse = Vec::with_capacity(N + 6);
    for i in 0..N {
        if !(at..at + 3).contains(&i) {
            f.push((i, i, 1.0));
        }
    }
    for a in 0..3 {
        for b in 0..3 {
            f.push((at + a, at + b, g[(a, b)]));
        }
    }
    propagate(p, &f, &[[0.0; N]; N])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn example() -> Matrix {
        let mut p = [[0.0; N]; N];
        for i in 0..N {
            for j in 0..N {
                p[i][j] =
                    0.1 / (1.0 + (i as f64 - j as f64).abs()) + if i == j { 1.0 } else { 0.0 };
            }
        }
        p
    }

    #[test]
    fn the_expanded_joseph_form_equals_the_matrix_product() {
        let p = example();
        let h: Row = std::array::from_fn(|i| libm::sin(i as f64 * 0.37));
        let r = 0.3;
        let (_, k) = gain(&p, &h, r);
        // (I - K h) P (I - K h)^T + K r K^T, multiplied out plainly.
        let a: Matrix = std::array::from_fn(|i| {
            std::array::from_fn(|j| if i == j { 1.0 } else { 0.0 } - k[i] * h[j])
        });
        let mut expected = [[0.0; N]; N];
        for i in 0..N {
            for j in 0..N {
                let mut s = r * k[i] * k[j];
                for m in 0..N {
                    for n in 0..N {
                        s += a[i][m] * p[m][n] * a[j][n];
                    }
                }
                expected[i][j] = s;
            }
        }
        let got = joseph(&p, &h, &k, r);
        for i in 0..N {
            for j in 0..N {
                assert!((got[i][j] - expected[i][j]).abs() < 1e-14, "{i} {j}");
            }
        }
    }

    #[test]
    fn the_sparse_propagation_equals_the_dense_product() {
        let p = example();
        let f: Sparse = vec![
            (0, 0, 1.0),
            (0, 3, 0.5),
            (1, 1, 2.0),
            (4, 2, -0.3),
            (14, 14, 1.0),
            (26, 20, 0.7),
        ];
        let mut dense = [[0.0; N]; N];
        for &(i, j, v) in &f {
            dense[i][j] += v;
        }
        let got = propagate(&p, &f, &[[0.0; N]; N]);
        for i in 0..N {
            for j in 0..N {
                let mut s = 0.0;
                for m in 0..N {
                    for n in 0..N {
                        s += dense[i][m] * p[m][n] * dense[j][n];
                    }
                }
                assert!((got[i][j] - s).abs() < 1e-14, "{i} {j}");
            }
        }
    }
}
