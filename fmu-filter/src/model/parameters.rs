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

/// The declared bounds, shared with the declarations in `fmu.rs`.
pub mod bounds {
    pub const GRAVITY_MAX: f64 = 30.0;
    pub const SAMPLE_PERIOD_MAX_S: f64 = 1.0;
    pub const ACCEL_BIAS_SIGMA_MAX: f64 = 10.0;
    pub const GYRO_BIAS_SIGMA_MAX: f64 = 1.0;
    pub const ACCEL_NOISE_DENSITY_MAX: f64 = 1.0;
    pub const GYRO_NOISE_DENSITY_MAX: f64 = 0.1;
    pub const ACCEL_BIAS_RANDOM_WALK_MAX: f64 = 1.0;
    pub const GYRO_BIAS_RANDOM_WALK_MAX: f64 = 0.1;
    /// The calibration errors are first-order in the model: 10 % and 0.1 rad at most.
    pub const SCALE_FACTOR_SIGMA_MAX: f64 = 0.1;
    pub const MISALIGNMENT_SIGMA_MAX_RAD: f64 = 0.1;
    pub const RANGE_NOISE_SIGMA_MAX_M: f64 = 1000.0;
    pub const RANGE_NOISE_PROPORTIONAL_MAX: f64 = 1.0;
    pub const LOS_NOISE_SIGMA_MAX_MPS: f64 = 100.0;
    pub const TERRAIN_HEIGHT_MAX_M: f64 = 1e6;
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
    ParameterError::new(field, index, value, reason)
}

/// `value` in `[lo, hi]`, or `(lo, hi]` when `lo_open`.
fn within(
    field: &'static str,
    index: Option<usize>,
    value: f64,
    lo: f64,
    lo_open: bool,
    hi: f64,
) -> Result<(), ParameterError> {
    let above = if lo_open { value > lo } else { value >= lo };
    if above && value <= hi {
        return Ok(());
    }
    let open = if lo_open { "(" } else { "[" };
    Err(refuse(
        field,
        index,
        value,
        format!("must be in {open}{lo}, {hi}]"),
    ))
}

fn each(field: &'static str, v: &[f64], bound: f64) -> Result<(), ParameterError> {
    v.iter()
        .enumerate()
        .try_for_each(|(i, x)| within(field, Some(i), *x, -bound, false, bound))
}

impl FilterParameters {
    pub fn validate(&self) -> Result<(), ParameterError> {
        use bounds::*;
        within(
            "gravity_mps2",
            None,
            self.gravity_mps2,
            0.0,
            false,
            GRAVITY_MAX,
        )?;
        within(
            "sample_period_s",
            None,
            self.sample_period_s,
            0.0,
            true,
            SAMPLE_PERIOD_MAX_S,
        )?;
        let a = &self.accel;
        within(
            "accel.bias_sigma",
            None,
            a.bias_sigma,
            0.0,
            false,
            ACCEL_BIAS_SIGMA_MAX,
        )?;
        within(
            "accel.noise_density",
            None,
            a.noise_density,
            0.0,
            false,
            ACCEL_NOISE_DENSITY_MAX,
        )?;
        within(
            "accel.bias_random_walk",
            None,
            a.bias_random_walk,
            0.0,
            false,
            ACCEL_BIAS_RANDOM_WALK_MAX,
        )?;
        let g = &self.gyro;
        within(
            "gyro.bias_sigma",
            None,
            g.bias_sigma,
            0.0,
            false,
            GYRO_BIAS_SIGMA_MAX,
        )?;
        within(
            "gyro.noise_density",
            None,
            g.noise_density,
            0.0,
            false,
            GYRO_NOISE_DENSITY_MAX,
        )?;
        within(
            "gyro.bias_random_walk",
            None,
            g.bias_random_walk,
            0.0,
            false,
            GYRO_BIAS_RANDOM_WALK_MAX,
        )?;
        for (imu, scale, misalignment) in [
            (
                &self.accel,
                "accel.scale_factor_sigma",
                "accel.misalignment_sigma",
            ),
            (
                &self.gyro,
                "gyro.scale_factor_sigma",
                "gyro.misalignment_sigma",
            ),
        ] {
            within(
                scale,
                None,
                imu.scale_factor_sigma,
                0.0,
                false,
                SCALE_FACTOR_SIGMA_MAX,
            )?;
            within(
                misalignment,
                None,
                imu.misalignment_sigma,
                0.0,
                false,
                MISALIGNMENT_SIGMA_MAX_RAD,
            )?;
        }
        ParameterError::direction("altimeter_beam_body", &self.altimeter_beam_body)?;
        // A measurement noise of zero would make the innovation variance singular when the
        // covariance has collapsed: the noises are strictly positive.
        within(
            "altimeter_noise_sigma_m",
            None,
            self.altimeter_noise_sigma_m,
            0.0,
            true,
            RANGE_NOISE_SIGMA_MAX_M,
        )?;
        within(
            "altimeter_noise_proportional",
            None,
            self.altimeter_noise_proportional,
            0.0,
            false,
            RANGE_NOISE_PROPORTIONAL_MAX,
        )?;
        ParameterError::direction("velocimeter_beam_1_body", &self.velocimeter_beam_1_body)?;
        ParameterError::direction("velocimeter_beam_2_body", &self.velocimeter_beam_2_body)?;
        ParameterError::direction("velocimeter_beam_3_body", &self.velocimeter_beam_3_body)?;
        within(
            "velocimeter_noise_sigma_mps",
            None,
            self.velocimeter_noise_sigma_mps,
            0.0,
            true,
            LOS_NOISE_SIGMA_MAX_MPS,
        )?;
        within(
            "terrain_height_m",
            None,
            self.terrain_height_m,
            -TERRAIN_HEIGHT_MAX_M,
            false,
            TERRAIN_HEIGHT_MAX_M,
        )?;
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
        each("r0_nue_m", &self.r0_nue_m, POSITION_MAX_M)?;
        each("v0_nue_mps", &self.v0_nue_mps, VELOCITY_MAX_MPS)?;
        each("q0_body_to_nue", &self.q0_body_to_nue, 1.0)?;
        let norm = super::rotation::norm(&self.q0_body_to_nue);
        if (norm - 1.0).abs() > QUATERNION_NORM_TOLERANCE {
            return Err(refuse("q0_body_to_nue", None, norm, format!("its norm {norm} is not 1 (tolerance {QUATERNION_NORM_TOLERANCE}): not an attitude")));
        }
        within(
            "r0_sigma_m",
            None,
            self.r0_sigma_m,
            0.0,
            false,
            R0_SIGMA_MAX_M,
        )?;
        within(
            "v0_sigma_mps",
            None,
            self.v0_sigma_mps,
            0.0,
            false,
            V0_SIGMA_MAX_MPS,
        )?;
        within(
            "attitude0_sigma_rad",
            None,
            self.attitude0_sigma_rad,
            0.0,
            false,
            ATTITUDE0_SIGMA_MAX_RAD,
        )?;
        within("chi2_gate", None, self.chi2_gate, 0.0, true, CHI2_GATE_MAX)?;
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
        assert_eq!(FilterParameters::default().validate(), Ok(()));
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
