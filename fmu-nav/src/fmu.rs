//! The FMI face of the navigation errors: the variable table (each variable declared once)
//! and the [`Model`] implementation. The outputs carry the names LanderPlant outputs and
//! LanderGnc reads, so the FMU slots in between without renaming; the inputs are the same
//! signals with `_true` appended.
//!
//! Timing (see [`crate::errors::navigation`]): the outputs at a communication point are the
//! inputs there (or `latency` steps earlier) with the error of the interval that starts
//! there; `fmi2DoStep` records the inputs and draws the next interval's error.
use crate::errors::{Group, NavErrors, NavParameters, Navigation, LATENCY_CAP_STEPS};
use fmi_model::parameter::{check_declared, ParameterError};
use fmi_model::{
    decl, role, same_names, Declaration, Dependencies, Experiment, Log, MatchingRule, Member,
    Model, ModelError, Shape, StepEnd, Terminal,
};
use lander_math::signal_groups as groups;
use serde::{Deserialize, Serialize};

/// The LanderNav FMU instance. Everything lives here: no global state.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct LanderNav {
    params: NavParameters,
    truth: Navigation,
    estimate: Navigation,
    /// Set by `exit_initialization` from the validated parameters.
    running: Option<NavErrors>,
}

impl LanderNav {
    /// The parameters (for tests and tools).
    pub fn parameters(&self) -> &NavParameters {
        &self.params
    }

    /// Each parameter against its declaration, then what declarations cannot say.
    fn check_parameters(&self) -> Result<(), ParameterError> {
        check_declared(self)?;
        self.params.validate()
    }
}

impl NavParameters {
    /// Every check of the parameters, for errors built without an FMI layer: each value
    /// against its declaration (as the layer checks it on every set), then
    /// [`NavParameters::validate`].
    pub fn check(&self) -> Result<(), ParameterError> {
        LanderNav {
            params: *self,
            ..LanderNav::default()
        }
        .check_parameters()
    }
}

/// The truth comes in under the navigation members' names, so the plant's navigation
/// terminal connects to it.
const TRUTH: [Member; 5] = [
    Member {
        member: groups::NAVIGATION[0],
        variable: "r_nue_true",
    },
    Member {
        member: groups::NAVIGATION[1],
        variable: "v_nue_true",
    },
    Member {
        member: groups::NAVIGATION[2],
        variable: "q_body_to_nue_true",
    },
    Member {
        member: groups::NAVIGATION[3],
        variable: "omega_body_true",
    },
    Member {
        member: groups::NAVIGATION[4],
        variable: "mass_true",
    },
];

const TERMINALS: &[Terminal] = &[
    Terminal {
        name: "truth",
        matching_rule: MatchingRule::Plug,
        kind: groups::NAVIGATION_KIND,
        description: "The true vehicle state, from the plant",
        members: &TRUTH,
    },
    Terminal {
        name: "navigation",
        matching_rule: MatchingRule::Plug,
        kind: groups::NAVIGATION_KIND,
        description: "The navigated vehicle state, for the controller",
        members: &same_names(groups::NAVIGATION),
    },
];

impl Model for LanderNav {
    const MODEL_IDENTIFIER: &'static str = "LanderNav";
    const MODEL_NAME: &'static str = "LanderNav";
    const VERSION: &'static str = env!("CARGO_PKG_VERSION");
    const DESCRIPTION: &'static str = "Navigation errors between the lunar lander plant and its GNC: white noise, \
         bias, random walk, quantisation and latency per signal group, seeded and reproducible; the identity by default";
    const DEFAULT_EXPERIMENT: Experiment = Experiment {
        start_time: 0.0,
        stop_time: 172.0,
        step_size: 0.01,
        tolerance: None,
    };

    fn declarations() -> &'static [Declaration<Self>] {
        DECLARATIONS
    }

    fn terminals() -> &'static [Terminal] {
        TERMINALS
    }

    fn output_dependencies(output: &str) -> Dependencies {
        // Each estimate depends on its own true signal only: element by element, except the
        // quaternion, whose every element mixes all four of the true one.
        match output {
            "r_nue" => Dependencies::SameElementOf("r_nue_true"),
            "v_nue" => Dependencies::SameElementOf("v_nue_true"),
            "q_body_to_nue" => Dependencies::Inputs(&["q_body_to_nue_true"]),
            "omega_body" => Dependencies::SameElementOf("omega_body_true"),
            "mass" => Dependencies::Inputs(&["mass_true"]),
            _ => Dependencies::AllInputs,
        }
    }

    fn calculate_values(&mut self, _log: &mut Log) {
        // In initialization mode, the first interval's errors as the parameters now give them
        // (a function of the parameters only, so the run starts with exactly these).
        self.estimate = match &self.running {
            Some(errors) => errors.estimate(&self.params, &self.truth),
            // Parameters set but not yet validated may overflow (an attitude bias of 1e279
            // rad): then the inputs are shown unchanged, and exit_initialization names the
            // parameter at fault.
            None => {
                let errors = NavErrors::start(&self.params);
                let valid =
                    self.check_parameters().is_ok() && errors.overflowing(&self.params).is_none();
                if valid {
                    errors.estimate(&self.params, &self.truth)
                } else {
                    self.truth
                }
            }
        };
    }

    fn exit_initialization(&mut self, _start_time: f64, _log: &mut Log) -> Result<(), ModelError> {
        self.check_parameters()?;
        let errors = NavErrors::start(&self.params);
        if let Some(group) = errors.overflowing(&self.params) {
            return Err(overflow(&self.params, group, "at the start"));
        }
        self.running = Some(errors);
        Ok(())
    }

    fn validate_restored(&self, initialized: bool) -> Result<(), ModelError> {
        match (initialized, &self.running) {
            (false, None) => Ok(()),
            (true, Some(errors)) => {
                self.check_parameters()?;
                match errors.inconsistency(&self.params) {
                    Some(why) => Err(ModelError::Other(format!("restored state: {why}"))),
                    None => Ok(()),
                }
            }
            _ => Err(ModelError::Other(format!(
                "restored state: initialized = {initialized} disagrees with the model's run"
            ))),
        }
    }

    fn do_step(&mut self, t: f64, h: f64, _log: &mut Log) -> Result<StepEnd, ModelError> {
        let Some(errors) = self.running.as_mut() else {
            return Err(ModelError::Other(
                "do_step before exit_initialization".into(),
            ));
        };
        errors.step(&self.params, &self.truth, h).map_err(|group| {
            let when = format!("in the step from t = {t} s (communicationStepSize {h} s)");
            overflow(&self.params, group, &when)
        })?;
        Ok(StepEnd::Complete)
    }
}

/// The refusal of an error that would not be finite, naming the group's parameters.
fn overflow(params: &NavParameters, group: Group, when: &str) -> ModelError {
    let (g, errors) = (group.name(), params.group(group));
    ModelError::Other(format!(
        "the {g} error would overflow {when}: {g}_noise_sigma = {}, {g}_random_walk = {} \
         and the bias are too large",
        errors.noise_sigma, errors.random_walk,
    ))
}

const NUE: &[&str] = &["North", "Up", "East"];
const BODY: &[&str] = &[
    "about body x (yaw)",
    "about body y (roll, the thrust axis)",
    "about body z (pitch)",
];
const QUATERNION: &[&str] = &[
    "scalar part",
    "vector part x",
    "vector part y",
    "vector part z",
];
const CAP: i32 = LATENCY_CAP_STEPS;

/// The declarations, one line each so that they read as a table. Start values are those of
/// `LanderNav::default()` (every error off); the bounds of each value are checked from here
/// only (`fmi_model::parameter::check_declared`), latency <= max_latency_steps in
/// `NavParameters::validate`.
#[rustfmt::skip]
static DECLARATIONS: &[Declaration<LanderNav>] = &[
    // Inputs: LanderPlant's navigation outputs.
    decl!(1, input r_nue_true[3]: truth.r_nue_m, "m", "True position of the centre of mass (LanderPlant r_nue)", components = NUE),
    decl!(4, input v_nue_true[3]: truth.v_nue_mps, "m/s", "True velocity relative to the surface (LanderPlant v_nue)", components = NUE),
    decl!(7, input q_body_to_nue_true[4]: truth.q_body_to_nue, "1", "True attitude quaternion body to NUE, Hamilton (LanderPlant q_body_to_nue)", components = QUATERNION),
    decl!(11, input omega_body_true[3]: truth.omega_body_radps, "rad/s", "True body rate (LanderPlant omega_body)", components = BODY),
    decl!(14, input mass_true: truth.mass_kg, "kg", "True mass (LanderPlant mass)"),
    // Outputs: the estimates LanderGnc reads.
    decl!(100, output r_nue[3]: estimate.r_nue_m, "m", "Estimated position", components = NUE),
    decl!(103, output v_nue[3]: estimate.v_nue_mps, "m/s", "Estimated velocity", components = NUE),
    decl!(106, output q_body_to_nue[4]: estimate.q_body_to_nue, "1", "Estimated attitude quaternion body to NUE (true attitude rotated by the body-axis error)", components = QUATERNION),
    decl!(110, output omega_body[3]: estimate.omega_body_radps, "rad/s", "Estimated body rate", components = BODY),
    decl!(113, output mass: estimate.mass_kg, "kg", "Estimated mass"),
    // Common parameters.
    decl!(200, parameter seed: params.seed as i32, "Seed of the noise and random-walk draws (the same seed gives the same errors, bit for bit)", int_min = 0),
    decl!(201, parameter max_latency_steps: params.max_latency_steps as i32, "Bound of every *_latency; the FMU keeps that many past inputs at most", int_min = 0, int_max = CAP),
    // Position errors.
    decl!(210, parameter r_nue_noise_sigma: params.r_nue.noise_sigma, "m", "Standard deviation of the white noise on each axis, a new sample per communication step", min = 0.0),
    decl!(211, parameter r_nue_bias[3]: params.r_nue.bias, "m", "Constant position error", components = NUE),
    decl!(214, parameter r_nue_random_walk: params.r_nue.random_walk, "m", "Random walk on each axis: its standard deviation after 1 s (it grows as the square root of time)", min = 0.0),
    decl!(215, parameter r_nue_quantum: params.r_nue.quantum, "m", "Resolution: each estimated component is rounded to a multiple of it (0 = none)", min = 0.0),
    decl!(216, parameter r_nue_latency: params.r_nue.latency_steps as i32, "Communication steps by which the position is late (0 = none)", int_min = 0, int_max = CAP),
    // Velocity errors.
    decl!(220, parameter v_nue_noise_sigma: params.v_nue.noise_sigma, "m/s", "Standard deviation of the white noise on each axis, a new sample per communication step", min = 0.0),
    decl!(221, parameter v_nue_bias[3]: params.v_nue.bias, "m/s", "Constant velocity error", components = NUE),
    decl!(224, parameter v_nue_random_walk: params.v_nue.random_walk, "m/s", "Random walk on each axis: its standard deviation after 1 s (it grows as the square root of time)", min = 0.0),
    decl!(225, parameter v_nue_quantum: params.v_nue.quantum, "m/s", "Resolution: each estimated component is rounded to a multiple of it (0 = none)", min = 0.0),
    decl!(226, parameter v_nue_latency: params.v_nue.latency_steps as i32, "Communication steps by which the velocity is late (0 = none)", int_min = 0, int_max = CAP),
    // Attitude errors: a small rotation about the body axes.
    decl!(230, parameter attitude_noise_sigma: params.attitude.noise_sigma, "rad", "Standard deviation of the white noise rotation about each body axis, a new sample per communication step", min = 0.0),
    decl!(231, parameter attitude_bias[3]: params.attitude.bias, "rad", "Constant attitude error, a rotation vector in body axes", components = BODY),
    decl!(234, parameter attitude_random_walk: params.attitude.random_walk, "rad", "Random walk of the rotation about each body axis: its standard deviation after 1 s (it grows as the square root of time)", min = 0.0),
    decl!(236, parameter attitude_latency: params.attitude.latency_steps as i32, "Communication steps by which the attitude is late (0 = none)", int_min = 0, int_max = CAP),
    // Body-rate errors.
    decl!(240, parameter omega_body_noise_sigma: params.omega_body.noise_sigma, "rad/s", "Standard deviation of the white noise on each axis, a new sample per communication step", min = 0.0),
    decl!(241, parameter omega_body_bias[3]: params.omega_body.bias, "rad/s", "Constant rate error", components = BODY),
    decl!(244, parameter omega_body_random_walk: params.omega_body.random_walk, "rad/s", "Random walk on each axis: its standard deviation after 1 s (it grows as the square root of time)", min = 0.0),
    decl!(245, parameter omega_body_quantum: params.omega_body.quantum, "rad/s", "Resolution: each estimated component is rounded to a multiple of it (0 = none)", min = 0.0),
    decl!(246, parameter omega_body_latency: params.omega_body.latency_steps as i32, "Communication steps by which the body rate is late (0 = none)", int_min = 0, int_max = CAP),
    // Mass errors.
    decl!(250, parameter mass_noise_sigma: params.mass.noise_sigma, "kg", "Standard deviation of the white noise, a new sample per communication step", min = 0.0),
    Declaration::real(251, "mass_bias", role::parameter, Shape::Scalar, "kg", "Constant mass error", |m: &LanderNav, _| m.params.mass.bias[0], |m: &mut LanderNav, _, v| m.params.mass.bias[0] = v).field("params.mass.bias"),
    decl!(254, parameter mass_random_walk: params.mass.random_walk, "kg", "Random walk: its standard deviation after 1 s (it grows as the square root of time)", min = 0.0),
    decl!(255, parameter mass_quantum: params.mass.quantum, "kg", "Resolution: the estimate is rounded to a multiple of it (0 = none)", min = 0.0),
    decl!(256, parameter mass_latency: params.mass.latency_steps as i32, "Communication steps by which the mass is late (0 = none)", int_min = 0, int_max = CAP),
];

#[cfg(test)]
mod tests {
    use super::*;
    use fmi_model::Causality;

    #[test]
    fn an_attitude_bias_too_large_to_square_shows_finite_outputs_and_is_refused() {
        // Found by the call_sequence fuzz target: 1e279 rad is finite, its square is not.
        let mut nav = LanderNav::default();
        nav.params.attitude.bias[0] = -3.969e279;
        nav.calculate_values(&mut Log::default());
        assert!(nav.estimate.q_body_to_nue.iter().all(|q| q.is_finite()));
        let err = nav
            .exit_initialization(0.0, &mut Log::default())
            .unwrap_err();
        assert!(
            err.to_string().contains("attitude error would overflow"),
            "{err}"
        );
    }

    #[test]
    fn a_restored_state_must_agree_with_initialization_and_its_parameters() {
        let mut nav = LanderNav::default();
        assert_eq!(nav.validate_restored(false), Ok(()));
        assert!(nav.validate_restored(true).is_err());
        nav.exit_initialization(0.0, &mut Log::default()).unwrap();
        nav.do_step(0.0, 0.01, &mut Log::default()).unwrap();
        assert_eq!(nav.validate_restored(true), Ok(()));
        assert!(nav.validate_restored(false).is_err());
    }

    #[test]
    fn the_export_layer_accepts_the_declarations() {
        assert_eq!(fmi2_export::check_table::<LanderNav>(), Ok(()));
    }

    /// Exact ModelStructure: each estimate depends on its own true signal only (element by
    /// element where that holds), never on another signal.
    #[test]
    fn each_output_depends_on_its_own_input_only() {
        let vars = fmi2_export::variables::<LanderNav>();
        let index_of = |name: &str| 1 + vars.iter().position(|v| v.name() == name).unwrap() as u32;
        let structure = fmi2_export::model_description::<LanderNav>().model_structure;
        let outputs = structure.outputs.expect("outputs listed");
        let mut checked = 0;
        for (i, v) in vars.iter().enumerate() {
            if v.causality != Causality::Output {
                continue;
            }
            let unknown = outputs
                .unknowns
                .iter()
                .find(|u| u.index == i as u32 + 1)
                .unwrap_or_else(|| panic!("{} is not listed", v.name()));
            let deps: Vec<u32> = unknown
                .dependencies
                .as_deref()
                .expect("dependencies declared")
                .split_whitespace()
                .map(|d| d.parse().unwrap())
                .collect();
            let expected: Vec<u32> = if v.name().starts_with("q_body_to_nue[") {
                (1..=4)
                    .map(|k| index_of(&format!("q_body_to_nue_true[{k}]")))
                    .collect()
            } else {
                let true_name = match v.name().split_once('[') {
                    Some((base, element)) => format!("{base}_true[{element}"),
                    None => format!("{}_true", v.name()),
                };
                vec![index_of(&true_name)]
            };
            assert_eq!(deps, expected, "{}", v.name());
            checked += 1;
        }
        assert_eq!(checked, 14);
    }

    #[test]
    fn the_estimates_carry_the_names_the_plant_outputs_and_the_gnc_reads() {
        let vars = fmi2_export::variables::<LanderNav>();
        for base in ["r_nue", "v_nue", "q_body_to_nue", "omega_body", "mass"] {
            for v in vars
                .iter()
                .filter(|v| v.name() == base || v.name().starts_with(&format!("{base}[")))
            {
                assert_eq!(v.causality, Causality::Output, "{}", v.name());
            }
            let true_name = format!("{base}_true");
            assert!(vars
                .iter()
                .any(|v| v.name().starts_with(&true_name) && v.causality == Causality::Input));
        }
    }

    #[test]
    fn a_latency_beyond_the_bound_is_refused_by_name_at_exit_initialization() {
        let mut m = LanderNav::default();
        m.params.max_latency_steps = 2;
        m.params.attitude.latency_steps = 3;
        let err = m.exit_initialization(0.0, &mut Log::default()).unwrap_err();
        assert!(
            matches!(
                err,
                ModelError::InvalidParameter {
                    field: "attitude.latency_steps",
                    ..
                }
            ),
            "{err:?}"
        );
        assert!(m.running.is_none());
    }

    #[test]
    fn a_step_that_would_overflow_an_error_is_refused_by_name_and_changes_nothing() {
        // GIVEN a random walk so wide that an enormous step overflows it
        let mut m = LanderNav::default();
        m.params.v_nue.random_walk = 1e200;
        let mut log = Log::default();
        m.exit_initialization(0.0, &mut log).unwrap();
        m.do_step(0.0, 0.01, &mut log).unwrap();
        let before = m.running.clone();
        // WHEN a master asks for a step of 1e300 s
        let err = m.do_step(0.01, 1e300, &mut log).unwrap_err();
        // THEN it is refused naming the parameter, and the state is untouched
        assert!(err.to_string().contains("v_nue_random_walk"), "{err}");
        assert_eq!(m.running, before);
        // AND the outputs stay finite
        m.calculate_values(&mut log);
        assert!(m.estimate.v_nue_mps.iter().all(|v| v.is_finite()));
    }

    #[test]
    fn white_noise_that_would_overflow_is_refused_at_exit_initialization() {
        // The largest sigma: seed 0 draws -2.44 for the second axis of the first interval.
        let mut m = LanderNav::default();
        m.params.r_nue.noise_sigma = f64::MAX;
        let err = m.exit_initialization(0.0, &mut Log::default()).unwrap_err();
        assert!(err.to_string().contains("r_nue_noise_sigma"), "{err}");
        assert!(m.running.is_none());
    }

    #[test]
    fn a_step_before_initialization_is_refused() {
        let mut m = LanderNav::default();
        assert!(m.do_step(0.0, 0.01, &mut Log::default()).is_err());
    }
}
