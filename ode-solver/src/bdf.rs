//! Variable-order (1..=5) BDF in the quasi-constant step-size form: the history is kept as
//! backward differences on an equally spaced grid and re-gridded whenever the step size
//! changes (Shampine & Reichelt, "The MATLAB ODE Suite", 1997; the scheme of
//! scipy.integrate.BDF). Plain BDF, not NDF: every κ is 0, so the method and its stability
//! regions are the textbook BDF1-5 that `Method::Bdf` names.
//!
//! Each step solves for the correction d = y_{n+1} - y_pred by a simplified Newton iteration
//! on (I - c J), c = h / γ_k, with a finite-difference Jacobian that is reused across steps
//! and re-formed only when Newton fails to converge.

use crate::differences::{regrid, rescale, Poly};
use crate::eval::Eval;
use crate::lu::{Lu, Matrix};
use crate::norm::{error_norm, scaled_rms};
use crate::step_control::{initial_step, min_step, toward, MAX_ATTEMPTS, MIN_FACTOR};
use crate::{SolverError, Tolerances};

pub(crate) const MAX_ORDER: usize = 5;

const NEWTON_MAXITER: usize = 4;

/// Growth of the step size at one change, and the range of proposed factors for which the step
/// size is kept. Every change re-grids the history, extrapolating its polynomial (and its
/// rounding) by factor^order: few, moderate changes keep that error below the one the error
/// test controls. Measured on exponential decay, an undamped oscillator and a free fall
/// restarted every 0.1 s (as the Model Exchange master does), 5 and [0.9, 2) gave global
/// errors 1.2 to 6 times smaller (6 on the free fall) than 10 and no range, for 10 to 30% more
/// steps.
const MAX_GROWTH: f64 = 5.0;
const KEEP_STEP: std::ops::Range<f64> = 0.9..2.0;

/// After this many failures within one step the order drops to 1: a step that keeps failing
/// usually straddles a discontinuity, which the high-order history only misrepresents.
const FAILURES_BEFORE_ORDER_ONE: u32 = 3;

/// γ_k = 1 + 1/2 + ... + 1/k, the leading coefficient of BDF-k in difference form.
fn gamma(k: usize) -> f64 {
    (1..=k).map(|j| 1.0 / j as f64).sum()
}

/// The local error of BDF-k is about this times the correction d.
fn error_constant(k: usize) -> f64 {
    1.0 / (k as f64 + 1.0)
}

/// The last accepted step, for dense output.
#[derive(Debug)]
struct LastStep {
    t0: f64,
    y0: Vec<f64>,
    /// The history after the step: the polynomial through its end and the points before.
    poly: Poly,
    /// Where the step now ends (t_ref, or where `move_back` moved to) and the state there.
    t1: f64,
    y1: Vec<f64>,
}

#[derive(Debug)]
pub(crate) struct Bdf {
    tol: Tolerances,
    t: f64,
    /// Backward differences at t on the grid of spacing h: rows 0..=order are the history,
    /// rows order+1 and order+2 the last corrections, for the error estimates of the
    /// neighbouring orders.
    d: Vec<Vec<f64>>,
    order: usize,
    h: f64,
    /// Until the first step, which knows its stop time, h is 1 and row 1 holds f itself.
    needs_initial_step: bool,
    /// Steps accepted since h or the order last changed: the differences of the neighbouring
    /// orders are only meaningful after order + 1 of them.
    equal_steps: usize,
    jac: Option<Matrix>,
    /// True while `jac` was formed during the current step: if Newton still fails, a fresh
    /// Jacobian cannot help and the step is cut instead.
    jac_fresh: bool,
    /// Factorisation of I - c J for the current h, order and J.
    lu: Option<Lu>,
    /// Contraction rate Newton last measured with this `lu`: lets the next step's Newton stop
    /// after one iteration. Used once, then measured again, so that a Jacobian going stale
    /// along the solution shows up in the rate.
    newton_rate: Option<f64>,
    newton_tol: f64,
    last: Option<LastStep>,
    pub steps: u64,
    pub rejected: u64,
}

#[derive(Debug)]
struct BeforeLanding {
    poly: Poly,
    /// Rows order+1 and order+2 of the differences.
    corrections: [Vec<f64>; 2],
    equal_steps: usize,
}

enum Newton {
    Converged {
        iterations: usize,
        y: Vec<f64>,
        d: Vec<f64>,
        /// The contraction rate measured, if there were two iterations or more.
        rate: Option<f64>,
    },
    Failed,
}

impl Bdf {
    pub fn new(
        eval: &mut Eval<'_>,
        tol: &Tolerances,
        t0: f64,
        y0: &[f64],
    ) -> Result<Self, SolverError> {
        let n = y0.len();
        let mut d = vec![vec![0.0; n]; MAX_ORDER + 3];
        d[0].copy_from_slice(y0);
        eval.rhs(t0, y0, &mut d[1])?;
        Ok(Self {
            tol: *tol,
            t: t0,
            d,
            order: 1,
            h: 1.0,
            needs_initial_step: true,
            equal_steps: 0,
            jac: None,
            jac_fresh: false,
            lu: None,
            newton_rate: None,
            // Newton need only be a little more accurate than the error test it feeds.
            newton_tol: (10.0 * f64::EPSILON / tol.relative).max(0.03f64.min(tol.relative.sqrt())),
            last: None,
            steps: 0,
            rejected: 0,
        })
    }

    pub fn time(&self) -> f64 {
        self.t
    }

    pub fn state(&self) -> &[f64] {
        &self.d[0]
    }

    /// Change the step size to `h`, keeping the history's polynomial.
    fn set_step(&mut self, h: f64) {
        if h != self.h {
            rescale(&mut self.d, self.order, h / self.h);
            self.h = h;
            self.equal_steps = 0;
            self.lu = None;
        }
    }

    /// The history before a step that lands on t_stop, to continue on its grid afterwards.
    fn before_landing(&self) -> BeforeLanding {
        let k = self.order;
        BeforeLanding {
            poly: Poly {
                d: self.d[..=k].to_vec(),
                order: k,
                t_ref: self.t,
                h: self.h,
            },
            corrections: [self.d[k + 1].clone(), self.d[k + 2].clone()],
            equal_steps: self.equal_steps,
        }
    }

    /// After the landing step to (t, y): the history on the grid it had before that step,
    /// shifted to end at t. The grid's spacing is unchanged, so the last corrections and the
    /// count of equal steps still describe it, and order selection goes on as if the short
    /// step had not been taken.
    fn resume_after_landing(&mut self, before: BeforeLanding, t: f64, y: &[f64]) {
        let k = before.poly.order;
        regrid(&before.poly, t, y, before.poly.h, &mut self.d);
        let [c1, c2] = before.corrections;
        self.d[k + 1] = c1;
        self.d[k + 2] = c2;
        self.order = k;
        self.h = before.poly.h;
        self.equal_steps = before.equal_steps;
        self.lu = None;
    }

    /// One accepted step toward `t_stop` (> time()); true if it landed on t_stop.
    pub fn step(&mut self, eval: &mut Eval<'_>, t_stop: f64) -> Result<bool, SolverError> {
        let t = self.t;
        let n = self.d[0].len();
        self.jac_fresh = false;
        if self.needs_initial_step {
            let h = initial_step(eval, t, &self.d[0], &self.d[1], 1, &self.tol, t_stop - t)?;
            // Row 1 becomes h f: the first difference on the grid of spacing h.
            self.set_step(h);
            self.needs_initial_step = false;
        }
        let mut failures = 0;
        for _ in 0..MAX_ATTEMPTS {
            if failures >= FAILURES_BEFORE_ORDER_ONE && self.order > 1 {
                self.order = 1;
                self.equal_steps = 0;
                self.lu = None;
            }
            let proposed = self.h;
            let (h, t_new, lands) = toward(t, proposed, t_stop);
            if !lands && h < min_step(t) {
                return Err(SolverError::StepSizeUnderflow { t });
            }
            // A step cut short to land on t_stop says nothing about the step size the
            // solution allows: the history on its grid is kept to continue from t_stop.
            let before_landing = (lands && h != proposed).then(|| self.before_landing());
            if lands {
                self.set_step(h);
            } else if h != proposed {
                // Only t + h rounding (t is large): move the grid, but it is still the same
                // step size to the order selection and to the Newton matrix.
                rescale(&mut self.d, self.order, h / proposed);
                self.h = h;
            }
            let k = self.order;
            let mut y_pred = vec![0.0; n];
            for row in &self.d[..=k] {
                for (p, v) in y_pred.iter_mut().zip(row) {
                    *p += v;
                }
            }
            let alpha = gamma(k);
            let mut psi = vec![0.0; n];
            for (j, row) in self.d.iter().enumerate().take(k + 1).skip(1) {
                let g = gamma(j) / alpha;
                for (p, v) in psi.iter_mut().zip(row) {
                    *p += g * v;
                }
            }
            let c = h / alpha;
            let scale: Vec<f64> = y_pred
                .iter()
                .map(|y| self.tol.absolute + self.tol.relative * y.abs())
                .collect();

            let newton = loop {
                if self.jac.is_none() {
                    self.refresh_jacobian(eval, t_new, &y_pred)?;
                }
                if self.lu.is_none() {
                    self.lu = self.factor(c);
                    self.newton_rate = None;
                }
                let hint = self.newton_rate.take();
                let result = match &self.lu {
                    Some(lu) => newton(
                        eval,
                        t_new,
                        (&y_pred, &psi, &scale),
                        c,
                        lu,
                        hint,
                        self.newton_tol,
                    )?,
                    None => Newton::Failed,
                };
                match result {
                    Newton::Failed if !self.jac_fresh => {
                        self.refresh_jacobian(eval, t_new, &y_pred)?;
                    }
                    other => break other,
                }
            };
            let Newton::Converged {
                iterations,
                y,
                d,
                rate,
            } = newton
            else {
                failures += 1;
                self.rejected += 1;
                self.set_step(0.5 * h);
                continue;
            };

            let err: Vec<f64> = d.iter().map(|v| error_constant(k) * v).collect();
            let err_norm = error_norm(&err, &self.d[0], &y, &self.tol);
            // Fewer Newton iterations: more trust in the error estimate.
            let safety =
                0.9 * (2 * NEWTON_MAXITER + 1) as f64 / (2 * NEWTON_MAXITER + iterations) as f64;
            // NaN fails the test too: the step is cut, never accepted.
            if err_norm.is_nan() || err_norm > 1.0 {
                failures += 1;
                self.rejected += 1;
                let factor = if err_norm.is_finite() {
                    (safety * libm::pow(err_norm, -1.0 / (k as f64 + 1.0))).max(MIN_FACTOR)
                } else {
                    MIN_FACTOR
                };
                self.set_step(factor * h);
                continue;
            }

            self.newton_rate = rate;
            let y0 = self.accept(t, t_new, &y, &d);
            match before_landing {
                // Rather than stretching the short step's grid back out to the old step
                // size, which amplifies its rounding by (ratio)^order.
                Some(before) => self.resume_after_landing(before, t_new, &y),
                None => self.choose_next(&y0, &y, safety),
            }
            self.steps += 1;
            return Ok(lands);
        }
        Err(SolverError::ConvergenceFailure {
            t,
            detail: format!(
                "{MAX_ATTEMPTS} failed attempts (error test or Newton) at one BDF step"
            ),
        })
    }

    fn refresh_jacobian(
        &mut self,
        eval: &mut Eval<'_>,
        t: f64,
        y: &[f64],
    ) -> Result<(), SolverError> {
        let mut jac = self.jac.take().unwrap_or_else(|| Matrix::zeros(y.len()));
        eval.jacobian(t, y, &mut jac)?;
        self.jac = Some(jac);
        self.jac_fresh = true;
        self.lu = None;
        Ok(())
    }

    /// LU of I - c J; None if singular, which fails the Newton iteration.
    fn factor(&self, c: f64) -> Option<Lu> {
        let jac = self.jac.as_ref()?;
        let n = jac.size();
        let mut m = Matrix::zeros(n);
        for i in 0..n {
            for j in 0..n {
                let identity = if i == j { 1.0 } else { 0.0 };
                m.set(i, j, identity - c * jac.get(i, j));
            }
        }
        Lu::factor(m)
    }

    /// Takes the step to (t_new, y) with correction d into the history; returns the state at
    /// the step's start.
    fn accept(&mut self, t: f64, t_new: f64, y: &[f64], d: &[f64]) -> Vec<f64> {
        let k = self.order;
        let y0 = self.d[0].clone();
        // d is the (k+1)-th difference at t_new; the one before becomes the (k+2)-th.
        let (low, high) = self.d.split_at_mut(k + 2);
        for ((last, before), di) in high[0].iter_mut().zip(low[k + 1].iter_mut()).zip(d) {
            *last = di - *before;
            *before = *di;
        }
        for j in (0..=k).rev() {
            let (low, high) = self.d.split_at_mut(j + 1);
            for (a, b) in low[j].iter_mut().zip(&high[0]) {
                *a += b;
            }
        }
        // The sum reproduces y up to rounding; y itself is the state the error test passed.
        self.d[0].copy_from_slice(y);
        self.t = t_new;
        self.equal_steps += 1;
        self.last = Some(LastStep {
            t0: t,
            y0: y0.clone(),
            poly: Poly {
                d: self.d[..=k].to_vec(),
                order: k,
                t_ref: t_new,
                h: self.h,
            },
            t1: t_new,
            y1: y.to_vec(),
        });
        y0
    }

    /// Order and step size for the next step, from the error estimates of orders k - 1, k and
    /// k + 1, once the history has been on one grid long enough for them to mean something.
    fn choose_next(&mut self, y0: &[f64], y: &[f64], safety: f64) {
        let k = self.order;
        if self.equal_steps < k + 1 {
            return;
        }
        let norm_of_row = |order: usize, row: usize| -> f64 {
            let err: Vec<f64> = self.d[row]
                .iter()
                .map(|v| error_constant(order) * v)
                .collect();
            error_norm(&err, y0, y, &self.tol)
        };
        let current = norm_of_row(k, k + 1);
        let lower = if k > 1 {
            norm_of_row(k - 1, k)
        } else {
            f64::INFINITY
        };
        let higher = if k < MAX_ORDER {
            norm_of_row(k + 1, k + 2)
        } else {
            f64::INFINITY
        };
        let factor_for = |err: f64, order: usize| libm::pow(err, -1.0 / (order as f64 + 1.0));
        // On a tie the current order wins, then the lower one.
        let candidates = [
            (factor_for(current, k), k),
            (factor_for(lower, k - 1), k - 1),
            (factor_for(higher, k + 1), k + 1),
        ];
        let (best, order) = candidates
            .iter()
            .copied()
            .filter(|(f, _)| !f.is_nan())
            .fold(
                (f64::NEG_INFINITY, k),
                |acc, c| if c.0 > acc.0 { c } else { acc },
            );
        let factor = (safety * best).min(MAX_GROWTH);
        if order == k && KEEP_STEP.contains(&factor) {
            return;
        }
        self.order = order;
        self.lu = None;
        // set_step compares against the old h: force the re-grid even for a factor of 1.
        rescale(&mut self.d, self.order, factor);
        self.h *= factor;
        self.equal_steps = 0;
    }

    /// The dense output of the last step at `t` within it; no derivative calls.
    pub fn interpolate(&self, t: f64, out: &mut [f64]) -> Result<(), SolverError> {
        let last = match &self.last {
            Some(last) if t >= last.t0 && t <= last.t1 => last,
            _ => {
                return Err(SolverError::InvalidInput(format!(
                    "t = {t} is outside the last step"
                )))
            }
        };
        if t == last.t1 {
            out.copy_from_slice(&last.y1);
        } else if t == last.t0 {
            out.copy_from_slice(&last.y0);
        } else {
            last.poly.at(t, out);
        }
        Ok(())
    }

    /// Continue from `t` inside the last step. The history is rebuilt from the step's
    /// polynomial on a grid ending at t, at the step's order and at most its step size, so
    /// the next step is of full order with no derivative call and no restart at order 1.
    pub fn move_back(&mut self, t: f64) -> Result<(), SolverError> {
        let mut y = vec![0.0; self.d[0].len()];
        self.interpolate(t, &mut y)?;
        let Some(last) = self.last.as_mut() else {
            return Ok(());
        };
        let h = self.h.min(last.poly.h);
        regrid(&last.poly, t, &y, h, &mut self.d);
        last.t1 = t;
        last.y1.clone_from(&y);
        self.order = last.poly.order;
        self.t = t;
        self.h = h;
        self.equal_steps = 0;
        self.lu = None;
        Ok(())
    }
}

/// Simplified Newton for d: (I - c J) Δ = c f(t_new, y_pred + d) - psi - d, stopped as soon
/// as the contraction rate shows the remaining error is below `tol`, or shows it will not be
/// within the iteration limit. The rate is measured from the second iteration on; `hint`, a
/// rate measured with the same matrix at the previous step, may end it after the first.
fn newton(
    eval: &mut Eval<'_>,
    t_new: f64,
    (y_pred, psi, scale): (&[f64], &[f64], &[f64]),
    c: f64,
    lu: &Lu,
    hint: Option<f64>,
    tol: f64,
) -> Result<Newton, SolverError> {
    let n = y_pred.len();
    let mut y = y_pred.to_vec();
    let mut d = vec![0.0; n];
    let mut f = vec![0.0; n];
    let mut dy = vec![0.0; n];
    let mut work = vec![0.0; n];
    let mut dy_norm_old: Option<f64> = None;
    for k in 0..NEWTON_MAXITER {
        eval.rhs(t_new, &y, &mut f)?;
        for i in 0..n {
            dy[i] = c * f[i] - psi[i] - d[i];
        }
        lu.solve(&mut dy, &mut work);
        let dy_norm = scaled_rms(&dy, scale);
        if !dy_norm.is_finite() {
            return Ok(Newton::Failed);
        }
        let measured = dy_norm_old.map(|old| dy_norm / old);
        if let Some(rate) = measured {
            let left = (NEWTON_MAXITER - k) as f64;
            if rate >= 1.0 || libm::pow(rate, left) / (1.0 - rate) * dy_norm > tol {
                return Ok(Newton::Failed);
            }
        }
        for i in 0..n {
            y[i] += dy[i];
            d[i] += dy[i];
        }
        let rate = measured.or(hint.filter(|r| *r < 1.0));
        if dy_norm == 0.0 || rate.is_some_and(|r| r / (1.0 - r) * dy_norm < tol) {
            return Ok(Newton::Converged {
                iterations: k + 1,
                y,
                d,
                rate: measured,
            });
        }
        dy_norm_old = Some(dy_norm);
    }
    Ok(Newton::Failed)
}
