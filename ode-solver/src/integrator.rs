use crate::backend::{Backend, Stop};
use crate::eval::{Counts, Eval};
use crate::events::{any_crossed, locate, which_crossed};
use crate::{Advance, Method, OdeSystem, SolverError, Statistics, Tolerances};

/// Default cap on accepted steps between two `Reached` (or resets).
pub const DEFAULT_MAX_STEPS: u64 = 500_000;

pub struct Integrator {
    method: Method,
    tol: Tolerances,
    n: usize,
    /// Calls into the system, over all backends since `new`.
    counts: Counts,
    /// None for a system without continuous states: time alone advances.
    backend: Option<Backend>,
    t: f64,
    x: Vec<f64>,
    /// Indicators at (t, x): the "before" side of the next crossing test.
    z: Vec<f64>,
    x_work: Vec<f64>,
    z_work: Vec<f64>,
    steps_since_reached: u64,
    max_steps: u64,
    /// Counters of backends replaced by `reset`.
    retired: Statistics,
    failed: bool,
}

impl Integrator {
    pub fn new(
        method: Method,
        tol: Tolerances,
        system: &mut dyn OdeSystem,
        t0: f64,
        x0: &[f64],
    ) -> Result<Self, SolverError> {
        check_tolerances(&tol)?;
        let n = system.state_count();
        let nz = system.indicator_count();
        let mut me = Self {
            method,
            tol,
            n,
            counts: Counts::default(),
            backend: None,
            t: t0,
            x: Vec::new(),
            z: vec![0.0; nz],
            x_work: vec![0.0; n],
            z_work: vec![0.0; nz],
            steps_since_reached: 0,
            max_steps: DEFAULT_MAX_STEPS,
            retired: Statistics::default(),
            failed: true,
        };
        me.restart(system, t0, x0)?;
        Ok(me)
    }

    /// Cap on accepted steps without reaching a t_stop; `TooManySteps` beyond it.
    pub fn set_max_steps(&mut self, max_steps: u64) {
        self.max_steps = max_steps;
    }

    pub fn time(&self) -> f64 {
        self.t
    }

    pub fn state(&self) -> &[f64] {
        &self.x
    }

    /// Event indicators at (time(), state()), as last evaluated.
    pub fn indicators(&self) -> &[f64] {
        &self.z
    }

    pub fn method(&self) -> Method {
        self.method
    }

    /// After an event changed the states (or a time event): restart from (t, x).
    /// Rebuilds the solver (order 1, new step-size estimate, new Jacobian) and re-reads
    /// the indicators, so the system must already be in its post-event mode.
    pub fn reset(
        &mut self,
        system: &mut dyn OdeSystem,
        t: f64,
        x: &[f64],
    ) -> Result<(), SolverError> {
        if let Some(b) = self.backend.take() {
            let (steps, rejected) = b.counters();
            self.retired.steps += steps;
            self.retired.rejected_steps += rejected;
        }
        self.retired.restarts += 1;
        self.restart(system, t, x)
    }

    fn restart(
        &mut self,
        system: &mut dyn OdeSystem,
        t: f64,
        x: &[f64],
    ) -> Result<(), SolverError> {
        self.failed = true;
        if !t.is_finite() {
            return Err(SolverError::InvalidInput(format!("time {t} is not finite")));
        }
        if x.len() != self.n || system.state_count() != self.n {
            return Err(SolverError::InvalidInput(format!(
                "expected {} states, got {} (system says {})",
                self.n,
                x.len(),
                system.state_count()
            )));
        }
        if system.indicator_count() != self.z.len() {
            return Err(SolverError::InvalidInput(
                "indicator count changed; create a new Integrator".into(),
            ));
        }
        if let Some(i) = x.iter().position(|v| !v.is_finite()) {
            return Err(SolverError::InvalidInput(format!(
                "state {i} is not finite"
            )));
        }
        let mut eval = Eval::new(system, &mut self.counts);
        self.backend = None;
        if self.n > 0 {
            // Building evaluates f(t, x): a system that fails there fails here.
            self.backend = Some(Backend::new(self.method, &self.tol, &mut eval, t, x)?);
        }
        self.t = t;
        self.x = x.to_vec();
        eval.indicators(t, &self.x, &mut self.z)?;
        self.steps_since_reached = 0;
        self.failed = false;
        Ok(())
    }

    /// Advance by at most one accepted internal step, never past t_stop.
    pub fn step(
        &mut self,
        system: &mut dyn OdeSystem,
        t_stop: f64,
    ) -> Result<Advance, SolverError> {
        if self.failed {
            return Err(SolverError::NeedsReset);
        }
        if !t_stop.is_finite() || t_stop < self.t {
            return Err(SolverError::InvalidInput(format!(
                "t_stop {t_stop} is before the current time {}",
                self.t
            )));
        }
        if t_stop == self.t {
            self.steps_since_reached = 0;
            return Ok(Advance::Reached { t: t_stop });
        }
        if self.steps_since_reached >= self.max_steps {
            self.failed = true;
            return Err(SolverError::TooManySteps {
                t: self.t,
                steps: self.steps_since_reached,
            });
        }
        // Lent out for the call, since the step needs the rest of `self` mutably too.
        let mut counts = std::mem::take(&mut self.counts);
        let r = self.step_with(&mut Eval::new(system, &mut counts), t_stop);
        self.counts = counts;
        if r.is_err() {
            self.failed = true;
        }
        r
    }

    fn step_with(&mut self, eval: &mut Eval<'_>, t_stop: f64) -> Result<Advance, SolverError> {
        let t_old = self.t;
        let reached = match self.backend.as_mut() {
            // No states: jump to t_stop; indicators can still depend on time.
            None => {
                self.x_work.clear();
                true
            }
            Some(b) => {
                let reached = matches!(b.step(eval, t_stop)?, Stop::TstopReached);
                b.state(&mut self.x_work);
                reached
            }
        };
        let t_new = if reached { t_stop } else { self.backend_time() };
        if t_new <= t_old {
            return Err(SolverError::StepSizeUnderflow { t: t_old });
        }
        self.steps_since_reached += 1;
        eval.indicators(t_new, &self.x_work, &mut self.z_work)?;

        if any_crossed(&self.z, &self.z_work) {
            return self.locate_event(eval, t_old, t_new, reached);
        }
        std::mem::swap(&mut self.x, &mut self.x_work);
        std::mem::swap(&mut self.z, &mut self.z_work);
        self.t = t_new;
        if reached {
            self.steps_since_reached = 0;
            Ok(Advance::Reached { t: t_stop })
        } else {
            Ok(Advance::Step { t: t_new })
        }
    }

    fn backend_time(&self) -> f64 {
        self.backend.as_ref().map_or(self.t, |b| b.time())
    }

    /// z crossed in (t_old, t_new]: bisect on the dense output, then move the solver back.
    fn locate_event(
        &mut self,
        eval: &mut Eval<'_>,
        t_old: f64,
        t_new: f64,
        reached: bool,
    ) -> Result<Advance, SolverError> {
        let backend = self.backend.as_ref();
        let mut x_mid = vec![0.0; self.n];
        let t_event = locate(
            t_old,
            t_new,
            &self.z,
            &mut self.z_work,
            self.tol.event_time,
            |t, z| {
                if let Some(b) = backend {
                    b.interpolate(t, &mut x_mid)?;
                }
                eval.indicators(t, &x_mid, z)
            },
        )?;
        if t_event < t_new {
            if let Some(b) = self.backend.as_mut() {
                b.interpolate(t_event, &mut self.x_work)?;
                b.move_back(t_event)?;
            }
        } else if reached {
            self.steps_since_reached = 0;
        }
        let which = which_crossed(&self.z, &self.z_work);
        std::mem::swap(&mut self.x, &mut self.x_work);
        std::mem::swap(&mut self.z, &mut self.z_work);
        self.t = t_event;
        Ok(Advance::StateEvent { t: t_event, which })
    }

    /// Counters: steps, rhs evaluations, jacobian evaluations, rejected steps, ...
    pub fn statistics(&self) -> Statistics {
        let (steps, rejected) = self.backend.as_ref().map_or((0, 0), |b| b.counters());
        Statistics {
            steps: self.retired.steps + steps,
            rhs_evaluations: self.counts.rhs,
            jacobian_evaluations: self.counts.jacobians,
            system_jacobians: self.counts.system_jacobians,
            rejected_steps: self.retired.rejected_steps + rejected,
            indicator_evaluations: self.counts.indicators,
            restarts: self.retired.restarts,
        }
    }
}

fn check_tolerances(tol: &Tolerances) -> Result<(), SolverError> {
    let ok = |v: f64| v.is_finite() && v > 0.0;
    if ok(tol.relative) && ok(tol.absolute) && ok(tol.event_time) {
        Ok(())
    } else {
        Err(SolverError::InvalidInput(format!(
            "tolerances must be finite and > 0: {tol:?}"
        )))
    }
}
