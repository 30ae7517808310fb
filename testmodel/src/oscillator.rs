//! The model: parameters, state, and the `fmi2_export::Model` implementation.
use crate::dynamics::{Coefficients, State};
use fmi_model::{
    ContinuousModel, Declaration, Dependencies, EventUpdate, Experiment, Log, Model, ModelError,
    StepEnd,
};
use serde::{Deserialize, Serialize};

/// The constant mass (kg) of the oscillator.
pub const MASS_KG: f64 = 1.0;

/// Bisection steps for the threshold crossing: 2^-60 of a sub-step is below f64 resolution.
const CROSSING_BISECTIONS: usize = 60;

/// Which crossings of `threshold` stop the simulation (`crossing_direction`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum Crossing {
    #[default]
    Either = 1,
    Falling = 2,
    Rising = 3,
}

fmi_model::enumeration! {
    Crossing = "Oscillator.Crossing", "Direction of a threshold crossing that stops the simulation" {
        Either: "either", "x crosses the threshold in either direction";
        Falling: "falling", "x falls through the threshold";
        Rising: "rising", "x rises through the threshold";
    }
}

impl Crossing {
    /// Whether going from `before` to `after` (offsets from the threshold) is a crossing.
    fn crossed(self, before: f64, after: f64) -> bool {
        let falling = before > 0.0 && after <= 0.0;
        let rising = before < 0.0 && after >= 0.0;
        match self {
            Crossing::Either => falling || rising,
            Crossing::Falling => falling,
            Crossing::Rising => rising,
        }
    }
}

/// m x'' = -k x - c x' + u with m = 1 kg.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Oscillator {
    pub(crate) x0_m: f64,
    pub(crate) k_n_per_m: f64,
    pub(crate) c_ns_per_m: f64,
    pub(crate) substeps: i32,
    pub(crate) stop_at_threshold: bool,
    pub(crate) threshold_m: f64,
    pub(crate) crossing: Crossing,
    pub(crate) label: String,
    pub(crate) u_n: f64,
    pub(crate) x_m: f64,
    pub(crate) v_m_per_s: f64,
    pub(crate) step_count: i32,
    pub(crate) omega_n_rad_per_s: f64,
    initialized: bool,
    /// Model Exchange: the time the solver set, and x - threshold at the end of
    /// initialization or at the last event (the side a crossing starts from).
    time_s: f64,
    event_offset_m: f64,
}

impl Default for Oscillator {
    /// The start values of every variable.
    fn default() -> Self {
        Oscillator {
            x0_m: 1.0,
            k_n_per_m: 1.0,
            c_ns_per_m: 0.1,
            substeps: 8,
            stop_at_threshold: false,
            threshold_m: 0.0,
            crossing: Crossing::Either,
            label: "oscillator".into(),
            u_n: 0.0,
            x_m: 0.0,
            v_m_per_s: 0.0,
            step_count: 0,
            omega_n_rad_per_s: 0.0,
            initialized: false,
            time_s: 0.0,
            event_offset_m: 0.0,
        }
    }
}

impl Oscillator {
    fn coefficients(&self) -> Coefficients {
        Coefficients {
            mass_kg: MASS_KG,
            k_n_per_m: self.k_n_per_m,
            c_ns_per_m: self.c_ns_per_m,
            u_n: self.u_n,
        }
    }

    fn state(&self) -> State {
        State {
            x_m: self.x_m,
            v_m_per_s: self.v_m_per_s,
        }
    }

    /// x'' at the current state and input.
    pub(crate) fn acceleration(&self) -> f64 {
        (-self.k_n_per_m * self.x_m - self.c_ns_per_m * self.v_m_per_s + self.u_n) / MASS_KG
    }

    /// The event indicator: x - threshold while stop_at_threshold is set, else 1 (no event).
    pub(crate) fn threshold_offset(&self) -> f64 {
        if self.stop_at_threshold {
            self.x_m - self.threshold_m
        } else {
            1.0
        }
    }

    /// The fraction of `dt_s` after `from` at which x reaches the threshold (bisection on
    /// the RK4 step itself, so the stop state lies on the integrated trajectory).
    fn crossing_time(&self, from: State, dt_s: f64) -> f64 {
        let offset = |s: State| s.x_m - self.threshold_m;
        let coefficients = self.coefficients();
        let (mut lo, mut hi) = (0.0, dt_s);
        for _ in 0..CROSSING_BISECTIONS {
            let mid = 0.5 * (lo + hi);
            if self
                .crossing
                .crossed(offset(from), offset(coefficients.rk4(from, mid)))
            {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        hi
    }
}

impl Model for Oscillator {
    const MODEL_IDENTIFIER: &'static str = "Oscillator";
    const MODEL_NAME: &'static str = "Oscillator";
    const VERSION: &'static str = env!("CARGO_PKG_VERSION");
    const DESCRIPTION: &'static str =
        "Damped spring-mass oscillator, the test model of the FMI 2.0 and 3.0 export layers";
    const DEFAULT_EXPERIMENT: Experiment = Experiment {
        start_time: 0.0,
        stop_time: 10.0,
        step_size: 0.01,
        tolerance: None,
    };

    fn declarations() -> &'static [Declaration<Self>] {
        &crate::variables::DECLARATIONS
    }

    fn output_dependencies(_output: &str) -> Dependencies {
        // x, v and step_count are state: the input acts through the integration only.
        Dependencies::NoInputs
    }

    fn calculate_values(&mut self, _log: &mut Log) {
        self.omega_n_rad_per_s = (self.k_n_per_m / MASS_KG).sqrt();
        if !self.initialized {
            // Initial unknowns in initialization mode follow the parameters.
            self.x_m = self.x0_m;
            self.v_m_per_s = 0.0;
        }
    }

    fn validate_restored(&self, initialized: bool) -> Result<(), ModelError> {
        let refuse = |what: &str| Err(ModelError::Other(format!("restored state: {what}")));
        if initialized != self.initialized {
            return refuse("initialization flag disagrees with the instance's state");
        }
        if !(self.x_m.is_finite() && self.v_m_per_s.is_finite()) {
            return refuse("x or v is not finite");
        }
        if self.step_count < 0 || self.substeps < 1 {
            return refuse("negative step_count or substeps below 1");
        }
        if initialized && self.stop_at_threshold && self.x0_m == self.threshold_m {
            return refuse("threshold equals x0 while stop_at_threshold is set");
        }
        Ok(())
    }

    fn exit_initialization(&mut self, start_time: f64, log: &mut Log) -> Result<(), ModelError> {
        if self.stop_at_threshold && self.x0_m == self.threshold_m {
            return Err(ModelError::InvalidParameter {
                field: "threshold_m",
                index: None,
                value: self.threshold_m.to_string(),
                reason: "equals x0 while stop_at_threshold is set: the model would stop at once"
                    .into(),
            });
        }
        self.x_m = self.x0_m;
        self.v_m_per_s = 0.0;
        self.step_count = 0;
        self.initialized = true;
        self.time_s = start_time;
        self.event_offset_m = self.x_m - self.threshold_m;
        log.info(format!(
            "{}: x0 = {} m, k = {} N/m, c = {} N.s/m",
            self.label, self.x0_m, self.k_n_per_m, self.c_ns_per_m
        ));
        Ok(())
    }

    fn do_step(&mut self, t: f64, h: f64, log: &mut Log) -> Result<StepEnd, ModelError> {
        let n = self.substeps.max(1);
        let dt_s = h / f64::from(n);
        let omega_n = (self.k_n_per_m / MASS_KG).sqrt();
        if omega_n * dt_s > 0.5 {
            log.warning(format!(
                "sub-step {dt_s} s is coarse for omega_n = {omega_n} rad/s (omega_n dt > 0.5): \
                 raise substeps"
            ));
        }
        let coefficients = self.coefficients();
        self.step_count = self.step_count.saturating_add(1);
        for i in 0..n {
            let from = self.state();
            let mut to = coefficients.rk4(from, dt_s);
            let crossed = self.stop_at_threshold
                && self
                    .crossing
                    .crossed(from.x_m - self.threshold_m, to.x_m - self.threshold_m);
            let mut stop = None;
            if crossed {
                let tau = self.crossing_time(from, dt_s);
                to = coefficients.rk4(from, tau);
                stop = Some((t + f64::from(i) * dt_s + tau).min(t + h));
            }
            if !(to.x_m.is_finite() && to.v_m_per_s.is_finite()) {
                return Err(ModelError::Other(format!(
                    "state diverged at t = {} s: x = {} m, v = {} m/s",
                    t + f64::from(i) * dt_s,
                    to.x_m,
                    to.v_m_per_s
                )));
            }
            self.x_m = to.x_m;
            self.v_m_per_s = to.v_m_per_s;
            if let Some(time) = stop {
                return Ok(StepEnd::Stopped {
                    time,
                    terminated: true,
                    reason: format!("x crossed the threshold {} m", self.threshold_m),
                });
            }
        }
        Ok(StepEnd::Complete)
    }
}

/// Model Exchange: the states x and v, one event indicator (x - threshold) while
/// stop_at_threshold is set; a crossing in the selected direction ends the simulation.
impl ContinuousModel for Oscillator {
    const STATE_DERIVATIVES: &'static [(&'static str, &'static str)] =
        &[("x", "der_x"), ("v", "der_v")];
    const EVENT_INDICATORS: usize = 1;
    const EVENT_INDICATOR_VARIABLES: &'static [&'static str] = &["threshold_offset"];

    fn state_count(&self) -> usize {
        2
    }

    fn event_indicator_count(&self) -> usize {
        1
    }

    fn set_time(&mut self, t: f64) {
        self.time_s = t;
    }

    fn states(&self, x: &mut [f64]) {
        x.copy_from_slice(&[self.x_m, self.v_m_per_s]);
    }

    fn set_states(&mut self, x: &[f64]) -> Result<(), ModelError> {
        let [x_m, v_m_per_s] = *x else {
            return Err(ModelError::Other(format!(
                "{} states given, 2 expected",
                x.len()
            )));
        };
        self.x_m = x_m;
        self.v_m_per_s = v_m_per_s;
        Ok(())
    }

    fn nominals(&self, nominal: &mut [f64]) {
        nominal.fill(1.0);
    }

    fn derivatives(&mut self, dx: &mut [f64]) -> Result<(), ModelError> {
        dx.copy_from_slice(&[self.v_m_per_s, self.acceleration()]);
        Ok(())
    }

    fn event_indicators(&mut self, z: &mut [f64]) -> Result<(), ModelError> {
        z.fill(self.threshold_offset());
        Ok(())
    }

    fn update_discrete_states(&mut self, log: &mut Log) -> Result<EventUpdate, ModelError> {
        if !self.initialized || !self.stop_at_threshold {
            return Ok(EventUpdate::default());
        }
        let offset = self.x_m - self.threshold_m;
        let crossed = self.crossing.crossed(self.event_offset_m, offset);
        self.event_offset_m = offset;
        if crossed {
            log.info(format!(
                "x crossed the threshold {} m at t = {} s",
                self.threshold_m, self.time_s
            ));
        }
        Ok(EventUpdate {
            terminate: crossed,
            ..EventUpdate::default()
        })
    }
}
