//! BDF on the system's own Jacobian: the same solution as with differences, at fewer
//! derivative calls, every Jacobian the system's; a Jacobian that is not finite is an error.
use crate::common;

use common::{run_to, Robertson};
use ode_solver::{Integrator, Method, OdeSystem, SolverError, Statistics, Tolerances};

/// Robertson's kinetics with its Jacobian by hand.
struct RobertsonExact {
    poison: bool,
}

impl OdeSystem for RobertsonExact {
    fn state_count(&self) -> usize {
        3
    }
    fn indicator_count(&self) -> usize {
        0
    }
    fn derivatives(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), String> {
        Robertson.derivatives(t, y, dy)
    }
    fn indicators(&mut self, _t: f64, _y: &[f64], _z: &mut [f64]) -> Result<(), String> {
        Ok(())
    }
    fn jacobian(&mut self, _t: f64, y: &[f64], jac: &mut [f64]) -> Result<bool, String> {
        // column-major: jac[i + 3 j] = d f_i / d y_j
        let rows = [
            [-0.04, 1e4 * y[2], 1e4 * y[1]],
            [0.04, -1e4 * y[2] - 6e7 * y[1], -1e4 * y[1]],
            [0.0, 6e7 * y[1], 0.0],
        ];
        for (i, row) in rows.iter().enumerate() {
            for (j, value) in row.iter().enumerate() {
                jac[i + 3 * j] = *value;
            }
        }
        if self.poison {
            jac[4] = f64::NAN;
        }
        Ok(true)
    }
}

fn solve(sys: &mut dyn OdeSystem, t_end: f64) -> Result<(Vec<f64>, Statistics), SolverError> {
    let tol = Tolerances {
        relative: 1e-6,
        absolute: 1e-10,
        event_time: 1e-9,
    };
    let mut integ = Integrator::new(Method::Bdf, tol, sys, 0.0, &[1.0, 0.0, 0.0])?;
    run_to(&mut integ, sys, t_end)?;
    Ok((integ.state().to_vec(), integ.statistics()))
}

#[test]
fn bdf_on_the_systems_jacobian_agrees_with_differences_at_fewer_calls() {
    let t_end = 40.0;
    let (exact_y, exact) = solve(&mut RobertsonExact { poison: false }, t_end).unwrap();
    let (fd_y, fd) = solve(&mut Robertson, t_end).unwrap();
    println!("own Jacobian: {exact:?}\ndifferences:  {fd:?}");
    for (a, b) in exact_y.iter().zip(&fd_y) {
        assert!(
            (a - b).abs() < 1e-5 * (1.0 + b.abs()),
            "{exact_y:?} vs {fd_y:?}"
        );
    }
    // Every Jacobian the system's own, none by differences
    assert!(exact.jacobian_evaluations > 0);
    assert_eq!(exact.system_jacobians, exact.jacobian_evaluations);
    assert_eq!(fd.system_jacobians, 0);
    // Each difference Jacobian costs n + 1 = 4 derivative calls; the system's none
    let fd_per_step = fd.rhs_evaluations - 4 * fd.jacobian_evaluations;
    assert!(
        exact.rhs_evaluations < fd.rhs_evaluations
            && exact.rhs_evaluations <= fd_per_step + fd_per_step / 2,
        "{} vs {}",
        exact.rhs_evaluations,
        fd.rhs_evaluations
    );
}

#[test]
fn a_jacobian_that_is_not_finite_is_an_error_naming_the_entry() {
    let error = solve(&mut RobertsonExact { poison: true }, 1.0).unwrap_err();
    let text = error.to_string();
    assert!(
        text.contains("non-finite") && text.contains("row 1, column 1"),
        "{text}"
    );
}
