//! The filter's parameters, their defaults and their validation (naming the field at fault).
//! The sensor models' parameters carry LanderSensors' names, meanings and defaults, so that a
//! filter left at its defaults matches the sensors left at theirs.
use serde::{Deserialize, Serialize};

/// The IMU's noise as LanderSensors declares it (the same names without the prefix).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ImuNoise {
    /// 1-sigma of the constant bias on each axis: the initial 1-sigma of the bias estimate.
    pub bias_sigma: f64,
    /// 1-sigma of the integrated white noise after 1 s (velocity or angle random walk).
    pub noise_density: f64,
    /// 1-sigma of the bias change after 1 s.
    pub bias_random_walk: f64,
    /// 1-sigma of the constant scale factor error on each axis (LanderSensors'
    /// `scale_factor_sigma`): the initial 1-sigma of its estimate; 0 leaves it unestimated.
    pub scale_factor_sigma: f64,
    /// 1-sigma of each component of the constant misalignment rotation (rad).
    pub misalignment_sigma: f64,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FilterParameters {
    /// Lunar gravity, along -Up (m/s2); a flat Moon, as LanderPlant's default.
    pub gravity_mps2: f64,
    /// The IMU's sampling interval (LanderSensors imu_sample_period): one sample's white
    /// noise has the variance `noise_density^2 / sample_period_s`.
    pub sample_period_s: f64,
    pub accel: ImuNoise,
    pub gyro: ImuNoise,
    pub altimeter_beam_body: [f64; 3],
    pub altimeter_noise_sigma_m: f64,
    pub altimeter_noise_proportional: f64,
    pub velocimeter_beam_1_body: [f64; 3],
    pub velocimeter_beam_2_body: [f64; 3],
    pub velocimeter_beam_3_body: [f64; 3],
    pub velocimeter_noise_sigma_mps: f64,
    pub terrain_height_m: f64,
    pub terrain_slope_normal_nue: [f64; 3],
    /// The initial estimate and its 1-sigmas (per axis).
    pub r0_nue_m: [f64; 3],
    pub v0_nue_mps: [f64; 3],
    pub q0_body_to_nue: [f64; 4],
    pub r0_sigma_m: f64,
    pub v0_sigma_mps: f64,
    pub attitude0_sigma_rad: f64,
    /// Reject a scalar measurement whose NIS exceeds `chi2_gate` (1 degree of freedom).
    pub chi2_gating: bool,
    pub chi2_gate: f64,
    /// The IMU inputs at a communication point are the means over the step that ended there
    /// (velocity and angle increments over the step, divided by it): the filter propagates
    /// that step with them, before the point's measurements. False: samples held over the
    /// coming step.
    pub imu_mean_over_last_step: bool,
}

/// The default velocimeter beam `i` of LanderSensors: 20 deg from body -y, at azimuths 0,
/// 120 and 240 deg from body +x towards body +z.
pub fn default_velocimeter_beam(i: usize) -> [f64; 3] {
    let cant = 20f64.to_radians();
    let azimuth = (120.0 * i as f64).to_radians();
    let (s, c) = libm::sincos(cant);
    let (sa, ca) = libm::sincos(azimuth);
    [s * ca, -c, s * sa]
}

impl Default for FilterParameters {
    fn default() -> Self {
        FilterParameters {
            gravity_mps2: 1.62,
            sample_period_s: 0.01,
            accel: ImuNoise {
                bias_sigma: 1e-3,
                noise_density: 5e-4,
                bias_random_walk: 1e-5,
                scale_factor_sigma: 0.0,
                misalignment_sigma: 0.0,
            },
            gyro: ImuNoise {
                bias_sigma: 1e-5,
                noise_density: 1.5e-5,
                bias_random_walk: 1e-7,
                scale_factor_sigma: 0.0,
                misalignment_sigma: 0.0,
            },
            altimeter_beam_body: [0.0, -1.0, 0.0],
            altimeter_noise_sigma_m: 0.1,
            altimeter_noise_proportional: 1e-3,
            velocimeter_beam_1_body: default_velocimeter_beam(0),
            velocimeter_beam_2_body: default_velocimeter_beam(1),
            velocimeter_beam_3_body: default_velocimeter_beam(2),
            velocimeter_noise_sigma_mps: 0.02,
            terrain_height_m: 0.0,
            terrain_slope_normal_nue: [0.0, 1.0, 0.0],
            r0_nue_m: [0.0, 800.0, 0.0],
            v0_nue_mps: [0.0; 3],
            q0_body_to_nue: [1.0, 0.0, 0.0, 0.0],
            r0_sigma_m: 10.0,
            v0_sigma_mps: 1.0,
            attitude0_sigma_rad: 0.01,
            chi2_gating: false,
            imu_mean_over_last_step: false,
            // The 99.9 % quantile of the chi-square distribution with 1 degree of freedom.
            chi2_gate: 10.83,
        }
    }
}

pub use fmi_model::parameter::ParameterError;

/// The declared bounds of the filter's own parameters; those of the sensors' parameters are
/// LanderSensors' ([`lander_math::sensor_limits`]).
pub mod bounds {
    pub use lander_math::sensor_limits::*;
    pub const GRAVITY_MAX: f64 = 30.0;
    pub const POSITION_MAX_M: f64 = 1e7;
    pub const VELOCITY_MAX_MPS: f64 = 1e4;
    pub const R0_SIGMA_MAX_M: f64 = 1e5;
    pub const V0_SIGMA_MAX_MPS: f64 = 1e3;
    pub const ATTITUDE0_SIGMA_MAX_RAD: f64 = 0.5;
    pub const CHI2_GATE_MAX: f64 = 1e6;
    /// How far `|q0_body_to_nue|` may be from 1.
    pub const QUATERNION_NORM_TOLERANCE: f64 = 1e-6;
}

fn refuse(field: &'static str, index: Option<usize>, value: f64, reason: String) -> ParameterError {
    ParameterError::real(field, index, value, reason)
}

impl FilterParameters {
    /// What the declarations cannot say (each value on its own is checked against its
    /// declaration, `fmi_model::parameter::check_declared`): directions, an upward terrain
    /// normal, a white noise variance that stays finite, a unit initial attitude.
    pub fn validate(&self) -> Result<(), ParameterError> {
        use bounds::QUATERNION_NORM_TOLERANCE;
        ParameterError::direction("altimeter_beam_body", &self.altimeter_beam_body)?;
        ParameterError::direction("velocimeter_beam_1_body", &self.velocimeter_beam_1_body)?;
        ParameterError::direction("velocimeter_beam_2_body", &self.velocimeter_beam_2_body)?;
        ParameterError::direction("velocimeter_beam_3_body", &self.velocimeter_beam_3_body)?;
        let n = &self.terrain_slope_normal_nue;
        ParameterError::direction("terrain_slope_normal_nue", n)?;
        if n[1] <= 0.0 {
            return Err(refuse(
                "terrain_slope_normal_nue",
                Some(1),
                n[1],
                "the terrain normal must point up (a positive Up component)".into(),
            ));
        }
        // One sample's white noise variance: with the shortest periods the bounds allow (down
        // to 5e-324 s) it overflows, and every step's covariance with it.
        for (name, density) in [
            ("accel_noise_density", self.accel.noise_density),
            ("gyro_noise_density", self.gyro.noise_density),
        ] {
            if !(density * density / self.sample_period_s).is_finite() {
                return Err(refuse(
                    "sample_period_s",
                    None,
                    self.sample_period_s,
                    format!(
                        "too short for {name} = {}: the white noise variance \
                         {name}^2 / imu_sample_period overflows",
                        fmi_model::readable(density)
                    ),
                ));
            }
        }
        let norm = super::rotation::norm(&self.q0_body_to_nue);
        if (norm - 1.0).abs() > QUATERNION_NORM_TOLERANCE {
            return Err(refuse("q0_body_to_nue", None, norm, format!("its norm {norm} is not 1 (tolerance {QUATERNION_NORM_TOLERANCE}): not an attitude")));
        }
        Ok(())
    }

    pub fn velocimeter_beams_body(&self) -> [[f64; 3]; 3] {
        [
            self.velocimeter_beam_1_body,
            self.velocimeter_beam_2_body,
            self.velocimeter_beam_3_body,
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_defaults_are_valid() {
        assert_eq!(FilterParameters::default().check(), Ok(()));
    }

    /// Found while covering the filter with the robustness suites: imu_sample_period =
    /// 5e-324 s (within its bounds) was accepted, and every step was then refused as "the
    /// estimate would not be finite", blaming the measurements.
    #[test]
    fn a_sample_period_whose_noise_variance_overflows_is_refused_by_name() {
        let p = FilterParameters {
            sample_period_s: 5e-324,
            ..FilterParameters::default()
        };
        let e = p.validate().unwrap_err();
        assert_eq!(e.field, "sample_period_s");
        assert!(e.reason.contains("accel_noise_density"), "{}", e.reason);
        // Without white noise any period in the bounds is fine.
        let mut quiet = p;
        quiet.accel.noise_density = 0.0;
        quiet.gyro.noise_density = 0.0;
        assert_eq!(quiet.validate(), Ok(()));
    }
}
