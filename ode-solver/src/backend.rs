//! Everything diffsol-specific: problem construction, the two methods, error mapping.

use std::panic::{catch_unwind, AssertUnwindSafe};

use diffsol::error::OdeSolverError;
use diffsol::{
    Bdf, Closure, ConstantClosure, DiffsolError, ExplicitRk, NalgebraLU, NalgebraMat, OdeBuilder,
    OdeSolverEquations, OdeSolverMethod, OdeSolverProblem, OdeSolverStopReason, UnitCallable,
};

use crate::bridge::Shared;
use crate::{Method, SolverError, Tolerances};

type M = NalgebraMat<f64>;
type LS = NalgebraLU<f64>;
// Boxed so the equation type can be named in a struct.
type RhsFn = Box<dyn Fn(&[f64], &[f64], f64, &mut [f64])>;
type JacFn = Box<dyn Fn(&[f64], &[f64], f64, &[f64], &mut [f64])>;
type InitFn = Box<dyn Fn(&[f64], f64, &mut [f64])>;
type Unit = UnitCallable<M>;
type Eqn = OdeSolverEquations<
    M,
    Closure<M, RhsFn, JacFn>,
    ConstantClosure<M, InitFn>,
    Unit,
    Unit,
    Unit,
    Unit,
>;
type Problem = OdeSolverProblem<Eqn>;

pub(crate) enum Solver<'a> {
    Bdf(Box<Bdf<'a, Eqn, LS>>),
    Tsit45(Box<ExplicitRk<'a, Eqn>>),
}

// diffsol solvers borrow their problem; the integrator must own both.
self_cell::self_cell!(
    struct Cell {
        owner: Problem,
        #[not_covariant]
        dependent: Solver,
    }
);

macro_rules! dispatch {
    ($solver:expr, $s:ident => $body:expr) => {
        match $solver {
            Solver::Bdf($s) => $body,
            Solver::Tsit45($s) => $body,
        }
    };
}

pub(crate) enum Stop {
    Internal,
    TstopReached,
}

pub(crate) struct Backend {
    cell: Cell,
}

impl Backend {
    /// A fresh solver at (t0, shared.x0): new step-size estimate, new Jacobian, order 1.
    pub fn new(
        method: Method,
        tol: &Tolerances,
        n: usize,
        t0: f64,
        shared: &Shared,
    ) -> Result<Self, SolverError> {
        let (s1, s2, s3) = (shared.clone(), shared.clone(), shared.clone());
        let rhs: RhsFn = Box::new(move |x, _p, t, dx| s1.borrow_mut().rhs(t, x, dx));
        let jac: JacFn = Box::new(move |x, _p, t, v, jv| s2.borrow_mut().jac_mul(t, x, v, jv));
        let init: InitFn = Box::new(move |_p, _t, y| y.copy_from_slice(&s3.borrow().x0));
        let mut problem = OdeBuilder::<M>::new()
            .t0(t0)
            .rtol(tol.relative)
            .atol(vec![tol.absolute; n])
            .rhs_implicit(rhs, jac)
            .init(init, n)
            .build()
            .map_err(map_err)?;
        // The integrator applies its own cap, counted per stretch toward a t_stop.
        problem.ode_options.max_number_timesteps = usize::MAX;
        let cell = Cell::try_new(problem, |p| {
            guarded(|| {
                Ok(match method {
                    Method::Bdf => Solver::Bdf(Box::new(p.bdf::<LS>()?)),
                    Method::Tsit45 => Solver::Tsit45(Box::new(p.tsit45()?)),
                })
            })
        })?;
        Ok(Self { cell })
    }

    pub fn set_stop_time(&mut self, t_stop: f64) -> Result<(), SolverError> {
        self.cell
            .with_dependent_mut(|_, s| guarded(|| dispatch!(s, s => s.set_stop_time(t_stop))))
    }

    pub fn step(&mut self) -> Result<Stop, SolverError> {
        self.cell.with_dependent_mut(|_, s| {
            guarded(|| {
                Ok(match dispatch!(s, s => s.step())? {
                    OdeSolverStopReason::TstopReached => Stop::TstopReached,
                    // No root function is given to diffsol, so this cannot occur.
                    OdeSolverStopReason::InternalTimestep | OdeSolverStopReason::RootFound(..) => {
                        Stop::Internal
                    }
                })
            })
        })
    }

    pub fn time(&self) -> f64 {
        self.cell
            .with_dependent(|_, s| dispatch!(s, s => s.state().t))
    }

    pub fn state(&self, out: &mut [f64]) {
        self.cell.with_dependent(
            |_, s| dispatch!(s, s => out.copy_from_slice(s.state().y.batch_as_slice(0))),
        )
    }

    /// Dense output inside the last accepted step; no derivative calls.
    pub fn interpolate(&self, t: f64, out: &mut [f64]) -> Result<(), SolverError> {
        self.cell.with_dependent(|_, s| {
            guarded(|| {
                let y = dispatch!(s, s => s.interpolate(t))?;
                out.copy_from_slice(y.batch_as_slice(0));
                Ok(())
            })
        })
    }

    /// Move the solver back to `t` inside the last step (after a located event).
    pub fn move_back(&mut self, t: f64) -> Result<(), SolverError> {
        self.cell
            .with_dependent_mut(|_, s| guarded(|| dispatch!(s, s => s.state_mut_back(t))))
    }

    /// (accepted steps, rejected attempts) of this solver instance.
    pub fn counters(&self) -> (u64, u64) {
        self.cell.with_dependent(|_, s| {
            let st = dispatch!(s, s => s.get_statistics());
            let rejected = st.number_of_error_test_failures + st.number_of_nonlinear_solver_fails;
            (st.number_of_steps as u64, rejected as u64)
        })
    }
}

/// Run a diffsol call, turning its errors and any panic into `SolverError`.
fn guarded<R>(f: impl FnOnce() -> Result<R, DiffsolError>) -> Result<R, SolverError> {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(r) => r.map_err(map_err),
        Err(p) => {
            let msg = p
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| p.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".into());
            Err(SolverError::Backend(format!("panic in diffsol: {msg}")))
        }
    }
}

fn map_err(e: DiffsolError) -> SolverError {
    match &e {
        DiffsolError::OdeSolverError(o) => match o {
            OdeSolverError::StepSizeTooSmall { time } => {
                SolverError::StepSizeUnderflow { t: *time }
            }
            OdeSolverError::TooManyTimesteps { time, num_steps } => SolverError::TooManySteps {
                t: *time,
                steps: *num_steps as u64,
            },
            OdeSolverError::TooManyErrorTestFailures { time, .. }
            | OdeSolverError::TooManyNonlinearSolverFailures { time, .. } => {
                SolverError::ConvergenceFailure {
                    t: *time,
                    detail: o.to_string(),
                }
            }
            _ => SolverError::Backend(e.to_string()),
        },
        _ => SolverError::Backend(e.to_string()),
    }
}
