//! BDF's history as backward differences on an equally spaced grid: row 0 is y_n, row j the
//! j-th backward difference of y at t_n, t_n - h, ..., t_n - j h. The rows 0..=k determine
//! the degree-k polynomial through those points (Newton's backward-difference form), so a
//! change of step size is a change of grid for the same polynomial (Shampine & Reichelt,
//! "The MATLAB ODE Suite", SIAM J. Sci. Comput. 18 (1997), section 2.1).

use crate::bdf::MAX_ORDER;

/// A polynomial in backward-difference form: rows 0..=order on the grid of spacing h whose
/// newest point is t_ref.
#[derive(Clone, Debug)]
pub(crate) struct Poly {
    pub d: Vec<Vec<f64>>,
    pub order: usize,
    pub t_ref: f64,
    pub h: f64,
}

impl Poly {
    /// The value at t: sum over j of D_j * prod_{m<j} (t - (t_ref - m h)) / ((m + 1) h).
    pub fn at(&self, t: f64, out: &mut [f64]) {
        out.copy_from_slice(&self.d[0]);
        let mut p = 1.0;
        for (j, row) in self.d.iter().enumerate().take(self.order + 1).skip(1) {
            let m = (j - 1) as f64;
            p *= (t - (self.t_ref - m * self.h)) / ((m + 1.0) * self.h);
            for (o, dj) in out.iter_mut().zip(row) {
                *o += p * dj;
            }
        }
    }
}

/// The history on a new grid: `y_t` at t, the polynomial at t - h, ..., t - order h, as
/// differences in rows 0..=order of `d`; the rows above are cleared.
pub(crate) fn regrid(poly: &Poly, t: f64, y_t: &[f64], h: f64, d: &mut [Vec<f64>]) {
    let values: Vec<Vec<f64>> = (0..=poly.order)
        .map(|m| {
            let mut v = y_t.to_vec();
            if m > 0 {
                poly.at(t - m as f64 * h, &mut v);
            }
            v
        })
        .collect();
    for row in d.iter_mut() {
        row.fill(0.0);
    }
    from_values(&values, d);
}

/// Rows 0..=order from the values y(t_ref - m h), m = 0..=order: the inverse of `Poly::at`
/// on the grid.
pub(crate) fn from_values(values: &[Vec<f64>], d: &mut [Vec<f64>]) {
    let order = values.len() - 1;
    let mut a = values.to_vec();
    // After pass j, a[m] (m >= j) is the j-th difference at the (m - j)-th newest point, so
    // a[j] is the one at the newest point.
    for j in 1..=order {
        for m in (j..=order).rev() {
            for i in 0..a[m].len() {
                a[m][i] = a[m - 1][i] - a[m][i];
            }
        }
    }
    for (row, v) in d.iter_mut().zip(a) {
        *row = v;
    }
}

/// Re-expresses rows 0..=order for the grid spacing `factor` times the current one, keeping
/// the polynomial: D <- (R(factor) U)^T D, with U = R(1).
pub(crate) fn rescale(d: &mut [Vec<f64>], order: usize, factor: f64) {
    let r = grid_change(order, factor);
    let u = grid_change(order, 1.0);
    let k = order + 1;
    let mut ru = [[0.0; MAX_ORDER + 1]; MAX_ORDER + 1];
    for i in 0..k {
        for j in 0..k {
            ru[i][j] = (0..k).map(|m| r[i][m] * u[m][j]).sum();
        }
    }
    let n = d[0].len();
    let old: Vec<Vec<f64>> = d[..k].to_vec();
    for (i, row) in d.iter_mut().enumerate().take(k) {
        for x in 0..n {
            row[x] = (0..k).map(|j| ru[j][i] * old[j][x]).sum();
        }
    }
}

/// R(f)_{ij} = prod_{m=1..=i} (m - 1 - f j) / m, R_{0j} = 1: the map from differences on one
/// grid to differences on the grid with spacing scaled by f.
fn grid_change(order: usize, factor: f64) -> [[f64; MAX_ORDER + 1]; MAX_ORDER + 1] {
    let mut r = [[0.0; MAX_ORDER + 1]; MAX_ORDER + 1];
    r[0] = [1.0; MAX_ORDER + 1];
    for i in 1..=order {
        let above = r[i - 1];
        for (j, (v, a)) in r[i].iter_mut().zip(above).enumerate().take(order + 1) {
            *v = a * (i as f64 - 1.0 - factor * j as f64) / i as f64;
        }
    }
    r
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two components: a cubic and a line.
    fn y(t: f64) -> Vec<f64> {
        vec![1.0 - 2.0 * t + 0.5 * t * t - 0.25 * t * t * t, 3.0 + t]
    }

    fn poly(t_ref: f64, h: f64, order: usize) -> Poly {
        Poly {
            d: grid(t_ref, h, order),
            order,
            t_ref,
            h,
        }
    }

    fn grid(t_ref: f64, h: f64, order: usize) -> Vec<Vec<f64>> {
        let values: Vec<Vec<f64>> = (0..=order).map(|m| y(t_ref - m as f64 * h)).collect();
        let mut d = vec![vec![0.0; 2]; MAX_ORDER + 3];
        from_values(&values, &mut d);
        d
    }

    fn close(a: &[f64], b: &[f64], eps: f64) -> bool {
        a.iter().zip(b).all(|(x, y)| (x - y).abs() <= eps)
    }

    #[test]
    fn a_cubic_is_reproduced_between_and_beyond_its_points() {
        let p = poly(2.0, 0.1, 3);
        let mut out = vec![0.0; 2];
        for t in [2.0, 1.95, 1.7, 2.3] {
            p.at(t, &mut out);
            assert!(close(&out, &y(t), 1e-12), "{t}: {out:?}");
        }
        // The first difference of the line is its slope times the spacing.
        assert!((p.d[1][1] - 0.1).abs() < 1e-14);
    }

    #[test]
    fn regridding_moves_the_grid_along_the_polynomial() {
        let p = poly(2.0, 0.1, 3);
        let mut d = vec![vec![7.0; 2]; MAX_ORDER + 3];
        regrid(&p, 1.93, &y(1.93), 0.05, &mut d);
        let direct = grid(1.93, 0.05, 3);
        for j in 0..=3 {
            assert!(close(&d[j], &direct[j], 1e-12), "row {j}");
        }
        assert!(d[4..].iter().all(|row| row.iter().all(|v| *v == 0.0)));
    }

    #[test]
    fn rescaling_keeps_the_polynomial() {
        for factor in [0.2, 0.5, 1.7, 10.0] {
            let mut d = grid(2.0, 0.1, 3);
            rescale(&mut d, 3, factor);
            let direct = grid(2.0, 0.1 * factor, 3);
            for j in 0..=3 {
                // Re-gridding by f amplifies rounding by about f^order.
                assert!(close(&d[j], &direct[j], 1e-11), "factor {factor}, row {j}");
            }
        }
    }
}
