//! The FMI face of the sensors: the variable table (each variable declared once) and the
//! [`Model`] implementation. The inputs carry the names LanderPlant outputs; the outputs the
//! names LanderFilter reads. Timing: see [`crate::model::sensors`].
use crate::model::truth::InputError;
use crate::model::{Measurements, SensorParameters, Sensors, Truth};
use fmi_model::parameter::{check_declared, ParameterError};
use fmi_model::{
    decl, readable, role, same_names, Declaration, Dependencies, Experiment, Log, MatchingRule,
    Model, ModelError, StepEnd, Terminal,
};
use lander_math::sensor_limits::*;
use lander_math::signal_groups as groups;
use serde::{Deserialize, Serialize};

/// The LanderSensors FMU instance. Everything lives here: no global state.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct LanderSensors {
    params: SensorParameters,
    truth: Truth,
    meas: Measurements,
    /// Set by `exit_initialization` from the validated parameters.
    running: Option<Sensors>,
}

impl LanderSensors {
    pub fn parameters(&self) -> &SensorParameters {
        &self.params
    }

    /// Each parameter against its declaration, then what declarations cannot say.
    fn check_parameters(&self) -> Result<(), ParameterError> {
        check_declared(self)?;
        self.params.validate()
    }
}

impl SensorParameters {
    /// Every check of the parameters, for sensors built without an FMI layer: each value
    /// against its declaration (as the layer checks it on every set), then
    /// [`SensorParameters::validate`].
    pub fn check(&self) -> Result<(), ParameterError> {
        LanderSensors {
            params: self.clone(),
            ..LanderSensors::default()
        }
        .check_parameters()
    }
}

fn input_error(e: InputError) -> ModelError {
    ModelError::InvalidInput {
        field: e.field,
        index: e.index,
        value: e.value.to_string(),
        reason: e.reason,
    }
}

/// An error in the master's words (the declared variable, not the field), as the layer
/// words a refusal.
fn described(e: &ModelError) -> String {
    fmi2_export::fmi_export::describe_model_error::<LanderSensors>(e)
}

const NOT_FINITE: &str =
    "a measurement would not be finite (the inputs are too large for the sensor errors)";

const TERMINALS: &[Terminal] = &[
    Terminal {
        name: "kinematics",
        matching_rule: MatchingRule::Plug,
        kind: groups::KINEMATICS_KIND,
        description: "The true motion and specific force, from the plant",
        members: &same_names(groups::KINEMATICS),
    },
    Terminal {
        name: "measurements",
        matching_rule: MatchingRule::Plug,
        kind: groups::MEASUREMENTS_KIND,
        description: "IMU, altimeter and velocimeter measurements, for the filter",
        members: &same_names(groups::MEASUREMENTS),
    },
];

impl Model for LanderSensors {
    const MODEL_IDENTIFIER: &'static str = "LanderSensors";
    const MODEL_NAME: &'static str = "LanderSensors";
    const VERSION: &'static str = env!("CARGO_PKG_VERSION");
    const DESCRIPTION: &'static str = "Sensors of the lunar lander: IMU (accelerometer and gyro with bias, scale \
         factor, misalignment, white noise, bias random walk), laser altimeter and three-beam Doppler velocimeter \
         over a terrain plane, seeded and reproducible";
    const DEFAULT_EXPERIMENT: Experiment = Experiment {
        start_time: 0.0,
        stop_time: 172.0,
        step_size: 0.01,
        tolerance: None,
    };

    /// 2: the run's drawn calibration errors; 3: the altimeter's and velocimeter's
    /// availability (faults).
    const STATE_VERSION: u32 = 3;

    fn declarations() -> &'static [Declaration<Self>] {
        DECLARATIONS
    }

    fn terminals() -> &'static [Terminal] {
        TERMINALS
    }

    fn output_dependencies(output: &str) -> Dependencies {
        match output {
            "accel_body_meas" => Dependencies::Inputs(&["specific_force_body"]),
            "gyro_body_meas" => Dependencies::Inputs(&["omega_body"]),
            "altimeter_range" | "altimeter_valid" => {
                Dependencies::Inputs(&["r_nue", "q_body_to_nue"])
            }
            _ => Dependencies::Inputs(&["r_nue", "v_nue", "q_body_to_nue"]),
        }
    }

    fn calculate_values(&mut self, log: &mut Log) {
        // Invalid parameters or inputs show as no measurement at all (every beam invalid,
        // the IMU zero) with a warning naming the value; exit_initialization and do_step
        // refuse them.
        let started;
        let sensors = match &self.running {
            Some(s) => s,
            None => {
                if let Err(e) = self.check_parameters() {
                    self.meas = Measurements::default();
                    log.warning(format!("no measurement: {}", described(&e.into())));
                    return;
                }
                started = Sensors::start(&self.params);
                &started
            }
        };
        if let Err(e) = self.truth.validate() {
            self.meas = Measurements::default();
            log.warning(format!("no measurement: {}", described(&input_error(e))));
            return;
        }
        match sensors.measure(&self.params, &self.truth) {
            Some(m) => self.meas = m,
            None => {
                self.meas = Measurements::default();
                log.warning(format!("no measurement: {NOT_FINITE}"));
            }
        }
    }

    fn exit_initialization(&mut self, _start_time: f64, _log: &mut Log) -> Result<(), ModelError> {
        self.check_parameters()?;
        self.running = Some(Sensors::start(&self.params));
        Ok(())
    }

    fn validate_restored(&self, initialized: bool) -> Result<(), ModelError> {
        match (initialized, &self.running) {
            (false, None) => Ok(()),
            (true, Some(sensors)) => {
                self.check_parameters()?;
                match sensors.inconsistency() {
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
        let Some(sensors) = self.running.as_mut() else {
            return Err(ModelError::Other(
                "do_step before exit_initialization".into(),
            ));
        };
        // The step's measurement is the one at its start: refuse to pass a point whose inputs
        // could not be measured.
        self.truth.validate().map_err(input_error)?;
        if sensors.measure(&self.params, &self.truth).is_none() {
            return Err(ModelError::Refused(format!(
                "in the step from t = {} s: {NOT_FINITE}",
                readable(t)
            )));
        }
        sensors.step(&self.params, h).ok_or_else(|| {
            ModelError::Refused(format!(
                "in the step from t = {} s (communicationStepSize {} s): a bias random walk \
                 would overflow",
                readable(t),
                readable(h)
            ))
        })?;
        Ok(StepEnd::Complete)
    }
}

const NUE: &[&str] = &["North", "Up", "East"];
const BODY: &[&str] = &["body x", "body y (the thrust axis)", "body z"];
const QUATERNION: &[&str] = &[
    "scalar part",
    "vector part x",
    "vector part y",
    "vector part z",
];

/// The declarations, one line each so that they read as a table. Start values are those of
/// `LanderSensors::default()`; the bounds of each value are checked from here only
/// (`fmi_model::parameter::check_declared`).
#[rustfmt::skip]
static DECLARATIONS: &[Declaration<LanderSensors>] = &[
    // Inputs: LanderPlant's true state.
    decl!(1, input r_nue[3]: truth.r_nue_m, "m", "True position of the centre of mass, NUE, landing site at the origin (LanderPlant r_nue)", components = NUE),
    decl!(4, input v_nue[3]: truth.v_nue_mps, "m/s", "True velocity relative to the surface (LanderPlant v_nue)", components = NUE),
    decl!(7, input q_body_to_nue[4]: truth.q_body_to_nue, "1", "True attitude quaternion body to NUE, Hamilton, scalar first, unit to 1e-6 (LanderPlant q_body_to_nue)", components = QUATERNION),
    decl!(11, input omega_body[3]: truth.omega_body_radps, "rad/s", "True body rate (LanderPlant omega_body)", components = BODY),
    decl!(14, input specific_force_body[3]: truth.specific_force_body_mps2, "m/s2", "True specific force, the non-gravitational acceleration in body axes (LanderPlant specific_force_body)", components = BODY),
    // Outputs: the measurements.
    decl!(100, discrete_output accel_body_meas[3]: meas.accel_body_meas_mps2, "m/s2", "Accelerometer: measured specific force in body axes", components = BODY),
    decl!(103, discrete_output gyro_body_meas[3]: meas.gyro_body_meas_radps, "rad/s", "Gyro: measured body rate", components = BODY),
    decl!(106, discrete_output altimeter_range: meas.altimeter_range_m, "m", "Laser altimeter: slant range along its beam to the terrain plane (0 when invalid)"),
    decl!(107, discrete_output altimeter_valid: meas.altimeter_valid as bool, "Whether altimeter_range is a measurement: the beam meets the terrain within altimeter_max_range and the sample is not dropped"),
    decl!(108, discrete_output velocimeter_los_velocity[3]: meas.velocimeter_los_velocity_mps, "m/s", "Doppler velocimeter: the lander's velocity relative to the terrain along each beam, positive away from the lander (towards the terrain); 0 when invalid", components = &["beam 1", "beam 2", "beam 3"]),
    Declaration::boolean(111, "velocimeter_valid_1", role::discrete_output, "Whether velocimeter_los_velocity[1] is a measurement", |m: &LanderSensors| m.meas.velocimeter_valid[0], |m: &mut LanderSensors, v| m.meas.velocimeter_valid[0] = v),
    Declaration::boolean(112, "velocimeter_valid_2", role::discrete_output, "Whether velocimeter_los_velocity[2] is a measurement", |m: &LanderSensors| m.meas.velocimeter_valid[1], |m: &mut LanderSensors, v| m.meas.velocimeter_valid[1] = v),
    Declaration::boolean(113, "velocimeter_valid_3", role::discrete_output, "Whether velocimeter_los_velocity[3] is a measurement", |m: &LanderSensors| m.meas.velocimeter_valid[2], |m: &mut LanderSensors, v| m.meas.velocimeter_valid[2] = v),
    // Common parameters.
    decl!(200, parameter seed: params.seed as i32, "Seed of every draw (the same seed gives the same measurements on one platform)", int_min = 0),
    decl!(201, parameter imu_sample_period: params.sample_period_s, "s", "IMU sampling interval, the communication step: the white noise of one sample has the 1-sigma noise_density / sqrt(imu_sample_period)", above = 0.0, max = SAMPLE_PERIOD_MAX_S),
    // Accelerometer.
    decl!(210, parameter accel_bias_sigma: params.accel.bias_sigma, "m/s2", "1-sigma of the constant bias on each axis, drawn once per run from the seed", min = 0.0, max = ACCEL_BIAS_SIGMA_MAX),
    decl!(211, parameter accel_scale_factor_error[3]: params.accel.scale_factor_error, "1", "Scale factor error per axis (1e-3 = 1000 ppm), fixed; the run's is this plus a draw of 1-sigma accel_scale_factor_sigma", components = BODY, min = -SCALE_FACTOR_ERROR_MAX, max = SCALE_FACTOR_ERROR_MAX),
    decl!(202, parameter accel_scale_factor_sigma: params.accel.scale_factor_sigma, "1", "1-sigma of the scale factor error drawn once per run from the seed on each axis, added to accel_scale_factor_error", min = 0.0, max = SCALE_FACTOR_SIGMA_MAX),
    decl!(214, parameter accel_misalignment[3]: params.accel.misalignment_rad, "rad", "Misalignment of the accelerometer axes: a small rotation vector from body to sensor axes, fixed; the run's is this plus a draw of 1-sigma accel_misalignment_sigma", components = BODY, min = -MISALIGNMENT_MAX_RAD, max = MISALIGNMENT_MAX_RAD),
    decl!(203, parameter accel_misalignment_sigma: params.accel.misalignment_sigma, "rad", "1-sigma of each component of the misalignment rotation drawn once per run from the seed, added to accel_misalignment", min = 0.0, max = MISALIGNMENT_SIGMA_MAX_RAD),
    decl!(217, parameter accel_noise_density: params.accel.noise_density, "m/s", "Velocity random walk: 1-sigma of the integrated white noise after 1 s on each axis (the density in m/s2/sqrt(Hz))", min = 0.0, max = ACCEL_NOISE_DENSITY_MAX),
    decl!(218, parameter accel_bias_random_walk: params.accel.bias_random_walk, "m/s2", "1-sigma of the bias change after 1 s on each axis (grows as the square root of time)", min = 0.0, max = ACCEL_BIAS_RANDOM_WALK_MAX),
    // Gyro.
    decl!(220, parameter gyro_bias_sigma: params.gyro.bias_sigma, "rad/s", "1-sigma of the constant bias on each axis, drawn once per run from the seed", min = 0.0, max = GYRO_BIAS_SIGMA_MAX),
    decl!(221, parameter gyro_scale_factor_error[3]: params.gyro.scale_factor_error, "1", "Scale factor error per axis (1e-3 = 1000 ppm), fixed; the run's is this plus a draw of 1-sigma gyro_scale_factor_sigma", components = BODY, min = -SCALE_FACTOR_ERROR_MAX, max = SCALE_FACTOR_ERROR_MAX),
    decl!(204, parameter gyro_scale_factor_sigma: params.gyro.scale_factor_sigma, "1", "1-sigma of the scale factor error drawn once per run from the seed on each axis, added to gyro_scale_factor_error", min = 0.0, max = SCALE_FACTOR_SIGMA_MAX),
    decl!(224, parameter gyro_misalignment[3]: params.gyro.misalignment_rad, "rad", "Misalignment of the gyro axes: a small rotation vector from body to sensor axes, fixed; the run's is this plus a draw of 1-sigma gyro_misalignment_sigma", components = BODY, min = -MISALIGNMENT_MAX_RAD, max = MISALIGNMENT_MAX_RAD),
    decl!(205, parameter gyro_misalignment_sigma: params.gyro.misalignment_sigma, "rad", "1-sigma of each component of the misalignment rotation drawn once per run from the seed, added to gyro_misalignment", min = 0.0, max = MISALIGNMENT_SIGMA_MAX_RAD),
    decl!(227, parameter gyro_noise_density: params.gyro.noise_density, "rad", "Angle random walk: 1-sigma of the integrated white noise after 1 s on each axis (the density in rad/s/sqrt(Hz))", min = 0.0, max = GYRO_NOISE_DENSITY_MAX),
    decl!(228, parameter gyro_bias_random_walk: params.gyro.bias_random_walk, "rad/s", "1-sigma of the bias change after 1 s on each axis (grows as the square root of time)", min = 0.0, max = GYRO_BIAS_RANDOM_WALK_MAX),
    // Laser altimeter.
    decl!(230, parameter altimeter_beam_body[3]: params.altimeter_beam_body, "1", "Direction of the altimeter beam in body axes (normalised; default down the thrust axis, -y)", components = BODY),
    decl!(233, parameter altimeter_noise_sigma: params.altimeter.noise_sigma, "m", "1-sigma of the range noise independent of the range", min = 0.0, max = RANGE_NOISE_SIGMA_MAX_M),
    decl!(234, parameter altimeter_noise_proportional: params.altimeter.noise_proportional, "1", "1-sigma of the range noise per metre of slant range, added in quadrature to altimeter_noise_sigma", min = 0.0, max = RANGE_NOISE_PROPORTIONAL_MAX),
    decl!(235, parameter altimeter_max_range: params.altimeter.max_range_m, "m", "Slant range beyond which the altimeter is invalid", above = 0.0, max = MAX_RANGE_MAX_M),
    decl!(236, parameter altimeter_dropout_probability: params.altimeter.dropout_probability, "1", "Probability that an altimeter sample is lost (invalid)", min = 0.0, max = 1.0),
    decl!(237, tunable altimeter_available: params.altimeter.available as bool, "Fault, tunable during the run: false is an altimeter failure, every sample invalid (altimeter_valid false, altimeter_range 0) until it is true again"),
    // Doppler velocimeter.
    decl!(240, parameter velocimeter_beam_1_body[3]: params.velocimeter_beam_1_body, "1", "Direction of velocimeter beam 1 in body axes (normalised; default 20 deg from -y at azimuth 0 from +x towards +z)", components = BODY),
    decl!(243, parameter velocimeter_beam_2_body[3]: params.velocimeter_beam_2_body, "1", "Direction of velocimeter beam 2 in body axes (default azimuth 120 deg)", components = BODY),
    decl!(246, parameter velocimeter_beam_3_body[3]: params.velocimeter_beam_3_body, "1", "Direction of velocimeter beam 3 in body axes (default azimuth 240 deg)", components = BODY),
    decl!(249, parameter velocimeter_noise_sigma: params.velocimeter.noise_sigma, "m/s", "1-sigma of the line-of-sight velocity noise of each beam", min = 0.0, max = LOS_NOISE_SIGMA_MAX_MPS),
    decl!(250, parameter velocimeter_max_range: params.velocimeter.max_range_m, "m", "Slant range along a beam beyond which that beam is invalid", above = 0.0, max = MAX_RANGE_MAX_M),
    decl!(251, parameter velocimeter_dropout_probability: params.velocimeter.dropout_probability, "1", "Probability that a beam's sample is lost (invalid), each beam drawn on its own", min = 0.0, max = 1.0),
    decl!(252, tunable velocimeter_available: params.velocimeter.available as bool, "Fault, tunable during the run: false is a velocimeter failure, every beam invalid (velocimeter_valid false, velocimeter_los_velocity 0) until it is true again"),
    // Terrain plane.
    decl!(260, parameter terrain_height: params.terrain_height_m, "m", "Up of the terrain plane at the origin (the landing site)", min = -TERRAIN_HEIGHT_MAX_M, max = TERRAIN_HEIGHT_MAX_M),
    decl!(261, parameter terrain_slope_normal_nue[3]: params.terrain_slope_normal_nue, "1", "Normal of the terrain plane in NUE, pointing up (normalised; a zero or downward normal is refused)", components = NUE),
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_export_layer_accepts_the_declarations() {
        assert_eq!(fmi2_export::check_table::<LanderSensors>(), Ok(()));
    }

    #[test]
    fn a_zero_terrain_normal_fails_initialization_by_name() {
        let mut m = LanderSensors::default();
        m.params.terrain_slope_normal_nue = [0.0; 3];
        let err = m.exit_initialization(0.0, &mut Log::default()).unwrap_err();
        assert!(
            err.to_string().contains("terrain_slope_normal_nue"),
            "{err}"
        );
        // Shown meanwhile: no measurement, a warning, nothing NaN.
        let mut log = Log::default();
        m.calculate_values(&mut log);
        assert!(log.has_warning());
        assert!(m.meas.is_finite() && !m.meas.altimeter_valid);
    }

    #[test]
    fn a_non_unit_quaternion_is_refused_by_the_step_and_warned_by_the_reads() {
        let mut m = LanderSensors::default();
        m.exit_initialization(0.0, &mut Log::default()).unwrap();
        m.truth.r_nue_m = [0.0, 100.0, 0.0];
        m.truth.q_body_to_nue = [0.5, 0.0, 0.0, 0.0];
        let mut log = Log::default();
        m.calculate_values(&mut log);
        assert!(log.has_warning(), "{:?}", log.entries);
        // In the master's words: the variable, not the field.
        let message = &log.entries[0].1;
        assert!(
            message.starts_with("no measurement: input q_body_to_nue = 0.5: its norm"),
            "{message}"
        );
        assert!(m.meas.is_finite() && !m.meas.altimeter_valid);
        let err = m.do_step(0.0, 0.01, &mut log).unwrap_err();
        assert!(err.to_string().contains("q_body_to_nue"), "{err}");
    }

    #[test]
    fn inputs_too_large_for_the_errors_are_refused_not_shown_as_infinity() {
        let mut m = LanderSensors::default();
        m.params.accel.scale_factor_error = [0.5; 3];
        m.exit_initialization(0.0, &mut Log::default()).unwrap();
        m.truth.specific_force_body_mps2 = [f64::MAX; 3];
        let mut log = Log::default();
        m.calculate_values(&mut log);
        assert!(log.has_warning() && m.meas.is_finite());
        assert!(matches!(
            m.do_step(0.0, 0.01, &mut log),
            Err(ModelError::Refused(_))
        ));
    }

    #[test]
    fn a_step_before_initialization_is_refused() {
        let mut m = LanderSensors::default();
        assert!(m.do_step(0.0, 0.01, &mut Log::default()).is_err());
    }
}
