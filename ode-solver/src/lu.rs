//! Dense LU factorisation with partial pivoting, for BDF's Newton matrix I - c J.
//!
//! Written out rather than taken from a linear-algebra crate: the matrices are small (one
//! row per continuous state of an FMU), and the Model Exchange master then builds no
//! linear-algebra library at all.

/// A square matrix, row-major.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Matrix {
    n: usize,
    a: Vec<f64>,
}

impl Matrix {
    pub fn zeros(n: usize) -> Self {
        Self {
            n,
            a: vec![0.0; n * n],
        }
    }

    pub fn size(&self) -> usize {
        self.n
    }

    pub fn get(&self, row: usize, col: usize) -> f64 {
        self.a[row * self.n + col]
    }

    pub fn set(&mut self, row: usize, col: usize, v: f64) {
        self.a[row * self.n + col] = v;
    }
}

/// P A = L U, L unit lower triangular, both stored in one matrix.
#[derive(Debug)]
pub(crate) struct Lu {
    lu: Matrix,
    /// Row i of P A is row perm[i] of A.
    perm: Vec<usize>,
}

impl Lu {
    /// None if a pivot is zero or not finite: Newton then treats the step as failed, which
    /// shrinks it, rather than solving with a meaningless factorisation.
    pub fn factor(mut m: Matrix) -> Option<Self> {
        let n = m.n;
        let mut perm: Vec<usize> = (0..n).collect();
        for k in 0..n {
            let (p, pivot) = (k..n)
                .map(|i| (i, m.get(i, k).abs()))
                .fold(
                    (k, -1.0),
                    |best, cur| if cur.1 > best.1 { cur } else { best },
                );
            if !(pivot > 0.0 && pivot.is_finite()) {
                return None;
            }
            if p != k {
                for j in 0..n {
                    m.a.swap(k * n + j, p * n + j);
                }
                perm.swap(k, p);
            }
            let d = m.get(k, k);
            for i in k + 1..n {
                let l = m.get(i, k) / d;
                m.set(i, k, l);
                if l != 0.0 {
                    for j in k + 1..n {
                        let v = m.get(i, j) - l * m.get(k, j);
                        m.set(i, j, v);
                    }
                }
            }
        }
        Some(Self { lu: m, perm })
    }

    /// Solves A x = b in place; `work` is scratch of the same length.
    pub fn solve(&self, b: &mut [f64], work: &mut [f64]) {
        let n = self.lu.n;
        for (w, &p) in work.iter_mut().zip(&self.perm) {
            *w = b[p];
        }
        for i in 0..n {
            let s: f64 = (0..i).map(|j| self.lu.get(i, j) * work[j]).sum();
            work[i] -= s;
        }
        for i in (0..n).rev() {
            let s: f64 = (i + 1..n).map(|j| self.lu.get(i, j) * work[j]).sum();
            work[i] = (work[i] - s) / self.lu.get(i, i);
        }
        b.copy_from_slice(work);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn from_rows(rows: &[&[f64]]) -> Matrix {
        let mut m = Matrix::zeros(rows.len());
        for (i, r) in rows.iter().enumerate() {
            for (j, v) in r.iter().enumerate() {
                m.set(i, j, *v);
            }
        }
        m
    }

    #[test]
    fn solves_a_system_that_needs_pivoting() {
        // A zero leading entry: without row exchanges the first pivot would be 0.
        let a = from_rows(&[&[0.0, 2.0, 1.0], &[1.0, 1.0, 0.0], &[3.0, 0.0, 1.0]]);
        let x = [1.0, -2.0, 0.5];
        let mut b: Vec<f64> = (0..3)
            .map(|i| (0..3).map(|j| a.get(i, j) * x[j]).sum())
            .collect();
        let lu = Lu::factor(a).unwrap();
        let mut work = vec![0.0; 3];
        lu.solve(&mut b, &mut work);
        for (got, want) in b.iter().zip(x) {
            assert!((got - want).abs() < 1e-14, "{got} vs {want}");
        }
    }

    #[test]
    fn singular_and_non_finite_matrices_are_refused() {
        assert!(Lu::factor(from_rows(&[&[1.0, 2.0], &[2.0, 4.0]])).is_none());
        assert!(Lu::factor(from_rows(&[&[f64::NAN, 0.0], &[0.0, 1.0]])).is_none());
        assert!(Lu::factor(Matrix::zeros(0)).is_some());
    }
}
