//! Model Exchange for LanderPlant: the flat ODE of `physics::continuous` behind the FMI
//! layers' continuous-state calls. The state vector has a fixed length (a model description
//! is static): all 18 states, the lag states with a zero derivative while their lag is off.
use super::LanderPlant;
use crate::physics::continuous::{
    LengthMismatch, StateElement, StateLayout, Unevaluable, EVENT_INDICATOR_COUNT,
};
use crate::physics::plant::{Plant, PlantRun};
use fmi_model::{ContinuousModel, Dependencies, EventUpdate, Log, ModelError};
use std::borrow::Cow;

const LAYOUT: StateLayout = StateLayout::ALL;
/// Where each declared state starts in the vector (`physics::continuous` order).
pub(super) const TRANSLATION: usize = 0;
pub(super) const ATTITUDE: usize = 6;
pub(super) const THRUST_LAG: usize = 14;
pub(super) const TORQUE_LAG: usize = 15;
pub(super) const STATE_COUNT: usize = 18;

fn not_running() -> ModelError {
    ModelError::Other("no continuous state before the end of initialization".into())
}

fn length(e: LengthMismatch) -> ModelError {
    ModelError::Other(format!("continuous state vector: {e}"))
}

/// A refused state element as the layers name it: the declaration's field (see the
/// `field` options of the continuous-state declarations) and the 0-based element.
pub(super) fn refused_state(e: Unevaluable) -> ModelError {
    let (field, index) = match e.element {
        StateElement::Translation(i) => ("translation_state", Some(i)),
        StateElement::Attitude => ("attitude_state", None),
        StateElement::AttitudeComponent(i) => ("attitude_state", Some(i)),
        StateElement::OmegaBody(i) => ("omega_body", Some(i)),
        StateElement::Mass => ("mass", None),
        StateElement::ThrustLag => ("thrust_lag_state", None),
        StateElement::TorqueLag(i) => ("torque_lag_state_body", Some(i)),
    };
    ModelError::InvalidInput {
        field,
        index,
        value: e.value,
        reason: e.reason,
    }
}

/// The declared name of element `i` of a vector laid out as `names` (each with its length),
/// 1-based: `der_omega_body[2]`.
fn element_name(names: &[(&str, usize)], mut i: usize) -> String {
    for (name, len) in names {
        if i < *len {
            return if *len == 1 {
                (*name).to_string()
            } else {
                format!("{name}[{}]", i + 1)
            };
        }
        i -= len;
    }
    format!("element {i}")
}

const DERIVATIVE_NAMES: &[(&str, usize)] = &[
    ("der_translation_state", 6),
    ("der_attitude_state", 4),
    ("der_omega_body", 3),
    ("der_mass", 1),
    ("der_thrust_lag_state", 1),
    ("der_torque_lag_state_body", 3),
];

/// The second net behind `check_evaluable`: a value computed at an accepted state that is
/// still not finite (e.g. under a parameter such as a denormal time constant) is an error
/// naming it, never a NaN handed out with status OK.
fn all_finite(values: &[f64], name: impl Fn(usize) -> String) -> Result<(), ModelError> {
    match values.iter().position(|v| !v.is_finite()) {
        None => Ok(()),
        Some(i) => Err(ModelError::Other(format!(
            "{} = {} at the current state: not finite",
            name(i),
            values[i]
        ))),
    }
}

/// What Model Exchange does not model: the landing gear (its contact is stiff and its
/// touchdown, cut-off and tip-over are events of the Co-Simulation step only), a throttle
/// rate limit without an engine lag (its rate jumps at the target: the Co-Simulation step
/// ends the ramp exactly there), the RCS valve delay (a history of the master's commands), slosh (pendulum states outside
/// the fixed state vector).
/// Refused by every call that hands out a derivative or takes a state, naming the parameter.
pub(super) fn co_simulation_only(plant: &Plant) -> Result<(), ModelError> {
    if plant.gear.is_some() {
        return Err(ModelError::InvalidParameter {
            field: "gear.enabled",
            index: None,
            value: "true".into(),
            reason: "the landing gear is modelled in Co-Simulation only; in Model Exchange \
                     set gear_enabled = false (see docs/plant-gear.md)"
                .into(),
        });
    }
    if plant.throttle_rate_limit_nps > 0.0 && plant.engines.time_constant_s == 0.0 {
        return Err(ModelError::InvalidParameter {
            field: "actuators.throttle_rate_limit_nps",
            index: None,
            value: plant.throttle_rate_limit_nps.to_string(),
            reason: "a throttle rate limit without an engine lag is modelled in Co-Simulation \
                     only; in Model Exchange also set engine_time_constant > 0 \
                     (docs/plant-actuators.md)"
                .into(),
        });
    }
    if plant.slosh.is_some() {
        return Err(ModelError::InvalidParameter {
            field: "slosh.enabled",
            index: None,
            value: "true".into(),
            reason: "propellant slosh is modelled in Co-Simulation only (its pendulum states \
                     are not in the fixed Model Exchange state vector; docs/plant-slosh.md)"
                .into(),
        });
    }
    if plant.rcs_valve_delay_s > 0.0 {
        return Err(ModelError::InvalidParameter {
            field: "actuators.rcs_valve_delay_s",
            index: None,
            value: plant.rcs_valve_delay_s.to_string(),
            reason: "the RCS valve delay is modelled in Co-Simulation only \
                     (docs/plant-actuators.md)"
                .into(),
        });
    }
    Ok(())
}

impl LanderPlant {
    /// The plant and its run: the running one, or in initialization the one the current
    /// parameters give (`None` while they are invalid).
    pub(super) fn continuous_view(&self) -> Option<Cow<'_, (Plant, PlantRun)>> {
        match &self.running {
            Some(running) => Some(Cow::Borrowed(running)),
            None => Plant::new(&self.parameters)
                .ok()
                .map(|(plant, run, _)| Cow::Owned((plant, run))),
        }
    }

    /// Element `i` of the state vector (0 while the parameters are invalid).
    pub(super) fn state_element(&self, i: usize) -> f64 {
        let mut x = [0.0; STATE_COUNT];
        if let Some(view) = self.continuous_view() {
            let _ = LAYOUT.pack(&view.1.state, &mut x);
        }
        x[i]
    }

    /// Event indicator `i` (0 while the parameters are invalid).
    pub(super) fn event_indicator(&self, i: usize) -> f64 {
        self.continuous_view()
            .map_or(0.0, |view| view.0.event_indicators(&view.1)[i])
    }

    /// Element `i` of the state derivative at the current state and inputs.
    pub(super) fn derivative_element(&self, i: usize) -> f64 {
        let mut dx = [0.0; STATE_COUNT];
        if let Some(view) = self.continuous_view() {
            let (plant, run) = view.as_ref();
            let _ = plant.continuous_derivative(&LAYOUT, run, &self.commands, &mut dx);
        }
        dx[i]
    }
}

impl ContinuousModel for LanderPlant {
    const STATE_DERIVATIVES: &'static [(&'static str, &'static str)] = &[
        ("translation_state", "der_translation_state"),
        ("attitude_state", "der_attitude_state"),
        ("omega_body", "der_omega_body"),
        ("mass", "der_mass"),
        ("thrust_lag_state", "der_thrust_lag_state"),
        ("torque_lag_state_body", "der_torque_lag_state_body"),
    ];
    const EVENT_INDICATORS: usize = EVENT_INDICATOR_COUNT;
    const EVENT_INDICATOR_VARIABLES: &'static [&'static str] =
        &["touchdown_indicator", "exhaustion_indicator"];
    const DECLARES_STATE_DEPENDENCIES: bool = true;

    /// Which states each output and state derivative depends on under Model Exchange, for
    /// every configuration it admits (a lag or mass properties on or off, either translation
    /// model): exactly what `physics::sensitivity` reads.
    fn state_dependencies(unknown: &str) -> Option<&'static [&'static str]> {
        Some(match unknown {
            "r_nue" | "v_nue" | "altitude" => &["translation_state"],
            "q_body_to_nue" => &["attitude_state"],
            "omega_body" | "omega_mean_body" => &["omega_body"],
            "mass" | "propellant_used" => &["mass"],
            "thrust_actual" => &["thrust_lag_state"],
            "engine_torque_body" | "specific_force_body" | "specific_force_mean_body" => {
                &["mass", "thrust_lag_state"]
            }
            "torque_actual_body" => &["torque_lag_state_body"],
            "der_translation_state" => &[
                "translation_state",
                "attitude_state",
                "mass",
                "thrust_lag_state",
            ],
            "der_attitude_state" => &["attitude_state", "omega_body"],
            "der_omega_body" => &[
                "omega_body",
                "mass",
                "thrust_lag_state",
                "torque_lag_state_body",
            ],
            "der_mass" => &["thrust_lag_state", "torque_lag_state_body"],
            "der_thrust_lag_state" => &["thrust_lag_state"],
            "der_torque_lag_state_body" => &["torque_lag_state_body"],
            // The gear's, the pendulums' and the thrusters' force: Co-Simulation only, or
            // constant.
            _ => &[],
        })
    }

    /// Within the declarations: what each element reads, over both translation models
    /// (flat: `r' = v`, `v' = a - g`; spherical: `r' = w`, `lon' = u / (r cos lat)`,
    /// `lat' = v / r`, and `w'` free of `w`), Euler's equations about principal axes (`w_i'`
    /// free of `w_i`) and per-axis torques and lags.
    fn depends_on_element(
        unknown: &str,
        element: usize,
        known: &str,
        known_element: usize,
    ) -> bool {
        let same = element == known_element;
        match (unknown, known) {
            ("r_nue", "translation_state") => known_element < 3,
            ("altitude", "translation_state") => known_element < 2,
            ("v_nue", "translation_state") => known_element > 0,
            ("omega_body" | "omega_mean_body", "omega_body") => same,
            ("torque_actual_body", "torque_lag_state_body" | "torque_cmd_body") => same,
            ("der_translation_state", "translation_state") => match element {
                0 => matches!(known_element, 3 | 5),
                1 => matches!(known_element, 0 | 2 | 3 | 4),
                2 => matches!(known_element, 0 | 4 | 5),
                5 => known_element != 5,
                _ => true,
            },
            // Position rates are velocities: no thrust, attitude or mass in them.
            ("der_translation_state", _) => element >= 3,
            ("der_omega_body", "omega_body") => !same,
            ("der_omega_body", "torque_lag_state_body" | "torque_cmd_body") => same,
            ("der_torque_lag_state_body", "torque_lag_state_body") => same,
            _ => true,
        }
    }

    fn derivative_input_dependencies(derivative: &str) -> Dependencies {
        match derivative {
            "der_translation_state" | "der_thrust_lag_state" => {
                Dependencies::Inputs(&["thrust_cmd"])
            }
            "der_omega_body" | "der_mass" => {
                Dependencies::Inputs(&["thrust_cmd", "torque_cmd_body"])
            }
            "der_torque_lag_state_body" => Dependencies::SameElementOf("torque_cmd_body"),
            _ => Dependencies::NoInputs,
        }
    }

    fn state_count(&self) -> usize {
        STATE_COUNT
    }

    fn event_indicator_count(&self) -> usize {
        EVENT_INDICATOR_COUNT
    }

    fn set_time(&mut self, t: f64) {
        self.time_s = t;
    }

    fn states(&self, x: &mut [f64]) {
        if let Some(view) = self.continuous_view() {
            let _ = LAYOUT.pack(&view.1.state, x);
        }
    }

    fn check_state_vector(&self, x: &[f64]) -> Result<(), ModelError> {
        let (plant, _) = self.running.as_ref().ok_or_else(not_running)?;
        let candidate = LAYOUT.unpack(x).map_err(length)?;
        plant.check_evaluable(&candidate).map_err(refused_state)
    }

    fn set_states(&mut self, x: &[f64]) -> Result<(), ModelError> {
        let (plant, run) = self.running.as_mut().ok_or_else(not_running)?;
        co_simulation_only(plant)?;
        // Checked before it replaces anything: a refused vector leaves the run as it was.
        let mut candidate = *run;
        plant
            .set_continuous_states(&LAYOUT, &mut candidate, x)
            .map_err(length)?;
        plant
            .check_evaluable(&candidate.state)
            .map_err(refused_state)?;
        *run = candidate;
        Ok(())
    }

    fn nominals(&self, nominal: &mut [f64]) {
        if let Some(view) = self.continuous_view() {
            let _ = view.0.nominals(&LAYOUT, nominal);
        }
    }

    fn derivatives(&mut self, dx: &mut [f64]) -> Result<(), ModelError> {
        let view = self.continuous_view().ok_or_else(not_running)?;
        let (plant, run) = view.as_ref();
        co_simulation_only(plant)?;
        plant
            .continuous_derivative(&LAYOUT, run, &self.commands, dx)
            .map_err(length)?;
        all_finite(dx, |i| element_name(DERIVATIVE_NAMES, i))
    }

    fn event_indicators(&mut self, z: &mut [f64]) -> Result<(), ModelError> {
        let view = self.continuous_view().ok_or_else(not_running)?;
        let (plant, run) = view.as_ref();
        co_simulation_only(plant)?;
        let values = plant.event_indicators(run);
        if z.len() != values.len() {
            return Err(length(LengthMismatch {
                expected: values.len(),
                got: z.len(),
            }));
        }
        all_finite(&values, |i| Self::EVENT_INDICATOR_VARIABLES[i].to_string())?;
        z.copy_from_slice(&values);
        Ok(())
    }

    /// Touchdown freezes the touchdown outputs and ends the run; exhaustion cuts the
    /// engines; both as the Co-Simulation step does at its located events.
    fn update_discrete_states(&mut self, log: &mut Log) -> Result<EventUpdate, ModelError> {
        // A fault set in this Event Mode acts from here on.
        self.apply_faults()?;
        let t = self.time_s;
        let Some((plant, run)) = self.running.as_mut() else {
            // The initial event update at the end of initialization has nothing to do.
            return Ok(EventUpdate::default());
        };
        let before = *run;
        let outcome = plant.update_at_event(run, t);
        // set_states admits only states the update can renormalise; should one still come
        // out unevaluable, the run stays as it was rather than poisoned for good.
        if let Err(e) = plant.check_evaluable(&run.state) {
            *run = before;
            return Err(ModelError::Other(format!(
                "the event update at t = {t} s would leave {e}; the state is kept as it was"
            )));
        }
        if outcome.exhausted {
            log.warning(format!(
                "propellant exhausted at t = {t} s: mass = dry_mass = {} kg, engines cut",
                plant.dry_mass_kg
            ));
        }
        if let (true, Some(td)) = (outcome.touchdown, run.touchdown) {
            log.info(format!(
                "touchdown at t = {t} s: v_nue = [{:.3}, {:.3}, {:.3}] m/s, tilt = {:.2} deg",
                td.v_nue_mps.0.x,
                td.v_nue_mps.0.y,
                td.v_nue_mps.0.z,
                td.tilt_rad.to_degrees()
            ));
        }
        Ok(EventUpdate {
            terminate: run.touchdown.is_some(),
            states_changed: run.state != before.state,
            nominals_changed: false,
        })
    }
}
