//! The beam sensors: a laser altimeter (slant range) and the Doppler velocimeter beams
//! (line-of-sight velocity `v . d`, the lander's velocity relative to the terrain along the
//! beam, positive away from the lander, i.e. towards the terrain). A beam is valid when its
//! sensor is available, it meets the terrain within its maximum range and its sample is not
//! dropped; an invalid measurement reads 0.
use super::parameters::BeamErrors;

/// One beam's sample: the measured value, or `None` when invalid.
pub fn sample(
    errors: &BeamErrors,
    slant_range_m: Option<f64>,
    truth: impl FnOnce(f64) -> f64,
    noise: f64,
    dropout: f64,
) -> Option<f64> {
    if !errors.available {
        return None;
    }
    let rho = slant_range_m.filter(|rho| *rho <= errors.max_range_m)?;
    if dropout < errors.dropout_probability {
        return None;
    }
    Some(truth(rho) + range_sigma(errors, rho) * noise)
}

/// The 1-sigma of a beam's noise at the slant range `rho`: `sqrt(sigma^2 + (k rho)^2)`.
pub fn range_sigma(errors: &BeamErrors, rho: f64) -> f64 {
    let p = errors.noise_proportional * rho;
    libm::sqrt(errors.noise_sigma * errors.noise_sigma + p * p)
}
