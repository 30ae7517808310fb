//! The random numbers of one sample, counter-based as LanderNav's: the draws of sample `k`
//! are a function of `(seed, k)` alone, so a restored state needs only its sample number, no
//! read can shift the sequence, and any master stepping the same grid sees the same numbers.
//!
//! Sample `k` uses ChaCha12 keyed by the seed (rand_core's portable `seed_from_u64`) on
//! stream `k`, and always draws the same values in the same order, whatever is switched on:
//! accelerometer white noise (3), gyro white noise (3), accelerometer bias walk (3), gyro bias
//! walk (3), altimeter noise, altimeter dropout, then per velocimeter beam its noise and its
//! dropout. The run's constant biases come from stream [`BIAS_STREAM`], its constant
//! calibration errors from [`CALIBRATION_STREAM`].
//!
//! Normal values are rand_distr's `StandardNormal` (its ziggurat). Unlike LanderNav's own
//! copy with libm, it calls std's `exp` and `ln` in its rare rejection branches, so the
//! sequence is reproducible on one platform; across platforms a last-bit difference of the C
//! library could in principle flip one accept-reject test.
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha12Rng;
use rand_distr::StandardNormal;

/// The stream of the run's constant biases: never a sample number.
pub const BIAS_STREAM: u64 = u64::MAX;
/// The stream of the run's constant calibration errors: never a sample number.
pub const CALIBRATION_STREAM: u64 = u64::MAX - 1;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SampleDraws {
    pub accel_white: [f64; 3],
    pub gyro_white: [f64; 3],
    pub accel_walk: [f64; 3],
    pub gyro_walk: [f64; 3],
    pub altimeter_noise: f64,
    /// Uniform in [0, 1): the sample is lost when below the dropout probability.
    pub altimeter_dropout: f64,
    pub velocimeter_noise: [f64; 3],
    pub velocimeter_dropout: [f64; 3],
}

fn rng(seed: i32, stream: u64) -> ChaCha12Rng {
    let mut rng = ChaCha12Rng::seed_from_u64(seed as u64);
    rng.set_stream(stream);
    rng
}

fn normals<const N: usize>(rng: &mut ChaCha12Rng) -> [f64; N] {
    std::array::from_fn(|_| rng.sample(StandardNormal))
}

impl SampleDraws {
    pub fn of_sample(seed: i32, sample: u64) -> SampleDraws {
        let mut rng = rng(seed, sample);
        let accel_white = normals(&mut rng);
        let gyro_white = normals(&mut rng);
        let accel_walk = normals(&mut rng);
        let gyro_walk = normals(&mut rng);
        let altimeter_noise = rng.sample(StandardNormal);
        let altimeter_dropout = rng.gen::<f64>();
        let mut velocimeter_noise = [0.0; 3];
        let mut velocimeter_dropout = [0.0; 3];
        for i in 0..3 {
            velocimeter_noise[i] = rng.sample(StandardNormal);
            velocimeter_dropout[i] = rng.gen::<f64>();
        }
        SampleDraws {
            accel_white,
            gyro_white,
            accel_walk,
            gyro_walk,
            altimeter_noise,
            altimeter_dropout,
            velocimeter_noise,
            velocimeter_dropout,
        }
    }
}

/// Standard normal values of the run's constant calibration errors, in the order
/// accelerometer scale factor, accelerometer misalignment, gyro scale factor, gyro
/// misalignment.
pub fn calibration_draws(seed: i32) -> [[f64; 3]; 4] {
    let mut rng = rng(seed, CALIBRATION_STREAM);
    std::array::from_fn(|_| normals(&mut rng))
}

/// Standard normal values of the run's constant biases: (accelerometer, gyro).
pub fn bias_draws(seed: i32) -> ([f64; 3], [f64; 3]) {
    let mut rng = rng(seed, BIAS_STREAM);
    (normals(&mut rng), normals(&mut rng))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sample_draws_the_same_values_whenever_it_is_asked() {
        assert_eq!(
            SampleDraws::of_sample(7, 123),
            SampleDraws::of_sample(7, 123)
        );
        assert_ne!(
            SampleDraws::of_sample(7, 123),
            SampleDraws::of_sample(7, 124)
        );
        assert_ne!(
            SampleDraws::of_sample(7, 123),
            SampleDraws::of_sample(8, 123)
        );
        assert_ne!(bias_draws(7), bias_draws(8));
    }
}
