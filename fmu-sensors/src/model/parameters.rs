//! The sensors' parameters, their defaults (a tactical-grade IMU, a laser altimeter down the
//! thrust axis, three Doppler beams canted 20 degrees from it) and their validation, which
//! names the field at fault. The bounds of each value are declared in `fmu.rs`.
use serde::{Deserialize, Serialize};

/// Cant of each velocimeter beam from body -y, and their azimuths about body y.
pub const VELOCIMETER_CANT_DEG: f64 = 20.0;
pub const VELOCIMETER_AZIMUTHS_DEG: [f64; 3] = [0.0, 120.0, 240.0];

/// The IMU's error parameters. The same names and meanings are the filter's process noise
/// parameters (LanderFilter), so a user sets both alike.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ImuErrors {
    /// 1-sigma of the constant bias on each axis, drawn once per run from the seed.
    pub bias_sigma: f64,
    /// Scale factor error per axis (0.001 = 1000 ppm): this fixed value plus one drawn once
    /// per run from the seed with the 1-sigma `scale_factor_sigma`.
    pub scale_factor_error: [f64; 3],
    pub scale_factor_sigma: f64,
    /// Misalignment of the sensor axes from the body axes: a small rotation vector (rad),
    /// this fixed value plus one drawn once per run with the 1-sigma `misalignment_sigma` per
    /// component.
    pub misalignment_rad: [f64; 3],
    pub misalignment_sigma: f64,
    /// White noise density: the 1-sigma of the integrated noise after 1 s (velocity or angle
    /// random walk), numerically the density per square root of hertz.
    pub noise_density: f64,
    /// Bias random walk: the 1-sigma of the bias change after 1 s.
    pub bias_random_walk: f64,
}

/// A beam's measurement errors and limits.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BeamErrors {
    /// 1-sigma of the white noise of each sample.
    pub noise_sigma: f64,
    /// 1-sigma of the noise proportional to the slant range (altimeter only; 0 for the
    /// velocimeter), added in quadrature to `noise_sigma`.
    pub noise_proportional: f64,
    /// Slant range beyond which the beam sees no return (m).
    pub max_range_m: f64,
    /// Probability that a sample is lost (reported invalid).
    pub dropout_probability: f64,
    /// Whether the sensor works at all: false is a failure (tunable, thrown during a run),
    /// every sample invalid until it is true again.
    pub available: bool,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SensorParameters {
    pub seed: i32,
    /// The IMU's sampling interval, the communication step the master takes: the white noise
    /// of one sample has the 1-sigma `noise_density / sqrt(sample_period_s)`.
    pub sample_period_s: f64,
    pub accel: ImuErrors,
    pub gyro: ImuErrors,
    /// Unit direction of the altimeter beam in body axes (normalised when used).
    pub altimeter_beam_body: [f64; 3],
    pub altimeter: BeamErrors,
    pub velocimeter_beam_1_body: [f64; 3],
    pub velocimeter_beam_2_body: [f64; 3],
    pub velocimeter_beam_3_body: [f64; 3],
    pub velocimeter: BeamErrors,
    /// Up of the terrain plane at the origin (m).
    pub terrain_height_m: f64,
    /// Normal of the terrain plane in NUE, pointing up (normalised when used).
    pub terrain_slope_normal_nue: [f64; 3],
}

/// The default velocimeter beam `i`: canted from body -y by [`VELOCIMETER_CANT_DEG`], at
/// azimuth [`VELOCIMETER_AZIMUTHS_DEG`]`[i]` from body +x towards body +z.
pub fn default_velocimeter_beam(i: usize) -> [f64; 3] {
    let cant = VELOCIMETER_CANT_DEG.to_radians();
    let azimuth = VELOCIMETER_AZIMUTHS_DEG[i].to_radians();
    let (s, c) = libm::sincos(cant);
    let (sa, ca) = libm::sincos(azimuth);
    [s * ca, -c, s * sa]
}

impl Default for SensorParameters {
    fn default() -> Self {
        SensorParameters {
            seed: 0,
            sample_period_s: 0.01,
            accel: ImuErrors {
                bias_sigma: 1e-3,
                scale_factor_error: [0.0; 3],
                scale_factor_sigma: 0.0,
                misalignment_rad: [0.0; 3],
                misalignment_sigma: 0.0,
                noise_density: 5e-4,
                bias_random_walk: 1e-5,
            },
            gyro: ImuErrors {
                bias_sigma: 1e-5,
                scale_factor_error: [0.0; 3],
                scale_factor_sigma: 0.0,
                misalignment_rad: [0.0; 3],
                misalignment_sigma: 0.0,
                noise_density: 1.5e-5,
                bias_random_walk: 1e-7,
            },
            altimeter_beam_body: [0.0, -1.0, 0.0],
            altimeter: BeamErrors {
                noise_sigma: 0.1,
                noise_proportional: 1e-3,
                max_range_m: 2000.0,
                dropout_probability: 0.0,
                available: true,
            },
            velocimeter_beam_1_body: default_velocimeter_beam(0),
            velocimeter_beam_2_body: default_velocimeter_beam(1),
            velocimeter_beam_3_body: default_velocimeter_beam(2),
            velocimeter: BeamErrors {
                noise_sigma: 0.02,
                noise_proportional: 0.0,
                max_range_m: 1000.0,
                dropout_probability: 0.0,
                available: true,
            },
            terrain_height_m: 0.0,
            terrain_slope_normal_nue: [0.0, 1.0, 0.0],
        }
    }
}

pub use fmi_model::parameter::ParameterError;

fn refuse(field: &'static str, index: Option<usize>, value: f64, reason: &str) -> ParameterError {
    ParameterError::real(field, index, value, reason)
}

impl SensorParameters {
    /// What the declarations cannot say (each value on its own is checked against its
    /// declaration, `fmi_model::parameter::check_declared`): the beams and the terrain normal
    /// are directions, the normal points up, the velocimeter has no range-proportional noise.
    pub fn validate(&self) -> Result<(), ParameterError> {
        if self.velocimeter.noise_proportional != 0.0 {
            let v = self.velocimeter.noise_proportional;
            return Err(refuse(
                "velocimeter.noise_proportional",
                None,
                v,
                "the velocimeter has no range-proportional noise",
            ));
        }
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
                "the terrain normal must point up (a positive Up component)",
            ));
        }
        Ok(())
    }

    /// The three velocimeter beams, in beam order.
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
    fn the_defaults_are_valid_and_the_beams_unit_and_canted() {
        let p = SensorParameters::default();
        assert_eq!(p.check(), Ok(()));
        for b in p.velocimeter_beams_body() {
            let norm = libm::sqrt(b.iter().map(|x| x * x).sum::<f64>());
            assert!((norm - 1.0).abs() < 1e-15);
            let cant = libm::acos(-b[1]).to_degrees();
            assert!((cant - VELOCIMETER_CANT_DEG).abs() < 1e-12, "{cant}");
        }
    }

    #[test]
    fn a_zero_or_downward_terrain_normal_is_refused_by_name() {
        let mut p = SensorParameters {
            terrain_slope_normal_nue: [0.0; 3],
            ..SensorParameters::default()
        };
        assert_eq!(p.validate().unwrap_err().field, "terrain_slope_normal_nue");
        p.terrain_slope_normal_nue = [0.0, -1.0, 0.0];
        assert_eq!(p.validate().unwrap_err().index, Some(1));
    }

    #[test]
    fn a_zero_beam_is_refused_by_name() {
        let p = SensorParameters {
            velocimeter_beam_2_body: [0.0; 3],
            ..SensorParameters::default()
        };
        assert_eq!(p.validate().unwrap_err().field, "velocimeter_beam_2_body");
    }
}
