//! The two methods behind one interface, so the integrator's stepping and event logic does
//! not care which one runs.

use crate::bdf::Bdf;
use crate::eval::Eval;
use crate::tsit5::Tsit5;
use crate::{Method, SolverError, Tolerances};

pub(crate) enum Stop {
    Internal,
    TstopReached,
}

#[derive(Debug)]
pub(crate) enum Backend {
    Bdf(Box<Bdf>),
    Tsit45(Box<Tsit5>),
}

macro_rules! dispatch {
    ($backend:expr, $s:ident => $body:expr) => {
        match $backend {
            Backend::Bdf($s) => $body,
            Backend::Tsit45($s) => $body,
        }
    };
}

impl Backend {
    /// A fresh solver at (t0, x0): f(t0, x0), a new step-size estimate, and for BDF order 1
    /// and no Jacobian yet (it is formed at the first step).
    pub fn new(
        method: Method,
        tol: &Tolerances,
        eval: &mut Eval<'_>,
        t0: f64,
        x0: &[f64],
    ) -> Result<Self, SolverError> {
        Ok(match method {
            Method::Bdf => Self::Bdf(Box::new(Bdf::new(eval, tol, t0, x0)?)),
            Method::Tsit45 => Self::Tsit45(Box::new(Tsit5::new(eval, tol, t0, x0)?)),
        })
    }

    /// One accepted step, never past `t_stop`; a step that reaches it ends on it bit-exactly.
    pub fn step(&mut self, eval: &mut Eval<'_>, t_stop: f64) -> Result<Stop, SolverError> {
        if t_stop.is_nan() || t_stop <= self.time() {
            return Err(SolverError::InvalidInput(format!(
                "t_stop {t_stop} is not after the solver's time {}",
                self.time()
            )));
        }
        let landed = dispatch!(self, s => s.step(eval, t_stop))?;
        Ok(if landed {
            Stop::TstopReached
        } else {
            Stop::Internal
        })
    }

    pub fn time(&self) -> f64 {
        dispatch!(self, s => s.time())
    }

    pub fn state(&self, out: &mut [f64]) {
        out.copy_from_slice(dispatch!(self, s => s.state()));
    }

    /// Dense output inside the last accepted step; no derivative calls.
    pub fn interpolate(&self, t: f64, out: &mut [f64]) -> Result<(), SolverError> {
        dispatch!(self, s => s.interpolate(t, out))
    }

    /// Move the solver back to `t` inside the last step (after a located event).
    pub fn move_back(&mut self, t: f64) -> Result<(), SolverError> {
        dispatch!(self, s => s.move_back(t))
    }

    /// (accepted steps, rejected attempts) of this solver instance.
    pub fn counters(&self) -> (u64, u64) {
        dispatch!(self, s => (s.steps, s.rejected))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::eval::Counts;
    use crate::OdeSystem;

    const METHODS: [Method; 2] = [Method::Bdf, Method::Tsit45];

    /// x'' = -x from [1, 0]: [cos t, -sin t].
    struct Oscillator;

    impl OdeSystem for Oscillator {
        fn state_count(&self) -> usize {
            2
        }
        fn indicator_count(&self) -> usize {
            0
        }
        fn derivatives(&mut self, _t: f64, x: &[f64], dx: &mut [f64]) -> Result<(), String> {
            dx[0] = x[1];
            dx[1] = -x[0];
            Ok(())
        }
        fn indicators(&mut self, _t: f64, _x: &[f64], _z: &mut [f64]) -> Result<(), String> {
            Ok(())
        }
    }

    fn exact(t: f64) -> [f64; 2] {
        [libm::cos(t), -libm::sin(t)]
    }

    const TOL: Tolerances = Tolerances {
        relative: 1e-8,
        absolute: 1e-10,
        event_time: 1e-12,
    };

    fn state(b: &Backend) -> Vec<f64> {
        let mut x = vec![0.0; 2];
        b.state(&mut x);
        x
    }

    #[test]
    fn dense_output_ends_on_the_steps_states_and_is_accurate_inside() {
        for method in METHODS {
            let (mut sys, mut counts) = (Oscillator, Counts::default());
            let mut eval = Eval::new(&mut sys, &mut counts);
            let mut b = Backend::new(method, &TOL, &mut eval, 0.0, &[1.0, 0.0]).unwrap();
            let mut out = vec![0.0; 2];
            // Before any step there is no step to interpolate in.
            assert!(b.interpolate(0.0, &mut out).is_err());
            let mut worst = 0.0f64;
            for _ in 0..10_000 {
                let (t0, x0) = (b.time(), state(&b));
                b.step(&mut eval, 3.0).unwrap();
                let (t1, x1) = (b.time(), state(&b));
                b.interpolate(t0, &mut out).unwrap();
                assert_eq!(out, x0, "{method:?} at the start of the step to {t1}");
                b.interpolate(t1, &mut out).unwrap();
                assert_eq!(out, x1, "{method:?} at the end of the step to {t1}");
                // Against the exact flow from the step's start, so that the error carried in
                // from earlier steps does not count.
                for s in [0.25, 0.5, 0.75] {
                    let t = t0 + s * (t1 - t0);
                    b.interpolate(t, &mut out).unwrap();
                    let (c, sn) = (libm::cos(t - t0), libm::sin(t - t0));
                    let e = [x0[0] * c + x0[1] * sn, -x0[0] * sn + x0[1] * c];
                    worst = worst.max((out[0] - e[0]).abs().max((out[1] - e[1]).abs()));
                }
                assert!(b.interpolate(t1 + 1e-9, &mut out).is_err());
                assert!(b.interpolate(t0 - 1e-9, &mut out).is_err());
                if t1 == 3.0 {
                    break;
                }
            }
            assert_eq!(b.time(), 3.0, "{method:?}");
            println!("{method:?}: dense output within {worst:e} of the exact solution");
            assert!(
                worst < 10.0 * (TOL.relative + TOL.absolute),
                "{method:?}: {worst}"
            );
        }
    }

    #[test]
    fn continuing_after_move_back_follows_the_exact_solution() {
        for method in METHODS {
            let (mut sys, mut counts) = (Oscillator, Counts::default());
            let mut eval = Eval::new(&mut sys, &mut counts);
            let mut b = Backend::new(method, &TOL, &mut eval, 0.0, &[1.0, 0.0]).unwrap();
            // Move back into every fifth step, as an event inside it would.
            let mut step = 0;
            let mut moves = 0;
            loop {
                let t0 = b.time();
                let reached = matches!(b.step(&mut eval, 6.0).unwrap(), Stop::TstopReached);
                if reached {
                    break;
                }
                step += 1;
                if step % 5 == 0 {
                    let t = t0 + 0.3 * (b.time() - t0);
                    let mut expected = vec![0.0; 2];
                    b.interpolate(t, &mut expected).unwrap();
                    b.move_back(t).unwrap();
                    assert_eq!((b.time(), state(&b)), (t, expected));
                    // The last step now ends at t: the dense output does too.
                    let mut out = vec![0.0; 2];
                    assert!(b.interpolate(t + 1e-9, &mut out).is_err());
                    moves += 1;
                }
            }
            let (x, e) = (state(&b), exact(6.0));
            let err = (x[0] - e[0]).abs().max((x[1] - e[1]).abs());
            println!("{method:?}: {moves} moves back, error {err:e} at t = 6");
            assert!(moves >= 3);
            assert!(
                err < 10.0 * (TOL.relative + TOL.absolute),
                "{method:?}: {err}"
            );
        }
    }
}
