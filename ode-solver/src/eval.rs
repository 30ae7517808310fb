//! Every call into the caller's system goes through here: counted, checked for non-finite
//! values, its errors turned into `SolverError`, so the methods can use `?` and no NaN ever
//! reaches their arithmetic from the system.

use crate::lu::Matrix;
use crate::{OdeSystem, SolverError};

/// Calls into the system over the integrator's life, across restarts.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Counts {
    pub rhs: u64,
    pub jacobians: u64,
    /// Of `jacobians`, the system's own.
    pub system_jacobians: u64,
    pub indicators: u64,
}

/// The system, lent for one integrator call, and the counters it is charged to.
pub(crate) struct Eval<'a> {
    system: &'a mut dyn OdeSystem,
    counts: &'a mut Counts,
}

impl<'a> Eval<'a> {
    pub fn new(system: &'a mut dyn OdeSystem, counts: &'a mut Counts) -> Self {
        Self { system, counts }
    }

    pub fn rhs(&mut self, t: f64, x: &[f64], dx: &mut [f64]) -> Result<(), SolverError> {
        self.counts.rhs += 1;
        self.system
            .derivatives(t, x, dx)
            .map_err(|message| SolverError::System { t, message })?;
        match dx.iter().position(|v| !v.is_finite()) {
            Some(index) => Err(SolverError::NonFiniteDerivative { t, index }),
            None => Ok(()),
        }
    }

    pub fn indicators(&mut self, t: f64, x: &[f64], z: &mut [f64]) -> Result<(), SolverError> {
        if z.is_empty() {
            return Ok(());
        }
        self.counts.indicators += 1;
        self.system
            .indicators(t, x, z)
            .map_err(|message| SolverError::System { t, message })?;
        match z.iter().position(|v| !v.is_finite()) {
            Some(index) => Err(SolverError::NonFiniteIndicator { t, index }),
            None => Ok(()),
        }
    }

    /// df/dx at (t, x): the system's own when it has one, else by forward differences, one
    /// column per state (n + 1 derivative calls).
    pub fn jacobian(&mut self, t: f64, x: &[f64], jac: &mut Matrix) -> Result<(), SolverError> {
        let n = x.len();
        debug_assert_eq!(jac.size(), n);
        self.counts.jacobians += 1;
        let mut own = vec![0.0; n * n];
        if self
            .system
            .jacobian(t, x, &mut own)
            .map_err(|message| SolverError::System { t, message })?
        {
            if let Some(index) = own.iter().position(|v| !v.is_finite()) {
                return Err(SolverError::System {
                    t,
                    message: format!(
                        "the system's Jacobian has a non-finite entry (row {}, column {})",
                        index % n,
                        index / n
                    ),
                });
            }
            self.counts.system_jacobians += 1;
            for j in 0..n {
                for i in 0..n {
                    jac.set(i, j, own[i + j * n]);
                }
            }
            return Ok(());
        }
        let mut f0 = vec![0.0; n];
        self.rhs(t, x, &mut f0)?;
        let mut xp = x.to_vec();
        let mut fp = vec![0.0; n];
        for j in 0..n {
            // sqrt(eps) balances truncation against cancellation; scaled by the state's
            // magnitude so that large states (h = 800 m) are not under-perturbed.
            let sigma = f64::EPSILON.sqrt() * (1.0 + x[j].abs());
            xp[j] = x[j] + sigma;
            // The perturbation that x + sigma actually represents, not sigma itself.
            let delta = xp[j] - x[j];
            self.rhs(t, &xp, &mut fp)?;
            xp[j] = x[j];
            for i in 0..n {
                jac.set(i, j, (fp[i] - f0[i]) / delta);
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// x0' = x0 * x1, x1' = 3 x0 + 800: J = [[x1, x0], [3, 0]].
    struct Quadratic;

    impl OdeSystem for Quadratic {
        fn state_count(&self) -> usize {
            2
        }
        fn indicator_count(&self) -> usize {
            0
        }
        fn derivatives(&mut self, _t: f64, x: &[f64], dx: &mut [f64]) -> Result<(), String> {
            dx[0] = x[0] * x[1];
            dx[1] = 3.0 * x[0] + 800.0;
            Ok(())
        }
        fn indicators(&mut self, _t: f64, _x: &[f64], _z: &mut [f64]) -> Result<(), String> {
            Ok(())
        }
    }

    #[test]
    fn finite_difference_jacobian_costs_n_plus_one_calls() {
        let mut counts = Counts::default();
        let mut sys = Quadratic;
        let mut eval = Eval::new(&mut sys, &mut counts);
        let mut jac = Matrix::zeros(2);
        let x = [800.0, -0.5];
        eval.jacobian(0.0, &x, &mut jac).unwrap();
        let want = [[x[1], x[0]], [3.0, 0.0]];
        for (i, row) in want.iter().enumerate() {
            for (j, w) in row.iter().enumerate() {
                let got = jac.get(i, j);
                assert!(
                    (got - w).abs() <= 1e-6 * (1.0 + w.abs()),
                    "J[{i}][{j}] = {got}"
                );
            }
        }
        assert_eq!((counts.rhs, counts.jacobians), (3, 1));
    }
}
