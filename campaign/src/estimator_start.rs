//! The navigation filter's start in a campaign. A scenario with an on-board filter
//! (LanderFilter, instance `filter`) initialises it with an estimate of the start; when the
//! campaign disperses the plant's start, the estimate must follow it, off by an error drawn
//! from the covariance the filter claims (`r0_sigma`, `v0_sigma`, `attitude0_sigma`), or
//! the filter starts with an error it neither knows of nor can observe (nothing measures
//! horizontal position). The sensors' noise seed (instance `sensors`) is drawn per run too.
//!
//! Every value is a pure function of the run seed, so every law and phi_cmd of a run sees
//! the same estimate and noise, and a replay the same bits. The normal draws are sums of
//! twelve uniforms minus six (mean 0, variance 1, tails cut at 6 sigma): additions only, no
//! logarithm of the platform's maths library (the attitude error's rotation takes a sine
//! and a cosine, as the dispersion's tilt does).
use crate::attitude::{self, Quat};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// The instance names a campaign recognises.
pub const FILTER: &str = "filter";
pub const SENSORS: &str = "sensors";

/// What the filter claims about its initial error, 1-sigma per axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClaimedStartError {
    pub r0_sigma_m: f64,
    pub v0_sigma_mps: f64,
    pub attitude0_sigma_rad: f64,
}

/// The truth a run starts from (the plant's dispersed start).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Start {
    pub r0_nue_m: [f64; 3],
    pub v0_nue_mps: [f64; 3],
    pub q0_body_to_nue: Quat,
}

/// Keeps the run's other streams (the dispersion draws from the run seed itself) apart.
const STREAM: u64 = 0x4649_4c54_4552_5354; // "FILTERST"

/// An approximately standard normal value from twelve uniforms.
fn normal(rng: &mut ChaCha8Rng) -> f64 {
    (0..12).map(|_| rng.gen::<f64>()).sum::<f64>() - 6.0
}

/// The filter's initial estimate for the run seeded with `run_seed`: the true start plus
/// an error drawn from `claimed`, the attitude error a rotation about the body axes
/// (q_est = q_true ⊗ δq). Draw order: position N, U, E; velocity N, U, E; attitude x, y, z.
pub fn estimate(run_seed: u64, truth: &Start, claimed: &ClaimedStartError) -> Start {
    let mut rng = ChaCha8Rng::seed_from_u64(run_seed ^ STREAM);
    let r0_nue_m = truth
        .r0_nue_m
        .map(|r| r + claimed.r0_sigma_m * normal(&mut rng));
    let v0_nue_mps = truth
        .v0_nue_mps
        .map(|v| v + claimed.v0_sigma_mps * normal(&mut rng));
    let error_body_rad = [(); 3].map(|_| claimed.attitude0_sigma_rad * normal(&mut rng));
    let angle = error_body_rad.iter().map(|a| a * a).sum::<f64>().sqrt();
    let q0_body_to_nue = if angle > 0.0 {
        let axis = error_body_rad.map(|a| a / angle);
        attitude::multiply(truth.q0_body_to_nue, attitude::from_axis_angle(axis, angle))
    } else {
        truth.q0_body_to_nue
    };
    Start {
        r0_nue_m,
        v0_nue_mps,
        q0_body_to_nue,
    }
}

/// The sensors' noise seed of a run: 31 bits (an FMI Integer), apart from the navigation
/// errors' seed (LanderNav takes the top 31 bits of the run seed).
pub fn sensors_seed(run_seed: u64) -> i64 {
    i64::try_from((run_seed ^ STREAM) & 0x7fff_ffff).expect("31 bits fit")
}

/// The filter parameters of an estimate (name, value).
pub fn parameters(estimate: &Start) -> Vec<(String, f64)> {
    let mut values = Vec::with_capacity(10);
    for i in 0..3 {
        values.push((format!("r0_nue[{}]", i + 1), estimate.r0_nue_m[i]));
        values.push((format!("v0_nue[{}]", i + 1), estimate.v0_nue_mps[i]));
    }
    for (k, q) in estimate.q0_body_to_nue.iter().enumerate() {
        values.push((format!("q0_body_to_nue[{}]", k + 1), *q));
    }
    values
}

#[cfg(test)]
mod tests {
    use super::*;

    const TRUTH: Start = Start {
        r0_nue_m: [10.0, 800.0, -5.0],
        v0_nue_mps: [0.5, -1.0, 0.0],
        q0_body_to_nue: [0.9914448613738104, 0.0, 0.0, -0.13052619222005157],
    };
    const CLAIMED: ClaimedStartError = ClaimedStartError {
        r0_sigma_m: 10.0,
        v0_sigma_mps: 1.0,
        attitude0_sigma_rad: 0.01,
    };

    /// The rotation angle between two unit quaternions.
    fn angle(a: Quat, b: Quat) -> f64 {
        let dot: f64 = a.iter().zip(&b).map(|(x, y)| x * y).sum();
        2.0 * dot.abs().min(1.0).acos()
    }

    #[test]
    fn a_filter_that_claims_no_error_starts_on_the_truth() {
        let exact = ClaimedStartError {
            r0_sigma_m: 0.0,
            v0_sigma_mps: 0.0,
            attitude0_sigma_rad: 0.0,
        };
        assert_eq!(estimate(42, &TRUTH, &exact), TRUTH);
    }

    #[test]
    fn the_errors_have_the_claimed_spread_and_are_the_same_for_a_seed() {
        // GIVEN 20,000 run seeds
        let n = 20_000;
        let (mut r2, mut v2, mut a2, mut r_mean) = (0.0, 0.0, 0.0, 0.0);
        for seed in 0..n {
            let e = estimate(seed, &TRUTH, &CLAIMED);
            for i in 0..3 {
                let dr = e.r0_nue_m[i] - TRUTH.r0_nue_m[i];
                r_mean += dr / (3 * n) as f64;
                r2 += dr * dr / (3 * n) as f64;
                v2 += (e.v0_nue_mps[i] - TRUTH.v0_nue_mps[i]).powi(2) / (3 * n) as f64;
            }
            a2 += angle(e.q0_body_to_nue, TRUTH.q0_body_to_nue).powi(2) / n as f64;
        }
        // THEN per axis the mean square error is the claimed variance (sampling error of a
        // variance over 60,000 values: 0.6 %; 2 % is beyond 3 sigma of it), the mean 0
        assert!((r2 / 100.0 - 1.0).abs() < 0.02, "{r2}");
        assert!((v2 - 1.0).abs() < 0.02, "{v2}");
        assert!(r_mean.abs() < 0.15, "{r_mean}");
        // AND the attitude error's squared angle sums three axes' variances
        assert!((a2 / (3.0 * 1e-4) - 1.0).abs() < 0.03, "{a2}");
        // AND a seed gives the same estimate twice, another seed another one
        assert_eq!(estimate(7, &TRUTH, &CLAIMED), estimate(7, &TRUTH, &CLAIMED));
        assert_ne!(estimate(7, &TRUTH, &CLAIMED), estimate(8, &TRUTH, &CLAIMED));
    }

    #[test]
    fn the_attitude_error_is_about_the_body_axes() {
        // GIVEN an error only about body y (the thrust axis), a claimed 0.3 rad
        let claimed = ClaimedStartError {
            r0_sigma_m: 0.0,
            v0_sigma_mps: 0.0,
            attitude0_sigma_rad: 0.3,
        };
        let e = estimate(3, &TRUTH, &claimed);
        // THEN the estimate's body axes are the truth's turned by the drawn rotation: the
        // truth's inverse times the estimate is that rotation in body axes, whatever the
        // truth's attitude (here 15 deg of tilt about Up)
        let conjugate = |q: Quat| [q[0], -q[1], -q[2], -q[3]];
        let relative = attitude::multiply(conjugate(TRUTH.q0_body_to_nue), e.q0_body_to_nue);
        let again = estimate(
            3,
            &Start {
                q0_body_to_nue: [1.0, 0.0, 0.0, 0.0],
                ..TRUTH
            },
            &claimed,
        );
        for (k, (a, b)) in relative.iter().zip(&again.q0_body_to_nue).enumerate() {
            assert!((a - b).abs() < 1e-15, "{k}");
        }
    }

    #[test]
    fn the_sensors_seed_fits_an_fmi_integer_and_differs_from_the_navigation_errors() {
        for run_seed in [0, 1, u64::MAX, 0x1234_5678_9abc_def0] {
            let s = sensors_seed(run_seed);
            assert!((0..=i64::from(i32::MAX)).contains(&s));
        }
        assert_ne!(sensors_seed(1), sensors_seed(2));
    }
}
