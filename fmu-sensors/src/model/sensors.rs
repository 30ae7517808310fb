//! All sensors together, and their timing. At communication point `k` (after `k` steps) the
//! outputs measure the inputs there, with the bias of sample `k` and the draws of sample `k`;
//! `step` moves the biases by their random walk over the step and goes to sample `k + 1`.
//! Reading the outputs never draws: they are a function of (parameters, inputs, state).
use super::draws::{bias_draws, calibration_draws, SampleDraws};
use super::parameters::{ImuErrors, SensorParameters};
use super::terrain::Terrain;
use super::truth::Truth;
use super::{beams, imu};
use lander_math::frames::{Body, BodyToNue, Nue};
use lander_math::quaternion::direction;
use serde::{Deserialize, Serialize};

/// What the sensors output at one communication point.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Measurements {
    pub accel_body_meas_mps2: [f64; 3],
    pub gyro_body_meas_radps: [f64; 3],
    pub altimeter_range_m: f64,
    pub altimeter_valid: bool,
    pub velocimeter_los_velocity_mps: [f64; 3],
    pub velocimeter_valid: [bool; 3],
}

/// The sensors' state: the sample number, the biases of that sample and the run's
/// calibration errors.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Sensors {
    pub sample: u64,
    pub accel_bias_mps2: [f64; 3],
    pub gyro_bias_radps: [f64; 3],
    pub accel_calibration: Calibration,
    pub gyro_calibration: Calibration,
}

/// One triad's scale factor errors and misalignment for the run: the parameters' fixed
/// values plus the draws.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Calibration {
    pub scale_factor: [f64; 3],
    pub misalignment_rad: [f64; 3],
}

impl Calibration {
    fn drawn(errors: &ImuErrors, scale: [f64; 3], misalignment: [f64; 3]) -> Calibration {
        Calibration {
            scale_factor: std::array::from_fn(|i| {
                errors.scale_factor_error[i] + errors.scale_factor_sigma * scale[i]
            }),
            misalignment_rad: std::array::from_fn(|i| {
                errors.misalignment_rad[i] + errors.misalignment_sigma * misalignment[i]
            }),
        }
    }

    /// `errors` with these calibration errors.
    fn applied(&self, errors: &ImuErrors) -> ImuErrors {
        ImuErrors {
            scale_factor_error: self.scale_factor,
            misalignment_rad: self.misalignment_rad,
            ..*errors
        }
    }

    fn is_finite(&self) -> bool {
        self.scale_factor
            .iter()
            .chain(&self.misalignment_rad)
            .all(|x| x.is_finite())
    }
}

impl Sensors {
    /// Sample 0: the run's constant biases and calibration errors drawn from the seed.
    pub fn start(params: &SensorParameters) -> Sensors {
        let (a, g) = bias_draws(params.seed);
        let [sa, ma, sg, mg] = calibration_draws(params.seed);
        Sensors {
            sample: 0,
            accel_bias_mps2: a.map(|w| params.accel.bias_sigma * w),
            gyro_bias_radps: g.map(|w| params.gyro.bias_sigma * w),
            accel_calibration: Calibration::drawn(&params.accel, sa, ma),
            gyro_calibration: Calibration::drawn(&params.gyro, sg, mg),
        }
    }

    /// The measurements of `truth` at this sample. The parameters must be valid and the
    /// truth checked ([`Truth::validate`]); `None` if a value would not be finite.
    pub fn measure(&self, params: &SensorParameters, truth: &Truth) -> Option<Measurements> {
        let draws = SampleDraws::of_sample(params.seed, self.sample);
        let accel = imu::measure(
            &self.accel_calibration.applied(&params.accel),
            &truth.specific_force_body_mps2,
            &self.accel_bias_mps2,
            &draws.accel_white,
            params.sample_period_s,
        );
        let gyro = imu::measure(
            &self.gyro_calibration.applied(&params.gyro),
            &truth.omega_body_radps,
            &self.gyro_bias_radps,
            &draws.gyro_white,
            params.sample_period_s,
        );
        let terrain = Terrain::new(params.terrain_height_m, &params.terrain_slope_normal_nue)?;
        let q = &truth.q_body_to_nue;
        let norm = libm::sqrt(q.iter().map(|x| x * x).sum::<f64>());
        let attitude = BodyToNue::of(&q.map(|x| x / norm));
        let r = Nue::from(truth.r_nue_m);
        let v = Nue::from(truth.v_nue_mps);
        let beam_nue = |b: &[f64; 3]| direction(b).map(|b| attitude.to_nue(&Body(b)));

        let d = beam_nue(&params.altimeter_beam_body)?;
        let altimeter = beams::sample(
            &params.altimeter,
            terrain.slant_range(&r, &d),
            |rho| rho,
            draws.altimeter_noise,
            draws.altimeter_dropout,
        );
        let mut los = [None; 3];
        for (i, b) in params.velocimeter_beams_body().iter().enumerate() {
            let d = beam_nue(b)?;
            los[i] = beams::sample(
                &params.velocimeter,
                terrain.slant_range(&r, &d),
                |_| v.dot(&d),
                draws.velocimeter_noise[i],
                draws.velocimeter_dropout[i],
            );
        }
        let m = Measurements {
            accel_body_meas_mps2: accel,
            gyro_body_meas_radps: gyro,
            altimeter_range_m: altimeter.unwrap_or(0.0),
            altimeter_valid: altimeter.is_some(),
            velocimeter_los_velocity_mps: los.map(|l| l.unwrap_or(0.0)),
            velocimeter_valid: los.map(|l| l.is_some()),
        };
        m.is_finite().then_some(m)
    }

    /// From this sample to the next, over a step of `h` seconds: each bias moves by
    /// `bias_random_walk * sqrt(h)` times a standard normal value. `None` (and no change) if
    /// a bias would not be finite.
    pub fn step(&mut self, params: &SensorParameters, h: f64) -> Option<()> {
        let draws = SampleDraws::of_sample(params.seed, self.sample);
        let root_h = libm::sqrt(h);
        let walk = |b: [f64; 3], rw: f64, w: [f64; 3]| -> [f64; 3] {
            std::array::from_fn(|i| b[i] + rw * root_h * w[i])
        };
        let a = walk(
            self.accel_bias_mps2,
            params.accel.bias_random_walk,
            draws.accel_walk,
        );
        let g = walk(
            self.gyro_bias_radps,
            params.gyro.bias_random_walk,
            draws.gyro_walk,
        );
        if !a.iter().chain(&g).all(|x| x.is_finite()) {
            return None;
        }
        self.accel_bias_mps2 = a;
        self.gyro_bias_radps = g;
        self.sample += 1;
        Some(())
    }

    /// Whether the state could have been reached with `params` (for a restored FMU state).
    pub fn inconsistency(&self) -> Option<String> {
        let all = self.accel_bias_mps2.iter().chain(&self.gyro_bias_radps);
        if !all.clone().all(|x| x.is_finite()) {
            return Some("a bias is not finite".to_string());
        }
        (!(self.accel_calibration.is_finite() && self.gyro_calibration.is_finite()))
            .then(|| "a calibration error is not finite".to_string())
    }
}

impl Measurements {
    pub fn is_finite(&self) -> bool {
        self.accel_body_meas_mps2
            .iter()
            .chain(&self.gyro_body_meas_radps)
            .chain(&self.velocimeter_los_velocity_mps)
            .chain([&self.altimeter_range_m])
            .all(|x| x.is_finite())
    }
}
