//! The paper case's GNC evaluations alone, for instruction counts: `n` samples at 100 Hz
//! (argument, default 17 200 = the 172 s flight) of an open-loop navigation sequence (a
//! lander descending and rocking), phi_cmd = 150 deg, each sample's guidance committed.
//! A second argument `shaped` turns the shaped thrust-axis manoeuvre on (15 deg/s, 0.1 rad/s2).
//!
//! `valgrind --tool=callgrind target/debug/examples/gnc_sample_loop N` for two values of N:
//! the difference of the totals over the difference of N is the cost of one evaluation,
//! free of start-up.
// std's transcendental functions here are outside the model.
#![allow(clippy::disallowed_methods)]
use fmu_gnc::attitude::profile::PhiProfile;
use fmu_gnc::controller::{gnc_sample, NavigationInputs};
use fmu_gnc::guidance::sequencer::GuidanceState;
use fmu_gnc::params::GncParameters;

const H_S: f64 = 0.01;

fn navigation(k: usize) -> NavigationInputs {
    let s = k as f64 * H_S;
    let half = 0.05 * (0.7 * s).sin();
    NavigationInputs {
        r_nue_m: [0.3, 800.0 - 2.0 * s, -0.2],
        v_nue_mps: [0.01, -2.0, 0.02],
        q_body_to_nue: [
            half.cos(),
            0.2 * half.sin(),
            0.5 * half.sin(),
            0.84 * half.sin(),
        ],
        omega_body_radps: [0.01, -0.02, 0.005],
        mass_kg: 880.0,
    }
}

fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .map(|a| a.parse().expect("the number of samples"))
        .unwrap_or(17_200);
    let shaped = std::env::args().nth(2).is_some_and(|a| a == "shaped");
    let design = GncParameters {
        phi_cmd_rad: 150f64.to_radians(),
        phi_rate_limit_radps: if shaped { 15f64.to_radians() } else { 0.0 },
        phi_accel_limit_radps2: if shaped { 0.1 } else { 0.0 },
        ..GncParameters::default()
    }
    .design()
    .expect("valid parameters");
    let mut guidance = GuidanceState::initial(design.params.gravity_mps2);
    let mut profile = PhiProfile::default();
    let mut torque_sum = 0.0;
    for k in 0..n {
        let t_s = k as f64 * H_S;
        let sample = gnc_sample(&design, 0.0, &guidance, &profile, &navigation(k), t_s);
        guidance = sample.advance.guidance;
        profile = sample.advance.profile;
        torque_sum += sample.outputs.torque_cmd_body_nm[1];
    }
    println!("{n} samples, sum of roll torque {torque_sum:?} N m");
}
