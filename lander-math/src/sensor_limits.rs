//! The admissible ranges of the sensor error parameters (inclusive upper bounds, lower
//! bounds 0 unless said). LanderSensors declares its parameters with them and LanderFilter
//! the same parameters of the same sensors: a value one FMU takes is one the other takes.

/// The IMU's sampling interval, s (lower bound exclusive).
pub const SAMPLE_PERIOD_MAX_S: f64 = 1.0;
/// 1-sigma of the accelerometer's constant bias, m/s2.
pub const ACCEL_BIAS_SIGMA_MAX: f64 = 10.0;
/// 1-sigma of the gyro's constant bias, rad/s.
pub const GYRO_BIAS_SIGMA_MAX: f64 = 1.0;
/// The fixed scale factor error, either sign.
pub const SCALE_FACTOR_ERROR_MAX: f64 = 0.5;
/// Each component of the fixed misalignment rotation, either sign, rad.
pub const MISALIGNMENT_MAX_RAD: f64 = 0.1;
/// 1-sigma of the drawn scale factor error: a tenth of the fixed value's bound, so that a
/// draw stays within that bound to ten sigmas. The filter estimates the error as a constant
/// entering linearly, as the sensors make it.
pub const SCALE_FACTOR_SIGMA_MAX: f64 = 0.05;
/// 1-sigma of each component of the drawn misalignment, rad: a tenth of the fixed value's
/// bound, where the first-order rotation both FMUs model (`x - mu x x`) is off by
/// `|mu|^2 / 2`, 5e-5 at one sigma.
pub const MISALIGNMENT_SIGMA_MAX_RAD: f64 = 0.01;
/// White noise density of the accelerometer, m/s/sqrt(s).
pub const ACCEL_NOISE_DENSITY_MAX: f64 = 1.0;
/// White noise density of the gyro, rad/sqrt(s).
pub const GYRO_NOISE_DENSITY_MAX: f64 = 0.1;
/// Bias random walk of the accelerometer, m/s2 after 1 s.
pub const ACCEL_BIAS_RANDOM_WALK_MAX: f64 = 1.0;
/// Bias random walk of the gyro, rad/s after 1 s.
pub const GYRO_BIAS_RANDOM_WALK_MAX: f64 = 0.1;
/// 1-sigma of the altimeter's range noise independent of the range, m.
pub const RANGE_NOISE_SIGMA_MAX_M: f64 = 1000.0;
/// 1-sigma of the altimeter's range noise per metre of range.
pub const RANGE_NOISE_PROPORTIONAL_MAX: f64 = 1.0;
/// A beam's maximum slant range, m (lower bound exclusive).
pub const MAX_RANGE_MAX_M: f64 = 1e6;
/// 1-sigma of a velocimeter beam's line-of-sight velocity noise, m/s.
pub const LOS_NOISE_SIGMA_MAX_MPS: f64 = 100.0;
/// Up of the terrain plane at the origin, either sign, m.
pub const TERRAIN_HEIGHT_MAX_M: f64 = 1e6;
