//! The IMU's measurement of one axis triad (accelerometer or gyro):
//!
//! `m = (I + diag(s)) (x - mu x x) + b + sigma w`
//!
//! `x` the true value in body axes, `s` the scale factor errors, `mu` the misalignment (a
//! small rotation vector from body to sensor axes, first order: `R^T x = x - mu x x`), `b` the
//! bias of this sample, `sigma = noise_density / sqrt(sample period)` and `w` standard normal.
use super::parameters::ImuErrors;
use nalgebra::Vector3;

pub fn measure(
    errors: &ImuErrors,
    truth: &[f64; 3],
    bias: &[f64; 3],
    white: &[f64; 3],
    sample_period_s: f64,
) -> [f64; 3] {
    let x = Vector3::from(*truth);
    let mu = Vector3::from(errors.misalignment_rad);
    let sensed = x - mu.cross(&x);
    let sigma = errors.noise_density / libm::sqrt(sample_period_s);
    std::array::from_fn(|i| {
        (1.0 + errors.scale_factor_error[i]) * sensed[i] + bias[i] + sigma * white[i]
    })
}
