//! The FMI face of the filter: the variable table (each variable declared once) and the
//! [`Model`] implementation. The inputs carry LanderSensors' output names, the navigation
//! outputs LanderGnc's input names, so the filter replaces LanderNav without renaming.
//!
//! Timing: the outputs at a communication point are the estimate propagated to it (before
//! that point's measurements), except `omega_body`, the gyro input there minus the
//! estimated bias. `do_step` first updates with the point's valid measurements, then
//! propagates with its IMU sample over the step; the NIS outputs are those of that update.
//! With `imu_mean_over_last_step` the IMU inputs at a point are the means over the step that
//! ended there: the outputs are the last point's update propagated over that step with them,
//! computed when read, and `do_step` takes that propagation, then the point's update; the
//! propagation of the coming step waits for the next point's inputs.
use crate::model::covariance::{N, NAVIGATION};
use crate::model::parameters::bounds::*;
use crate::model::{Eskf, FilterParameters, Heading, Imu};
use fmi_model::parameter::{check_declared, ParameterError};
use fmi_model::{
    decl, readable, same_names, Causality, Declaration, Dependencies, Experiment, Log,
    MatchingRule, Member, Model, ModelError, Role, StepEnd, Terminal, Variability,
};
use lander_math::signal_groups as groups;
use serde::{Deserialize, Serialize};

/// The measurements at the current communication point (LanderSensors' outputs).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Measurements {
    pub imu: Imu,
    pub altimeter_range_m: f64,
    pub altimeter_valid: bool,
    pub velocimeter_los_velocity_mps: [f64; 3],
    pub velocimeter_valid: [bool; 3],
}

/// What the last update did.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Innovations {
    pub nis_altimeter: f64,
    pub altimeter_dof: i32,
    pub nis_velocimeter: f64,
    pub velocimeter_dof: i32,
    pub rejected: i32,
}

impl Innovations {
    /// Why these statistics could not come from an update, if they could not: a NIS that
    /// is not finite or negative, degrees of freedom outside 0..=1 and 0..=3, more
    /// rejections than measurements.
    pub fn inconsistency(&self) -> Option<String> {
        let nis_ok = |x: f64| x.is_finite() && x >= 0.0;
        if !nis_ok(self.nis_altimeter) || !nis_ok(self.nis_velocimeter) {
            return Some(format!(
                "a normalised innovation squared is not finite and >= 0 (altimeter {}, \
                 velocimeter {})",
                readable(self.nis_altimeter),
                readable(self.nis_velocimeter)
            ));
        }
        let (a, v, r) = (self.altimeter_dof, self.velocimeter_dof, self.rejected);
        if !(0..=1).contains(&a) || !(0..=3).contains(&v) || !(0..=a + v).contains(&r) {
            return Some(format!(
                "altimeter_dof {a}, velocimeter_dof {v}, measurements_rejected {r} are not \
                 counts of one update"
            ));
        }
        None
    }
}

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct Outputs {
    pub r_nue_m: [f64; 3],
    pub v_nue_mps: [f64; 3],
    pub q_body_to_nue: [f64; 4],
    pub omega_body_radps: [f64; 3],
    pub accel_bias_mps2: [f64; 3],
    pub gyro_bias_radps: [f64; 3],
    pub covariance_diag: [f64; NAVIGATION],
    pub accel_scale_factor: [f64; 3],
    pub accel_misalignment_rad: [f64; 3],
    pub gyro_scale_factor: [f64; 3],
    pub gyro_misalignment_rad: [f64; 3],
    pub calibration_covariance_diag: [f64; N - NAVIGATION],
}

/// `imu_mean_over_last_step`: what the propagation over the step after a communication
/// point takes from that point, until the next point's IMU inputs complete it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Pending {
    /// The step's length, s.
    pub h: f64,
    /// The state the point's measurements were linearised about (the heading constraint).
    pub linearised_at: Heading,
}

impl Pending {
    fn is_finite(&self) -> bool {
        self.h.is_finite()
            && self.linearised_at.r_nue.iter().all(|x| x.is_finite())
            && self.linearised_at.v_nue.iter().all(|x| x.is_finite())
            && self.linearised_at.rotation.iter().all(|x| x.is_finite())
    }
}

/// The LanderFilter FMU instance. Everything lives here: no global state.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct LanderFilter {
    params: FilterParameters,
    meas: Measurements,
    out: Outputs,
    last: Innovations,
    /// Set by `exit_initialization` from the validated parameters; with
    /// `imu_mean_over_last_step` the estimate after the last point's update.
    running: Option<Eskf>,
    /// `imu_mean_over_last_step`: the step since the last point (`None` before the first).
    pending: Option<Pending>,
}

impl LanderFilter {
    pub fn parameters(&self) -> &FilterParameters {
        &self.params
    }
    pub fn estimate(&self) -> Option<&Eskf> {
        self.running.as_ref()
    }

    /// Each parameter against its declaration, then what declarations cannot say.
    fn check_parameters(&self) -> Result<(), ParameterError> {
        check_declared(self)?;
        self.params.validate()
    }
}

impl FilterParameters {
    /// Every check of the parameters, for a filter built without an FMI layer: each value
    /// against its declaration (as the layer checks it on every set), then
    /// [`FilterParameters::validate`].
    pub fn check(&self) -> Result<(), ParameterError> {
        LanderFilter {
            params: self.clone(),
            ..LanderFilter::default()
        }
        .check_parameters()
    }
}

/// One communication point's measurements into the filter: the altimeter, then each
/// velocimeter beam, each only when valid; the statistics of what was used. `interval_s`:
/// the time between updates (the communication step), which sets how often the models'
/// linearisation error repeats.
pub fn update(
    eskf: &mut Eskf,
    params: &FilterParameters,
    meas: &Measurements,
    interval_s: f64,
) -> Innovations {
    let mut out = Innovations::default();
    let mut dx = [0.0; N];
    if meas.altimeter_valid {
        if let Some(u) = eskf.update_altimeter(&mut dx, params, meas.altimeter_range_m, interval_s)
        {
            out.nis_altimeter = u.nis;
            out.altimeter_dof = 1;
            out.rejected += i32::from(!u.applied);
        }
    }
    for i in 0..3 {
        if meas.velocimeter_valid[i] {
            let y = meas.velocimeter_los_velocity_mps[i];
            let u = eskf.update_velocimeter(&mut dx, params, i, y, interval_s);
            out.nis_velocimeter += u.nis;
            out.velocimeter_dof += 1;
            out.rejected += i32::from(!u.applied);
        }
    }
    eskf.inject(&dx);
    out
}

/// `imu_mean_over_last_step`: the estimate at a communication point, the last point's
/// update `eskf` propagated over the step `pending` since then with `imu`, this point's IMU
/// inputs (the step's means); `eskf` itself at the first point.
pub fn propagated_over_last_step(
    eskf: &mut Eskf,
    params: &FilterParameters,
    pending: Option<&Pending>,
    imu: &Imu,
) {
    if let Some(p) = pending {
        eskf.propagate(params, imu, p.h, Some(&p.linearised_at));
    }
}

/// One communication step with `imu_mean_over_last_step`: the propagation over the step
/// that ended at this point ([`propagated_over_last_step`]), this point's measurements, and
/// what the next point's propagation over `h` needs from this one.
pub fn step_with_mean_imu(
    eskf: &mut Eskf,
    pending: &mut Option<Pending>,
    params: &FilterParameters,
    meas: &Measurements,
    h: f64,
) -> Innovations {
    propagated_over_last_step(eskf, params, pending.as_ref(), &meas.imu);
    let linearised_at = eskf.heading();
    let innovations = update(eskf, params, meas, h);
    *pending = Some(Pending { h, linearised_at });
    innovations
}

/// One communication step: this point's measurements, then the propagation over `h` with its
/// IMU sample, constrained by the state the measurements were linearised about.
pub fn step(
    eskf: &mut Eskf,
    params: &FilterParameters,
    meas: &Measurements,
    h: f64,
) -> Innovations {
    let linearised_at = eskf.heading();
    let innovations = update(eskf, params, meas, h);
    eskf.propagate(params, &meas.imu, h, Some(&linearised_at));
    innovations
}

/// The filter estimates no mass: its navigation terminal is a bus, and a controller's
/// plug takes the mass from elsewhere (the plant).
const NAVIGATION_MEMBERS: [Member; 4] = {
    let all = same_names(groups::NAVIGATION);
    [all[0], all[1], all[2], all[3]]
};

const TERMINALS: &[Terminal] = &[
    Terminal {
        name: "measurements",
        matching_rule: MatchingRule::Plug,
        kind: groups::MEASUREMENTS_KIND,
        description: "IMU, altimeter and velocimeter measurements, from the sensors",
        members: &same_names(groups::MEASUREMENTS),
    },
    Terminal {
        name: "navigation",
        matching_rule: MatchingRule::Bus,
        kind: groups::NAVIGATION_KIND,
        description: "The estimated position, velocity, attitude and rate, for the controller",
        members: &NAVIGATION_MEMBERS,
    },
];

impl Model for LanderFilter {
    const MODEL_IDENTIFIER: &'static str = "LanderFilter";
    const MODEL_NAME: &'static str = "LanderFilter";
    const VERSION: &'static str = env!("CARGO_PKG_VERSION");
    const DESCRIPTION: &'static str = "Error-state Kalman filter of the lunar lander: IMU propagation, laser \
         altimeter and Doppler velocimeter updates (Joseph form, optional chi-square gating); position, velocity, \
         attitude, body rate and IMU bias estimates with their covariance";
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

    /// 3: the IMU calibration states (2: `imu_mean_over_last_step` and its pending step).
    const STATE_VERSION: u32 = 3;

    fn output_dependencies(output: &str) -> Dependencies {
        match output {
            // The misalignment estimate mixes the gyro's axes.
            "omega_body" => Dependencies::Inputs(&["gyro_body_meas"]),
            // With imu_mean_over_last_step (declared whatever its value: the description
            // does not depend on parameters); the body's turn over the step enters the
            // velocity and position increments.
            "r_nue" | "v_nue" => Dependencies::Inputs(&["accel_body_meas", "gyro_body_meas"]),
            "q_body_to_nue" => Dependencies::Inputs(&["gyro_body_meas"]),
            "covariance_diag" => Dependencies::Inputs(&["accel_body_meas", "gyro_body_meas"]),
            _ => Dependencies::NoInputs,
        }
    }

    fn calculate_values(&mut self, log: &mut Log) {
        let started;
        let eskf = match &self.running {
            Some(e) => e,
            None => {
                if let Err(e) = self.check_parameters() {
                    self.out = Outputs::default();
                    let e = ModelError::from(e);
                    let described = fmi2_export::fmi_export::describe_model_error::<Self>(&e);
                    log.warning(format!("no estimate: {described}"));
                    return;
                }
                started = Eskf::start(&self.params);
                &started
            }
        };
        let propagated;
        let eskf = if self.params.imu_mean_over_last_step && self.pending.is_some() {
            let mut e = eskf.clone();
            propagated_over_last_step(&mut e, &self.params, self.pending.as_ref(), &self.meas.imu);
            propagated = e;
            &propagated
        } else {
            eskf
        };
        self.out = Outputs {
            r_nue_m: eskf.r_nue_m,
            v_nue_mps: eskf.v_nue_mps,
            q_body_to_nue: eskf.q_body_to_nue,
            omega_body_radps: eskf.omega_body(&self.meas.imu),
            accel_bias_mps2: eskf.accel_bias_mps2,
            gyro_bias_radps: eskf.gyro_bias_radps,
            covariance_diag: std::array::from_fn(|i| eskf.p[i][i]),
            accel_scale_factor: eskf.accel_calibration.scale_factor,
            accel_misalignment_rad: eskf.accel_calibration.misalignment_rad,
            gyro_scale_factor: eskf.gyro_calibration.scale_factor,
            gyro_misalignment_rad: eskf.gyro_calibration.misalignment_rad,
            calibration_covariance_diag: std::array::from_fn(|i| {
                eskf.p[NAVIGATION + i][NAVIGATION + i]
            }),
        };
    }

    fn exit_initialization(&mut self, _start_time: f64, _log: &mut Log) -> Result<(), ModelError> {
        self.check_parameters()?;
        self.running = Some(Eskf::start(&self.params));
        self.pending = None;
        Ok(())
    }

    fn validate_restored(&self, initialized: bool) -> Result<(), ModelError> {
        match (initialized, &self.running) {
            (false, None) => Ok(()),
            (true, Some(eskf)) => {
                self.check_parameters()?;
                if !eskf.is_sound() {
                    return Err(ModelError::Other(
                        "restored state: an estimate or covariance value is not finite".into(),
                    ));
                }
                let pending_sound = match &self.pending {
                    None => true,
                    Some(p) => self.params.imu_mean_over_last_step && p.is_finite() && p.h > 0.0,
                };
                if !pending_sound {
                    return Err(ModelError::Other(
                        "restored state: a pending step value is not finite (or a pending step \
                         without imu_mean_over_last_step)"
                            .into(),
                    ));
                }
                let norm = crate::model::rotation::norm(&eskf.q_body_to_nue);
                if (norm - 1.0).abs() > 1e-9 {
                    return Err(ModelError::Other(format!(
                        "restored state: the attitude quaternion's norm {norm} is not 1"
                    )));
                }
                match self.last.inconsistency() {
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
        let Some(eskf) = self.running.as_ref() else {
            return Err(ModelError::Other(
                "do_step before exit_initialization".into(),
            ));
        };
        // Computed on a copy: a step whose result is not finite changes nothing.
        let mut next = eskf.clone();
        let mut pending = self.pending;
        let innovations = if self.params.imu_mean_over_last_step {
            step_with_mean_imu(&mut next, &mut pending, &self.params, &self.meas, h)
        } else {
            step(&mut next, &self.params, &self.meas, h)
        };
        if !next.is_sound() {
            return Err(ModelError::Refused(format!(
                "in the step from t = {} s (communicationStepSize {} s): the estimate would \
                 not be finite (measurements or step too large for the filter)",
                readable(t),
                readable(h)
            )));
        }
        if let Some(why) = innovations.inconsistency() {
            return Err(ModelError::Refused(format!(
                "in the step from t = {} s: {why}: a measurement too far from its prediction \
                 for the filter",
                readable(t)
            )));
        }
        self.running = Some(next);
        self.pending = pending;
        self.last = innovations;
        Ok(StepEnd::Complete)
    }
}

/// The measurements are samples: Boolean inputs are discrete (FMI 2.0 allows no continuous
/// Boolean).
const DISCRETE_INPUT: Role = Role {
    causality: Causality::Input,
    variability: Variability::Discrete,
    initial: None,
};

const NUE: &[&str] = &["North", "Up", "East"];
const BODY: &[&str] = &["body x", "body y (the thrust axis)", "body z"];
const QUATERNION: &[&str] = &[
    "scalar part",
    "vector part x",
    "vector part y",
    "vector part z",
];
const BEAMS: &[&str] = &["beam 1", "beam 2", "beam 3"];
const ERROR_STATE: &[&str] = &[
    "position North (m2)",
    "position Up (m2)",
    "position East (m2)",
    "velocity North (m2/s2)",
    "velocity Up (m2/s2)",
    "velocity East (m2/s2)",
    "attitude about body x (rad2)",
    "attitude about body y (rad2)",
    "attitude about body z (rad2)",
    "accelerometer bias x (m2/s4)",
    "accelerometer bias y (m2/s4)",
    "accelerometer bias z (m2/s4)",
    "gyro bias x (rad2/s2)",
    "gyro bias y (rad2/s2)",
    "gyro bias z (rad2/s2)",
];
const CALIBRATION_STATE: &[&str] = &[
    "accelerometer scale factor x (1)",
    "accelerometer scale factor y (1)",
    "accelerometer scale factor z (1)",
    "gyro scale factor x (1)",
    "gyro scale factor y (1)",
    "gyro scale factor z (1)",
    "accelerometer misalignment about body x (rad2)",
    "accelerometer misalignment about body y (rad2)",
    "accelerometer misalignment about body z (rad2)",
    "gyro misalignment about body x (rad2)",
    "gyro misalignment about body y (rad2)",
    "gyro misalignment about body z (rad2)",
];

/// The declarations, one line each so that they read as a table. Start values are those of
/// `LanderFilter::default()`; the bounds of each value are checked from here only
/// (`fmi_model::parameter::check_declared`).
#[rustfmt::skip]
static DECLARATIONS: &[Declaration<LanderFilter>] = &[
    // Inputs: LanderSensors' measurements.
    decl!(1, input accel_body_meas[3]: meas.imu.accel_body_mps2, "m/s2", "Accelerometer: measured specific force in body axes (LanderSensors accel_body_meas)", components = BODY),
    decl!(4, input gyro_body_meas[3]: meas.imu.gyro_body_radps, "rad/s", "Gyro: measured body rate (LanderSensors gyro_body_meas)", components = BODY),
    decl!(7, input altimeter_range: meas.altimeter_range_m, "m", "Laser altimeter slant range (LanderSensors altimeter_range)"),
    Declaration::boolean(8, "altimeter_valid", DISCRETE_INPUT, "Whether altimeter_range is a measurement (LanderSensors altimeter_valid)", |m: &LanderFilter| m.meas.altimeter_valid, |m: &mut LanderFilter, v| m.meas.altimeter_valid = v).field("meas.altimeter_valid"),
    decl!(9, input velocimeter_los_velocity[3]: meas.velocimeter_los_velocity_mps, "m/s", "Doppler line-of-sight velocities, positive away from the lander (LanderSensors velocimeter_los_velocity)", components = BEAMS),
    Declaration::boolean(12, "velocimeter_valid_1", DISCRETE_INPUT, "Whether velocimeter_los_velocity[1] is a measurement (LanderSensors velocimeter_valid_1)", |m: &LanderFilter| m.meas.velocimeter_valid[0], |m: &mut LanderFilter, v| m.meas.velocimeter_valid[0] = v),
    Declaration::boolean(13, "velocimeter_valid_2", DISCRETE_INPUT, "Whether velocimeter_los_velocity[2] is a measurement (LanderSensors velocimeter_valid_2)", |m: &LanderFilter| m.meas.velocimeter_valid[1], |m: &mut LanderFilter, v| m.meas.velocimeter_valid[1] = v),
    Declaration::boolean(14, "velocimeter_valid_3", DISCRETE_INPUT, "Whether velocimeter_los_velocity[3] is a measurement (LanderSensors velocimeter_valid_3)", |m: &LanderFilter| m.meas.velocimeter_valid[2], |m: &mut LanderFilter, v| m.meas.velocimeter_valid[2] = v),
    // Outputs: the estimate under LanderGnc's names, and the filter's own.
    decl!(100, discrete_output r_nue[3]: out.r_nue_m, "m", "Estimated position of the centre of mass, NUE", components = NUE),
    decl!(103, discrete_output v_nue[3]: out.v_nue_mps, "m/s", "Estimated velocity relative to the surface", components = NUE),
    decl!(106, discrete_output q_body_to_nue[4]: out.q_body_to_nue, "1", "Estimated attitude quaternion body to NUE, Hamilton, scalar first", components = QUATERNION),
    decl!(110, discrete_output omega_body[3]: out.omega_body_radps, "rad/s", "Body rate: gyro_body_meas less the estimated gyro bias, calibrated by the estimated scale factor and misalignment", components = BODY),
    decl!(113, discrete_output accel_bias_estimate[3]: out.accel_bias_mps2, "m/s2", "Estimated accelerometer bias", components = BODY),
    decl!(116, discrete_output gyro_bias_estimate[3]: out.gyro_bias_radps, "rad/s", "Estimated gyro bias", components = BODY),
    decl!(119, discrete_output covariance_diag[15]: out.covariance_diag, "1", "Diagonal of the error-state covariance (dr, dv, dtheta in body axes, db_a, db_g), each in the square of its error's unit", components = ERROR_STATE),
    decl!(134, discrete_output nis_altimeter: last.nis_altimeter, "1", "Normalised innovation squared of the last step's altimeter update (0 when none)"),
    decl!(135, discrete_output altimeter_dof: last.altimeter_dof as i32, "Degrees of freedom of nis_altimeter: 1 when the last step had an altimeter measurement, else 0"),
    decl!(136, discrete_output nis_velocimeter: last.nis_velocimeter, "1", "Sum over the velocimeter beams of the last step's normalised innovations squared"),
    decl!(137, discrete_output velocimeter_dof: last.velocimeter_dof as i32, "Degrees of freedom of nis_velocimeter: the number of beams in the last step's update"),
    decl!(138, discrete_output measurements_rejected: last.rejected as i32, "Scalar measurements of the last step the chi-square gate rejected"),
    decl!(140, discrete_output accel_scale_factor_estimate[3]: out.accel_scale_factor, "1", "Estimated accelerometer scale factor error (LanderSensors' model m = (I + diag(s)) (x - mu x x) + b + n; 0 while accel_scale_factor_sigma is 0)", components = BODY),
    decl!(143, discrete_output accel_misalignment_estimate[3]: out.accel_misalignment_rad, "rad", "Estimated accelerometer misalignment rotation (0 while accel_misalignment_sigma is 0)", components = BODY),
    decl!(146, discrete_output gyro_scale_factor_estimate[3]: out.gyro_scale_factor, "1", "Estimated gyro scale factor error (0 while gyro_scale_factor_sigma is 0)", components = BODY),
    decl!(149, discrete_output gyro_misalignment_estimate[3]: out.gyro_misalignment_rad, "rad", "Estimated gyro misalignment rotation (0 while gyro_misalignment_sigma is 0)", components = BODY),
    decl!(152, discrete_output calibration_covariance_diag[12]: out.calibration_covariance_diag, "1", "Diagonal of the calibration errors' covariance (ds_a, ds_g, dmu_a, dmu_g), each in the square of its error's unit", components = CALIBRATION_STATE),
    // The IMU's noise: LanderSensors' names and meanings.
    decl!(200, parameter gravity: params.gravity_mps2, "m/s2", "Lunar gravity, along -Up (flat Moon)", min = 0.0, max = GRAVITY_MAX),
    decl!(201, parameter imu_sample_period: params.sample_period_s, "s", "IMU sampling interval (LanderSensors imu_sample_period): one sample's white noise has the variance noise_density^2 / imu_sample_period", above = 0.0, max = SAMPLE_PERIOD_MAX_S),
    decl!(202, parameter imu_mean_over_last_step: params.imu_mean_over_last_step as bool, "accel_body_meas and gyro_body_meas at a communication point are the means over the step that ended there (LanderSensors fed with LanderPlant specific_force_mean_body and omega_mean_body): the outputs are the last point's estimate propagated over that step with them, and r_nue, v_nue (on both), q_body_to_nue (on gyro_body_meas) and covariance_diag depend on them at the same point; false (default): samples held over the coming step (docs/filter.md)"),
    decl!(210, parameter accel_bias_sigma: params.accel.bias_sigma, "m/s2", "1-sigma of the accelerometer's constant bias per axis (LanderSensors accel_bias_sigma): the initial 1-sigma of its estimate", min = 0.0, max = ACCEL_BIAS_SIGMA_MAX),
    decl!(217, parameter accel_noise_density: params.accel.noise_density, "m/s", "Velocity random walk: 1-sigma of the integrated accelerometer noise after 1 s (LanderSensors accel_noise_density)", min = 0.0, max = ACCEL_NOISE_DENSITY_MAX),
    decl!(218, parameter accel_bias_random_walk: params.accel.bias_random_walk, "m/s2", "1-sigma of the accelerometer bias change after 1 s (LanderSensors accel_bias_random_walk)", min = 0.0, max = ACCEL_BIAS_RANDOM_WALK_MAX),
    decl!(211, parameter accel_scale_factor_sigma: params.accel.scale_factor_sigma, "1", "1-sigma of the accelerometer's constant scale factor error per axis (LanderSensors accel_scale_factor_sigma): the initial 1-sigma of its estimate; 0 (default): not estimated", min = 0.0, max = SCALE_FACTOR_SIGMA_MAX),
    decl!(212, parameter accel_misalignment_sigma: params.accel.misalignment_sigma, "rad", "1-sigma of each component of the accelerometer's constant misalignment rotation (LanderSensors accel_misalignment_sigma); 0 (default): not estimated", min = 0.0, max = MISALIGNMENT_SIGMA_MAX_RAD),
    decl!(220, parameter gyro_bias_sigma: params.gyro.bias_sigma, "rad/s", "1-sigma of the gyro's constant bias per axis (LanderSensors gyro_bias_sigma): the initial 1-sigma of its estimate", min = 0.0, max = GYRO_BIAS_SIGMA_MAX),
    decl!(227, parameter gyro_noise_density: params.gyro.noise_density, "rad", "Angle random walk: 1-sigma of the integrated gyro noise after 1 s (LanderSensors gyro_noise_density)", min = 0.0, max = GYRO_NOISE_DENSITY_MAX),
    decl!(228, parameter gyro_bias_random_walk: params.gyro.bias_random_walk, "rad/s", "1-sigma of the gyro bias change after 1 s (LanderSensors gyro_bias_random_walk)", min = 0.0, max = GYRO_BIAS_RANDOM_WALK_MAX),
    // The beam sensors and the terrain: LanderSensors' names and meanings.
    decl!(221, parameter gyro_scale_factor_sigma: params.gyro.scale_factor_sigma, "1", "1-sigma of the gyro's constant scale factor error per axis (LanderSensors gyro_scale_factor_sigma); 0 (default): not estimated", min = 0.0, max = SCALE_FACTOR_SIGMA_MAX),
    decl!(222, parameter gyro_misalignment_sigma: params.gyro.misalignment_sigma, "rad", "1-sigma of each component of the gyro's constant misalignment rotation (LanderSensors gyro_misalignment_sigma); 0 (default): not estimated", min = 0.0, max = MISALIGNMENT_SIGMA_MAX_RAD),
    decl!(230, parameter altimeter_beam_body[3]: params.altimeter_beam_body, "1", "Direction of the altimeter beam in body axes (normalised; LanderSensors altimeter_beam_body)", components = BODY),
    decl!(233, parameter altimeter_noise_sigma: params.altimeter_noise_sigma_m, "m", "1-sigma of the range noise independent of the range (LanderSensors altimeter_noise_sigma; > 0)", above = 0.0, max = RANGE_NOISE_SIGMA_MAX_M),
    decl!(234, parameter altimeter_noise_proportional: params.altimeter_noise_proportional, "1", "1-sigma of the range noise per metre of slant range, in quadrature (LanderSensors altimeter_noise_proportional)", min = 0.0, max = RANGE_NOISE_PROPORTIONAL_MAX),
    decl!(240, parameter velocimeter_beam_1_body[3]: params.velocimeter_beam_1_body, "1", "Direction of velocimeter beam 1 in body axes (LanderSensors velocimeter_beam_1_body)", components = BODY),
    decl!(243, parameter velocimeter_beam_2_body[3]: params.velocimeter_beam_2_body, "1", "Direction of velocimeter beam 2 in body axes (LanderSensors velocimeter_beam_2_body)", components = BODY),
    decl!(246, parameter velocimeter_beam_3_body[3]: params.velocimeter_beam_3_body, "1", "Direction of velocimeter beam 3 in body axes (LanderSensors velocimeter_beam_3_body)", components = BODY),
    decl!(249, parameter velocimeter_noise_sigma: params.velocimeter_noise_sigma_mps, "m/s", "1-sigma of each beam's line-of-sight velocity noise (LanderSensors velocimeter_noise_sigma; > 0)", above = 0.0, max = LOS_NOISE_SIGMA_MAX_MPS),
    decl!(260, parameter terrain_height: params.terrain_height_m, "m", "Up of the terrain plane at the origin (LanderSensors terrain_height)", min = -TERRAIN_HEIGHT_MAX_M, max = TERRAIN_HEIGHT_MAX_M),
    decl!(261, parameter terrain_slope_normal_nue[3]: params.terrain_slope_normal_nue, "1", "Normal of the terrain plane in NUE, pointing up (LanderSensors terrain_slope_normal_nue)", components = NUE),
    // Initialisation.
    decl!(300, parameter r0_nue[3]: params.r0_nue_m, "m", "Initial position estimate", components = NUE, min = -POSITION_MAX_M, max = POSITION_MAX_M),
    decl!(303, parameter v0_nue[3]: params.v0_nue_mps, "m/s", "Initial velocity estimate", components = NUE, min = -VELOCITY_MAX_MPS, max = VELOCITY_MAX_MPS),
    decl!(306, parameter q0_body_to_nue[4]: params.q0_body_to_nue, "1", "Initial attitude estimate, unit to 1e-6", components = QUATERNION, min = -1.0, max = 1.0),
    decl!(310, parameter r0_sigma: params.r0_sigma_m, "m", "Initial 1-sigma of the position error per axis", min = 0.0, max = R0_SIGMA_MAX_M),
    decl!(311, parameter v0_sigma: params.v0_sigma_mps, "m/s", "Initial 1-sigma of the velocity error per axis", min = 0.0, max = V0_SIGMA_MAX_MPS),
    decl!(312, parameter attitude0_sigma: params.attitude0_sigma_rad, "rad", "Initial 1-sigma of the attitude error about each body axis", min = 0.0, max = ATTITUDE0_SIGMA_MAX_RAD),
    // Gating.
    decl!(320, parameter chi2_gating: params.chi2_gating as bool, "Reject a scalar measurement whose normalised innovation squared exceeds chi2_gate (off by default)"),
    decl!(321, parameter chi2_gate: params.chi2_gate, "1", "Gate of each scalar measurement's NIS (1 degree of freedom; 10.83 is the 99.9 % quantile)", above = 0.0, max = CHI2_GATE_MAX),
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_export_layer_accepts_the_declarations() {
        assert_eq!(fmi2_export::check_table::<LanderFilter>(), Ok(()));
    }

    #[test]
    fn a_non_unit_initial_quaternion_fails_initialization_by_name() {
        let mut m = LanderFilter::default();
        m.params.q0_body_to_nue = [0.9, 0.0, 0.0, 0.0];
        let err = m.exit_initialization(0.0, &mut Log::default()).unwrap_err();
        assert!(err.to_string().contains("q0_body_to_nue"), "{err}");
        let mut log = Log::default();
        m.calculate_values(&mut log);
        assert!(log.has_warning());
        assert!(m.out.r_nue_m.iter().all(|x| x.is_finite()));
    }

    /// The mean specific force (body = NUE axes) over step `k`, changing every step.
    fn step_mean(k: usize) -> [f64; 3] {
        let sign = if k.is_multiple_of(2) { 1.0 } else { -1.0 };
        let k = k as f64;
        [0.02 * k, 1.62 + 0.05 * sign, -0.01 * k]
    }

    /// Flies `steps` steps of 0.01 s with no beam measurement, the IMU inputs at point k
    /// `input(k)`; the outputs at each point.
    fn flown(mean_mode: bool, input: impl Fn(usize) -> Imu, steps: usize) -> Vec<Outputs> {
        let mut m = LanderFilter::default();
        m.params.imu_mean_over_last_step = mean_mode;
        m.params.v0_nue_mps = [0.0; 3];
        let mut log = Log::default();
        m.exit_initialization(0.0, &mut log).unwrap();
        let mut out = Vec::new();
        for k in 0..=steps {
            m.meas.imu = input(k);
            m.calculate_values(&mut log);
            out.push(m.out.clone());
            if k < steps {
                m.do_step(k as f64 * 0.01, 0.01, &mut log).unwrap();
            }
        }
        out
    }

    #[test]
    fn with_the_mean_accelerometer_the_estimate_at_a_point_holds_the_step_that_ended_there() {
        // GIVEN a truth whose specific force changes every step, at rest at the start, and
        // the accelerometer at point k its mean over the step that ended there (at point 0
        // an instantaneous value, unused)
        let (h, g) = (0.01, 1.62);
        let input = |k: usize| Imu {
            accel_body_mps2: if k == 0 { [9.0; 3] } else { step_mean(k - 1) },
            gyro_body_radps: [0.0; 3],
        };
        let mut v = [0.0; 3];
        let mut r = [0.0, 800.0, 0.0];
        let mut truth = vec![(r, v)];
        for k in 0..20 {
            let f = step_mean(k);
            for i in 0..3 {
                let a = f[i] - if i == 1 { g } else { 0.0 };
                r[i] += v[i] * h + a * 0.5 * h * h;
                v[i] += a * h;
            }
            truth.push((r, v));
        }
        // WHEN the filter propagates with imu_mean_over_last_step
        let out = flown(true, input, 20);
        // THEN its estimate at every point is the truth, to rounding
        for (k, (o, (r, v))) in out.iter().zip(&truth).enumerate() {
            for i in 0..3 {
                assert!(
                    (o.v_nue_mps[i] - v[i]).abs() < 1e-14,
                    "{k} {i}: {o:?} vs {v:?}"
                );
                assert!(
                    (o.r_nue_m[i] - r[i]).abs() < 1e-11,
                    "{k} {i}: {o:?} vs {r:?}"
                );
            }
        }
        // AND without it, the same inputs held over the coming step are a step late
        let late = flown(false, input, 20);
        let error = (late[20].v_nue_mps[0] - truth[20].1[0]).abs();
        assert!(error > 1e-3, "{error}");
    }

    #[test]
    fn with_the_mean_gyro_the_attitude_at_a_point_holds_the_turn_of_the_step_that_ended_there() {
        // GIVEN a body rate whose mean changes every step, the gyro at point k its mean over
        // the step that ended there (at point 0 an instantaneous value, unused)
        let h = 0.01;
        let rate = |k: usize| {
            let sign = if k.is_multiple_of(2) { 1.0 } else { -1.0 };
            [0.1 * sign, 0.3 + 0.01 * k as f64, 0.0]
        };
        let input = |k: usize| Imu {
            accel_body_mps2: [0.0, 1.62, 0.0],
            gyro_body_radps: if k == 0 { [1.0; 3] } else { rate(k - 1) },
        };
        let mut q = [1.0, 0.0, 0.0, 0.0];
        let mut truth = vec![q];
        for k in 0..20 {
            let w = nalgebra::Vector3::from(rate(k)) * h;
            q = crate::model::rotation::mul(&q, &crate::model::rotation::exp(&w));
            truth.push(q);
        }
        // WHEN the filter propagates with imu_mean_over_last_step
        let out = flown(true, input, 20);
        // THEN its attitude at every point is the truth's, to rounding, and so is the body
        // rate output (the mean rate over the step that ended at the point)
        for (k, (o, q)) in out.iter().zip(&truth).enumerate() {
            for i in 0..4 {
                assert!(
                    (o.q_body_to_nue[i] - q[i]).abs() < 1e-14,
                    "{k}: {o:?} vs {q:?}"
                );
            }
            if k > 0 {
                assert_eq!(o.omega_body_radps, rate(k - 1));
            }
        }
        // AND without it the same inputs held over the coming step are a step late
        let late = flown(false, input, 20);
        let error = (late[20].q_body_to_nue[1] - truth[20][1]).abs();
        assert!(error > 1e-3, "{error}");
    }

    #[test]
    fn a_restored_pending_step_without_the_mean_imu_option_is_refused() {
        let mut m = LanderFilter::default();
        m.params.imu_mean_over_last_step = true;
        m.exit_initialization(0.0, &mut Log::default()).unwrap();
        m.do_step(0.0, 0.01, &mut Log::default()).unwrap();
        assert_eq!(m.validate_restored(true), Ok(()));
        m.params.imu_mean_over_last_step = false;
        assert!(m.validate_restored(true).is_err());
    }

    #[test]
    fn a_step_whose_estimate_would_overflow_is_refused_and_changes_nothing() {
        let mut m = LanderFilter::default();
        m.exit_initialization(0.0, &mut Log::default()).unwrap();
        m.meas.imu.accel_body_mps2 = [1e300; 3];
        let before = m.running.clone();
        let err = m.do_step(0.0, 1e10, &mut Log::default()).unwrap_err();
        assert!(matches!(err, ModelError::Refused(_)), "{err}");
        assert_eq!(m.running, before);
    }

    /// Found while covering the filter with the robustness suites: a terrain normal or a beam
    /// whose squared length overflows (each component finite; the directions have no
    /// declared bounds) was accepted and divided by infinity to zero, so that the filter
    /// silently used no altimeter and no velocimeter beam at all.
    #[test]
    fn directions_of_any_finite_length_act_as_their_unit_vectors() {
        let run = |scale: f64| {
            let mut m = LanderFilter::default();
            let p = &mut m.params;
            p.terrain_slope_normal_nue = [0.0, scale, 0.0];
            p.altimeter_beam_body = p.altimeter_beam_body.map(|x| x * scale);
            p.velocimeter_beam_1_body = p.velocimeter_beam_1_body.map(|x| x * scale);
            p.velocimeter_beam_2_body = p.velocimeter_beam_2_body.map(|x| x * scale);
            p.velocimeter_beam_3_body = p.velocimeter_beam_3_body.map(|x| x * scale);
            m.exit_initialization(0.0, &mut Log::default()).unwrap();
            m.meas.altimeter_valid = true;
            m.meas.altimeter_range_m = 790.0;
            m.meas.velocimeter_valid = [true; 3];
            m.meas.velocimeter_los_velocity_mps = [0.1, 0.2, 0.3];
            m.do_step(0.0, 0.01, &mut Log::default()).unwrap();
            (m.last, m.running.unwrap())
        };
        let (last, huge) = run(1e200);
        assert_eq!((last.altimeter_dof, last.velocimeter_dof), (1, 3));
        let (_, unit) = run(1.0);
        for (a, b) in huge.r_nue_m.iter().zip(&unit.r_nue_m) {
            assert!(
                (a - b).abs() < 1e-9,
                "{:?} vs {:?}",
                huge.r_nue_m,
                unit.r_nue_m
            );
        }
        for (a, b) in huge.v_nue_mps.iter().zip(&unit.v_nue_mps) {
            assert!(
                (a - b).abs() < 1e-12,
                "{:?} vs {:?}",
                huge.v_nue_mps,
                unit.v_nue_mps
            );
        }
    }

    /// Found while covering the filter with the robustness suites: an altimeter range of
    /// 1e300 m gave an innovation whose square overflows; the step was accepted and the
    /// NIS output read infinity, so every later read of it failed.
    #[test]
    fn a_step_whose_nis_would_overflow_is_refused_and_changes_nothing() {
        for (altimeter, los) in [(1e300, 0.0), (790.0, -1e200)] {
            let mut m = LanderFilter::default();
            m.exit_initialization(0.0, &mut Log::default()).unwrap();
            m.meas.altimeter_valid = true;
            m.meas.altimeter_range_m = altimeter;
            m.meas.velocimeter_valid = [true; 3];
            m.meas.velocimeter_los_velocity_mps = [los; 3];
            let before = (m.running.clone(), m.last);
            let err = m.do_step(0.0, 0.01, &mut Log::default()).unwrap_err();
            // The NIS, or the estimate corrected by such an innovation.
            assert!(matches!(err, ModelError::Refused(_)), "{err}");
            assert!(err.to_string().contains("finite"), "{err}");
            assert_eq!((m.running.clone(), m.last), before);
            let mut log = Log::default();
            m.calculate_values(&mut log);
            assert!(m.last.nis_altimeter.is_finite() && m.last.nis_velocimeter.is_finite());
        }
    }

    #[test]
    fn a_restored_state_must_hold_a_unit_quaternion_and_counts_of_one_update() {
        let mut m = LanderFilter::default();
        m.exit_initialization(0.0, &mut Log::default()).unwrap();
        assert_eq!(m.validate_restored(true), Ok(()));
        let mut q = m.clone();
        q.running.as_mut().unwrap().q_body_to_nue = [2.0, 0.0, 0.0, 0.0];
        assert!(q.validate_restored(true).is_err());
        let mut nis = m.clone();
        nis.last.nis_velocimeter = f64::NAN;
        assert!(nis.validate_restored(true).is_err());
        let mut dof = m.clone();
        dof.last.velocimeter_dof = 4;
        assert!(dof.validate_restored(true).is_err());
        let mut rejected = m;
        rejected.last.altimeter_dof = 1;
        rejected.last.rejected = 2;
        assert!(rejected.validate_restored(true).is_err());
    }

    /// Found by the robustness suite: a step of 1e300 s was named with its 301 digits.
    #[test]
    fn a_refused_step_names_its_size_readably() {
        let mut m = LanderFilter::default();
        m.exit_initialization(0.0, &mut Log::default()).unwrap();
        let err = m.do_step(0.0, 1e300, &mut Log::default()).unwrap_err();
        let message = err.to_string();
        assert!(
            message.contains("communicationStepSize 1e300 s"),
            "{message}"
        );
        assert!(message.len() < 200, "{message}");
    }
}
