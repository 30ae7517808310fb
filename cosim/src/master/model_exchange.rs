//! A Model Exchange instance inside the fixed communication grid: between two points the
//! master integrates its continuous states with an adaptive solver (`ode-solver`), handling
//! state events (event indicators, located to the solver's event tolerance), time events
//! (`nextEventTime`), step events (`completedIntegratorStep`) and the event iteration, and
//! stops the run where the FMU asks for it (`terminateSimulation`).
//!
//! Each communication step starts the solver afresh from the FMU's states: the inputs the
//! master has just set are constant over the step and may have jumped at its start, which a
//! multistep method must not integrate across.
use crate::system::JacobianSource;
pub use crate::system::SolverSettings;
use fmi_import::{FmiError, Instance, MeVector, StepStatus, Success};
use ode_solver::{Advance, Integrator, Method, OdeSystem, SolverError, Statistics};

/// Event iterations (`fmi2NewDiscreteStates` or `fmi3UpdateDiscreteStates` calls at one instant) before the master gives up:
/// an FMU that keeps asking for new discrete states would otherwise hang the run.
const MAX_EVENT_ITERATIONS: usize = 1000;

/// What a step failed on: the FMU's call or the solver.
#[derive(Debug, thiserror::Error)]
pub enum MeError {
    #[error(transparent)]
    Fmi(#[from] FmiError),
    #[error("solver ({method:?}) at t = {time} s: {source}")]
    Solver {
        method: Method,
        time: f64,
        source: SolverError,
    },
    /// A value a scenario event set was refused (see `events.rs`).
    #[error("setting a scenario event's value: {0}")]
    Set(#[source] fmi_import::CallError),
    #[error(
        "the event iteration at t = {time} s did not end after {MAX_EVENT_ITERATIONS} \
             calls of fmi2NewDiscreteStates (newDiscreteStatesNeeded stayed true)"
    )]
    EventIteration { time: f64 },
}

pub(super) struct ModelExchangeUnit {
    settings: SolverSettings,
    states: usize,
    indicators: usize,
    next_time_event: Option<f64>,
    x: Vec<f64>,
    pub(super) events: EventCounts,
    /// The FMU's Jacobian, when BDF takes it from its directional derivatives.
    jacobian: Option<JacobianPlan>,
    /// The solver's counters over the run, every communication step's added.
    pub(super) statistics: Statistics,
}

/// How BDF's Jacobian is read from an FMU: per state (column), the derivatives (rows) its
/// `ModelStructure` declares dependent on it, asked for together with a unit seed.
struct JacobianPlan {
    states: Vec<u32>,
    derivatives: Vec<u32>,
    /// Per column: the rows asked for.
    rows: Vec<Vec<usize>>,
}

impl JacobianPlan {
    /// The plan of `instance`, if its description declares directional derivatives and
    /// states that match its state vector.
    fn of(instance: &Instance, states: usize) -> Option<Self> {
        if instance.derivative_refusal(false).is_some() {
            return None;
        }
        let structure = instance.derivative_structure().ok()?;
        if structure.states.len() != states || structure.derivatives.len() != states {
            return None;
        }
        let rows = structure
            .states
            .iter()
            .map(|&state| {
                (0..states)
                    .filter(|&i| structure.derivatives[i].depends_on(state))
                    .collect()
            })
            .collect();
        Some(Self {
            states: structure.states,
            derivatives: structure.derivatives.iter().map(|d| d.unknown).collect(),
            rows,
        })
    }
}

/// The events a Model Exchange instance had in a run, by their cause.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub struct EventCounts {
    /// An event indicator changed domain.
    pub state: u64,
    /// `nextEventTime` was reached.
    pub time: u64,
    /// `completedIntegratorStep` asked for Event Mode (and nothing else did).
    pub step: u64,
}

/// The FMU as the solver sees it: set time and states, read derivatives, indicators or its
/// Jacobian.
struct Fmu<'a> {
    instance: &'a mut Instance,
    states: usize,
    indicators: usize,
    jacobian: Option<&'a JacobianPlan>,
}

impl Fmu<'_> {
    fn at(&mut self, t: f64, x: &[f64]) -> Result<(), String> {
        self.instance.set_time(t).map_err(|e| e.to_string())?;
        if !x.is_empty() {
            self.instance
                .set_continuous_states(x)
                .map_err(|e| e.to_string())?;
        }
        Ok(())
    }
}

impl OdeSystem for Fmu<'_> {
    fn state_count(&self) -> usize {
        self.states
    }
    fn indicator_count(&self) -> usize {
        self.indicators
    }
    fn derivatives(&mut self, t: f64, x: &[f64], dx: &mut [f64]) -> Result<(), String> {
        self.at(t, x)?;
        self.instance
            .get_vector(MeVector::Derivatives, dx)
            .map(|_| ())
            .map_err(|e| e.to_string())
    }
    fn indicators(&mut self, t: f64, x: &[f64], z: &mut [f64]) -> Result<(), String> {
        self.at(t, x)?;
        self.instance
            .get_vector(MeVector::EventIndicators, z)
            .map(|_| ())
            .map_err(|e| e.to_string())
    }
    fn jacobian(&mut self, t: f64, x: &[f64], jac: &mut [f64]) -> Result<bool, String> {
        let Some(plan) = self.jacobian else {
            return Ok(false);
        };
        self.at(t, x)?;
        let n = self.states;
        jac.fill(0.0);
        let mut unknowns = Vec::with_capacity(n);
        let mut column = Vec::with_capacity(n);
        for (j, rows) in plan.rows.iter().enumerate() {
            if rows.is_empty() {
                continue;
            }
            unknowns.clear();
            unknowns.extend(rows.iter().map(|&i| plan.derivatives[i]));
            column.clear();
            column.resize(rows.len(), 0.0);
            self.instance
                .get_directional_derivative(&unknowns, &[plan.states[j]], &[1.0], &mut column)
                .map_err(|e| e.to_string())?;
            for (&i, value) in rows.iter().zip(&column) {
                jac[i + j * n] = *value;
            }
        }
        Ok(true)
    }
}

impl ModelExchangeUnit {
    pub(super) fn new(settings: SolverSettings, instance: &mut Instance) -> Result<Self, FmiError> {
        let (states, indicators) = instance.model_exchange_sizes()?;
        let jacobian = match (settings.method, settings.jacobian) {
            (Method::Bdf, JacobianSource::Fmu) => JacobianPlan::of(instance, states),
            _ => None,
        };
        Ok(Self {
            settings,
            states,
            indicators,
            next_time_event: None,
            x: vec![0.0; states],
            events: EventCounts::default(),
            jacobian,
            statistics: Statistics::default(),
        })
    }

    /// After `fmi2ExitInitializationMode`: the instance is in Event Mode; the event iteration
    /// there, then Continuous-Time Mode. `Some(t)` if the FMU ended the run already.
    pub(super) fn start(
        &mut self,
        instance: &mut Instance,
        time: f64,
    ) -> Result<Option<f64>, MeError> {
        if self.event_iteration(instance, time)? {
            return Ok(Some(time));
        }
        instance.enter_continuous_time_mode()?;
        Ok(None)
    }

    /// Integrates from `time` to `time + h`; the FMU is left at the step's end (or where it
    /// ended the run), its outputs ready to read.
    pub(super) fn do_step(
        &mut self,
        instance: &mut Instance,
        time: f64,
        h: f64,
    ) -> Result<StepStatus, MeError> {
        let end = time + h;
        let settings = self.settings;
        let solver = |source, time| MeError::Solver {
            method: settings.method,
            time,
            source,
        };
        instance.set_time(time)?;
        if self.states > 0 {
            instance.get_vector(MeVector::States, &mut self.x)?;
        }
        let plan = self.jacobian.take();
        let mut fmu = Fmu {
            instance,
            states: self.states,
            indicators: self.indicators,
            jacobian: plan.as_ref(),
        };
        let stepped = match Integrator::new(
            settings.method,
            settings.tolerances,
            &mut fmu,
            time,
            &self.x,
        ) {
            Ok(mut integrator) => {
                let stepped = self.integrate(&mut integrator, &mut fmu, end);
                self.add_statistics(integrator.statistics());
                stepped
            }
            Err(e) => Err(solver(e, time)),
        };
        self.jacobian = plan;
        stepped
    }

    /// A scenario event at the communication point `time`, between two steps: Event Mode,
    /// `set`, the event iteration, Continuous-Time Mode; the next step starts its solver
    /// afresh from the states the iteration left. True if the FMU asked to end the run.
    pub(super) fn event(
        &mut self,
        instance: &mut Instance,
        time: f64,
        set: impl FnOnce(&mut Instance) -> Result<(), fmi_import::CallError>,
    ) -> Result<bool, MeError> {
        instance.set_time(time)?;
        instance.enter_event_mode_me()?;
        set(instance).map_err(MeError::Set)?;
        if self.event_iteration(instance, time)? {
            return Ok(true);
        }
        instance.enter_continuous_time_mode()?;
        Ok(false)
    }

    fn add_statistics(&mut self, step: Statistics) {
        let s = &mut self.statistics;
        s.steps += step.steps;
        s.rhs_evaluations += step.rhs_evaluations;
        s.jacobian_evaluations += step.jacobian_evaluations;
        s.system_jacobians += step.system_jacobians;
        s.rejected_steps += step.rejected_steps;
        s.indicator_evaluations += step.indicator_evaluations;
        s.restarts += step.restarts;
    }

    fn integrate(
        &mut self,
        integrator: &mut Integrator,
        fmu: &mut Fmu<'_>,
        end: f64,
    ) -> Result<StepStatus, MeError> {
        let settings = self.settings;
        let solver = |source, time| MeError::Solver {
            method: settings.method,
            time,
            source,
        };
        loop {
            let stop = match self.next_time_event {
                Some(t_event) if t_event < end => t_event.max(integrator.time()),
                _ => end,
            };
            let advance = integrator
                .step(fmu, stop)
                .map_err(|e| solver(e, integrator.time()))?;
            let (t, state_event) = match advance {
                Advance::Step { t } | Advance::Reached { t } => (t, false),
                Advance::StateEvent { t, .. } => (t, true),
            };
            fmu.at(t, integrator.state())
                .map_err(|message| solver(SolverError::System { t, message }, t))?;
            // The accepted step is the FMU's now: it may ask for an event at it.
            let step = fmu.instance.completed_integrator_step()?;
            if step.terminate_simulation {
                return Ok(ended(t));
            }
            let time_event = !state_event && self.next_time_event.is_some_and(|te| te <= t);
            if state_event || time_event || step.enter_event_mode {
                self.events.state += u64::from(state_event);
                self.events.time += u64::from(time_event);
                self.events.step += u64::from(step.enter_event_mode && !state_event && !time_event);
                fmu.instance.enter_event_mode_me()?;
                if self.event_iteration(fmu.instance, t)? {
                    return Ok(ended(t));
                }
                fmu.instance.enter_continuous_time_mode()?;
                if self.states > 0 {
                    fmu.instance.get_vector(MeVector::States, &mut self.x)?;
                } else {
                    self.x.clear();
                }
                integrator
                    .reset(fmu, t, &self.x)
                    .map_err(|e| solver(e, t))?;
            }
            if t >= end {
                return Ok(StepStatus::Complete(Success::Ok));
            }
        }
    }

    /// `fmi2NewDiscreteStates` until no new discrete states are needed; true if the FMU asks
    /// to end the run. Records the next time event.
    fn event_iteration(&mut self, instance: &mut Instance, time: f64) -> Result<bool, MeError> {
        for _ in 0..MAX_EVENT_ITERATIONS {
            let update = instance.update_discrete_states()?;
            if update.terminate_simulation {
                return Ok(true);
            }
            self.next_time_event = update.next_event_time;
            if !update.discrete_states_need_update {
                return Ok(false);
            }
        }
        Err(MeError::EventIteration { time })
    }
}

/// The run ends with this instance's row at `time` (as a Co-Simulation FMU that discards its
/// step with `fmi2Terminated` does).
fn ended(time: f64) -> StepStatus {
    StepStatus::Discarded {
        last_successful_time: time,
        terminated: true,
    }
}
