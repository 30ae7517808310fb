//! Tsitouras 5(4): seven-stage explicit Runge-Kutta pair, first same as last, with a free
//! 4th-order dense output (Ch. Tsitouras, "Runge-Kutta pairs of order 5(4) satisfying only
//! the first column simplifying assumption", Comput. Math. Appl. 62 (2011) 770-775). The
//! 5th-order solution is propagated; the embedded 4th-order one only estimates the error.

use crate::eval::Eval;
use crate::norm::error_norm;
use crate::step_control::{initial_step, min_step, reject_factor, toward, PiControl, MAX_ATTEMPTS};
use crate::{SolverError, Tolerances};

const STAGES: usize = 7;

const C: [f64; STAGES] = [0.0, 0.161, 0.327, 0.9, 0.9800255409045097, 1.0, 1.0];

/// Row i holds a_{i,0..i}; the last row is also the propagated weights b (first same as last).
const A: [[f64; STAGES - 1]; STAGES] = [
    [0.0; 6],
    [0.161, 0.0, 0.0, 0.0, 0.0, 0.0],
    [-0.008480655492356989, 0.335480655492357, 0.0, 0.0, 0.0, 0.0],
    [
        2.897153057105493,
        -6.359448489975075,
        4.3622954328695815,
        0.0,
        0.0,
        0.0,
    ],
    [
        5.325864828439257,
        -11.748883564062828,
        7.4955393428898365,
        -0.09249506636175525,
        0.0,
        0.0,
    ],
    [
        5.86145544294642,
        -12.92096931784711,
        8.159367898576159,
        -0.071584973281401,
        -0.028269050394068383,
        0.0,
    ],
    [
        0.09646076681806523,
        0.01,
        0.4798896504144996,
        1.379008574103742,
        -3.290069515436081,
        2.324710524099774,
    ],
];

/// b - b̂: the local error estimate is h * sum(E_i k_i).
#[allow(clippy::excessive_precision)] // the digits as published, to compare with the paper
const E: [f64; STAGES] = [
    -0.00178001105222577714,
    -0.0008164344596567469,
    0.007880878010261995,
    -0.1447110071732629,
    0.5823571654525552,
    -0.45808210592918697,
    1.0 / 66.0,
];

/// Dense-output weights b_i(θ) = θ^m (R_i0 + R_i1 θ + R_i2 θ² + R_i3 θ³), with m = 1 for
/// the first stage and m = 2 for the others (b_i(θ) has a double root at 0 for i > 1).
#[allow(clippy::excessive_precision)] // the digits as published, to compare with the paper
const R: [[f64; 4]; STAGES] = [
    [
        1.0,
        -2.763706197274825911336736,
        2.91325546182191264,
        -1.0530884977290216,
    ],
    [0.1317, -0.2234, 0.1017, 0.0],
    [
        3.930296236894751528506874,
        -5.941033872131504734702492,
        2.490627285651252793,
        0.0,
    ],
    [
        -12.41107716693367698373438,
        30.33818863028232159817299,
        -16.54810288924490272,
        0.0,
    ],
    [
        37.50931341651103919496904,
        -88.17890489476640110142767,
        47.37952196281928122,
        0.0,
    ],
    [
        -27.89652628919728780594826,
        65.09189467479367152629022,
        -34.87065786149660974,
        0.0,
    ],
    [1.5, -4.0, 2.5, 0.0],
];

fn dense_weights(theta: f64) -> [f64; STAGES] {
    let mut b = [0.0; STAGES];
    for (i, (bi, r)) in b.iter_mut().zip(&R).enumerate() {
        let p = r[0] + theta * (r[1] + theta * (r[2] + theta * r[3]));
        *bi = if i == 0 { theta * p } else { theta * theta * p };
    }
    b
}

/// The last accepted step, kept for dense output.
#[derive(Debug)]
struct LastStep {
    t0: f64,
    /// The step's full length: θ is measured against it even after `move_back` shortened the
    /// step, since the polynomial is the one of the full step.
    h: f64,
    y0: Vec<f64>,
    k: [Vec<f64>; STAGES],
    /// Where the step now ends (its end, or the time `move_back` moved to) and the state
    /// there, so both ends are returned exactly, not re-evaluated by the polynomial.
    t1: f64,
    y1: Vec<f64>,
}

#[derive(Debug)]
pub(crate) struct Tsit5 {
    tol: Tolerances,
    t: f64,
    y: Vec<f64>,
    /// f(t, y), the first stage of the next step; None after `move_back`, since the state
    /// then comes from the dense output and f there is not known yet.
    f: Option<Vec<f64>>,
    /// The next step size to try; None until the first step, which knows its stop time.
    h: Option<f64>,
    control: PiControl,
    last: Option<LastStep>,
    pub steps: u64,
    pub rejected: u64,
}

impl Tsit5 {
    pub fn new(
        eval: &mut Eval<'_>,
        tol: &Tolerances,
        t0: f64,
        y0: &[f64],
    ) -> Result<Self, SolverError> {
        let mut f = vec![0.0; y0.len()];
        eval.rhs(t0, y0, &mut f)?;
        Ok(Self {
            tol: *tol,
            t: t0,
            y: y0.to_vec(),
            f: Some(f),
            h: None,
            control: PiControl::new(4),
            last: None,
            steps: 0,
            rejected: 0,
        })
    }

    pub fn time(&self) -> f64 {
        self.t
    }

    pub fn state(&self) -> &[f64] {
        &self.y
    }

    /// One accepted step toward `t_stop` (> time()); true if it landed on t_stop.
    pub fn step(&mut self, eval: &mut Eval<'_>, t_stop: f64) -> Result<bool, SolverError> {
        let n = self.y.len();
        let t = self.t;
        let k1 = match &self.f {
            Some(f) => f.clone(),
            None => {
                let mut f = vec![0.0; n];
                eval.rhs(t, &self.y, &mut f)?;
                self.f = Some(f.clone());
                f
            }
        };
        let mut h_try = match self.h {
            Some(h) => h,
            None => initial_step(eval, t, &self.y, &k1, 4, &self.tol, t_stop - t)?,
        };
        let mut k: [Vec<f64>; STAGES] = std::array::from_fn(|_| vec![0.0; n]);
        k[0] = k1;
        let mut y_stage = vec![0.0; n];
        let mut err = vec![0.0; n];
        let mut rejected_here = false;
        for _ in 0..MAX_ATTEMPTS {
            let (h, t_new, lands) = toward(t, h_try, t_stop);
            if !lands && h < min_step(t) {
                return Err(SolverError::StepSizeUnderflow { t });
            }
            for s in 1..STAGES {
                for i in 0..n {
                    let incr: f64 = (0..s).map(|j| A[s][j] * k[j][i]).sum();
                    y_stage[i] = self.y[i] + h * incr;
                }
                // Stages at the step's end are at t_new itself, bit-exact on t_stop, and no
                // stage is past it: the system is never asked beyond a stop time.
                let ts = if C[s] == 1.0 {
                    t_new
                } else {
                    (t + C[s] * h).min(t_new)
                };
                eval.rhs(ts, &y_stage, &mut k[s])?;
            }
            // y_stage now holds the propagated solution: the last stage is evaluated there.
            for (i, e) in err.iter_mut().enumerate() {
                *e = h * (0..STAGES).map(|j| E[j] * k[j][i]).sum::<f64>();
            }
            let err_norm = error_norm(&err, &self.y, &y_stage, &self.tol);
            if err_norm <= 1.0 {
                let factor = self.control.accept_factor(err_norm, rejected_here);
                // A step cut short to land on t_stop says nothing against the longer one.
                self.h = Some(if lands {
                    (h * factor).max(h_try)
                } else {
                    h * factor
                });
                let y0 = std::mem::replace(&mut self.y, y_stage.clone());
                self.f = Some(k[STAGES - 1].clone());
                self.t = t_new;
                self.last = Some(LastStep {
                    t0: t,
                    h,
                    y0,
                    k,
                    t1: t_new,
                    y1: y_stage,
                });
                self.steps += 1;
                return Ok(lands);
            }
            self.rejected += 1;
            rejected_here = true;
            h_try = h * reject_factor(err_norm, 4);
            self.h = Some(h_try);
        }
        Err(SolverError::ConvergenceFailure {
            t,
            detail: format!("{MAX_ATTEMPTS} rejected attempts at one Tsitouras 5(4) step"),
        })
    }

    /// The dense output of the last step at `t` within it; no derivative calls.
    pub fn interpolate(&self, t: f64, out: &mut [f64]) -> Result<(), SolverError> {
        let last = self.last_step_containing(t)?;
        if t == last.t1 {
            out.copy_from_slice(&last.y1);
        } else if t == last.t0 {
            out.copy_from_slice(&last.y0);
        } else {
            let b = dense_weights((t - last.t0) / last.h);
            for (i, o) in out.iter_mut().enumerate() {
                let incr: f64 = (0..STAGES).map(|j| b[j] * last.k[j][i]).sum();
                *o = last.y0[i] + last.h * incr;
            }
        }
        Ok(())
    }

    /// Continue from `t` inside the last step, as if the step had ended there.
    pub fn move_back(&mut self, t: f64) -> Result<(), SolverError> {
        let mut y = vec![0.0; self.y.len()];
        self.interpolate(t, &mut y)?;
        if let Some(last) = self.last.as_mut() {
            last.t1 = t;
            last.y1.clone_from(&y);
        }
        self.t = t;
        self.y = y;
        self.f = None;
        Ok(())
    }

    fn last_step_containing(&self, t: f64) -> Result<&LastStep, SolverError> {
        match &self.last {
            Some(last) if t >= last.t0 && t <= last.t1 => Ok(last),
            _ => Err(SolverError::InvalidInput(format!(
                "t = {t} is outside the last step"
            ))),
        }
    }
}

#[cfg(test)]
// powi only builds the exact right-hand sides of the order conditions here.
#[allow(clippy::disallowed_methods)]
mod tests {
    use super::*;

    /// Σ_i w_i Φ_i over the stages for a vector Φ.
    fn dot(w: &[f64; STAGES], phi: &[f64; STAGES]) -> f64 {
        w.iter().zip(phi).map(|(a, b)| a * b).sum()
    }

    /// (A v)_i.
    fn a_times(v: &[f64; STAGES]) -> [f64; STAGES] {
        std::array::from_fn(|i| (0..i.min(STAGES - 1)).map(|j| A[i][j] * v[j]).sum())
    }

    /// The order conditions up to order 4 for weights `w` scaled to the step fraction θ:
    /// each is Σ w Φ(tree) = θ^ρ / γ(tree).
    fn check_order_4(w: &[f64; STAGES], theta: f64, eps: f64) {
        let c = C;
        let ones = [1.0; STAGES];
        let c2: [f64; STAGES] = std::array::from_fn(|i| c[i] * c[i]);
        let c3: [f64; STAGES] = std::array::from_fn(|i| c[i] * c2[i]);
        let ac = a_times(&c);
        let cac: [f64; STAGES] = std::array::from_fn(|i| c[i] * ac[i]);
        let ac2 = a_times(&c2);
        let aac = a_times(&ac);
        let conditions = [
            (dot(w, &ones), theta),
            (dot(w, &c), theta.powi(2) / 2.0),
            (dot(w, &c2), theta.powi(3) / 3.0),
            (dot(w, &ac), theta.powi(3) / 6.0),
            (dot(w, &c3), theta.powi(4) / 4.0),
            (dot(w, &cac), theta.powi(4) / 8.0),
            (dot(w, &ac2), theta.powi(4) / 12.0),
            (dot(w, &aac), theta.powi(4) / 24.0),
        ];
        for (k, (got, want)) in conditions.iter().enumerate() {
            assert!(
                (got - want).abs() < eps,
                "θ {theta}, condition {k}: {got} vs {want}"
            );
        }
    }

    #[test]
    fn tableau_satisfies_the_order_conditions() {
        // Row sums are the nodes.
        for i in 1..STAGES {
            let s: f64 = A[i].iter().sum();
            assert!((s - C[i]).abs() < 1e-14, "row {i}: {s}");
        }
        let b: [f64; STAGES] = std::array::from_fn(|i| if i < 6 { A[6][i] } else { 0.0 });
        check_order_4(&b, 1.0, 1e-14);
        // The fifth-order conditions of b, the nine trees of order 5.
        let c = C;
        let pw = |p: i32| -> [f64; STAGES] { std::array::from_fn(|i| c[i].powi(p)) };
        let mul = |x: &[f64; STAGES], y: &[f64; STAGES]| -> [f64; STAGES] {
            std::array::from_fn(|i| x[i] * y[i])
        };
        let ac = a_times(&c);
        let ac2 = a_times(&pw(2));
        let ac3 = a_times(&pw(3));
        let aac = a_times(&ac);
        let order5 = [
            (dot(&b, &pw(4)), 1.0 / 5.0),
            (dot(&b, &mul(&pw(2), &ac)), 1.0 / 10.0),
            (dot(&b, &mul(&ac, &ac)), 1.0 / 20.0),
            (dot(&b, &mul(&c, &ac2)), 1.0 / 15.0),
            (dot(&b, &ac3), 1.0 / 20.0),
            (dot(&b, &mul(&c, &aac)), 1.0 / 30.0),
            (dot(&b, &a_times(&mul(&c, &ac))), 1.0 / 40.0),
            (dot(&b, &a_times(&ac2)), 1.0 / 60.0),
            (dot(&b, &a_times(&aac)), 1.0 / 120.0),
        ];
        for (k, (got, want)) in order5.iter().enumerate() {
            assert!(
                (got - want).abs() < 1e-13,
                "order 5, tree {k}: {got} vs {want}"
            );
        }
        // The embedded weights b̂ = b - E are of order 4 and differ from b.
        let b_hat: [f64; STAGES] = std::array::from_fn(|i| b[i] - E[i]);
        check_order_4(&b_hat, 1.0, 1e-14);
        assert!((dot(&b_hat, &pw(4)) - 0.2).abs() > 1e-6);
    }

    #[test]
    fn dense_output_is_of_order_four_and_ends_on_the_step() {
        for theta in [0.0, 0.1, 0.37, 0.5, 0.8, 1.0] {
            check_order_4(&dense_weights(theta), theta, 1e-14);
        }
        let b1 = dense_weights(1.0);
        for i in 0..STAGES - 1 {
            assert!((b1[i] - A[6][i]).abs() < 1e-14, "b_{i}(1) = {}", b1[i]);
        }
        assert!(b1[6].abs() < 1e-15);
    }
}
