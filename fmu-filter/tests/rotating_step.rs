//! One propagation step of a body that turns while the specific force acts. With the body
//! rate `w` and the body specific force `f` constant over the step, the exact increments are
//! `dv = R0 (int_0^h exp([w]x t) dt) f h + g h` and the double integral for the position;
//! Rodrigues' formula gives both in closed form. The filter's increments must match them to
//! third order in `|w| h`; taken at the step's start attitude they would be off by
//! `(h^2 / 2) |w x f|`.
// std's transcendental functions here make the reference, outside the model.
#![allow(clippy::disallowed_methods)]
use fmu_filter::model::rotation::{self, skew};
use fmu_filter::model::{Eskf, FilterParameters, Imu};
use nalgebra::{Matrix3, Vector3};

#[test]
fn a_turning_body_gains_the_velocity_and_position_of_the_exact_integral() {
    // GIVEN a lander tilted 10 deg, moving, pitching at 0.5 rad/s about body z and yawing at
    // 0.2 rad/s about its thrust axis, with 2 m/s^2 of thrust and a small side force, over a
    // 0.01 s step
    let h = 0.01;
    let params = FilterParameters::default();
    let q0 = rotation::exp(&Vector3::new(0.0, 0.0, 10f64.to_radians()));
    let mut eskf = Eskf::start(&FilterParameters {
        q0_body_to_nue: q0,
        r0_nue_m: [5.0, 400.0, -3.0],
        v0_nue_mps: [1.0, -8.0, 0.5],
        ..params.clone()
    });
    let w = Vector3::new(0.0, 0.2, 0.5);
    let f = Vector3::new(0.03, 2.0, -0.01);
    let imu = Imu {
        accel_body_mps2: f.into(),
        gyro_body_radps: w.into(),
    };
    let (r0, v0) = (Vector3::from(eskf.r_nue_m), Vector3::from(eskf.v_nue_mps));
    // WHEN the filter propagates the step
    eskf.propagate(&params, &imu, h, None);
    // THEN the increments are Rodrigues' integrals (|w| h = 5.4e-3, so the third-order
    // remainder is about h^3 |w|^2 |f| / 6 = 1e-7 m/s)
    let rate = w.norm();
    let k = skew(&w);
    let (s, c) = ((rate * h).sin(), (rate * h).cos());
    let once = Matrix3::identity() * h
        + k * ((1.0 - c) / (rate * rate))
        + k * k * ((h - s / rate) / (rate * rate));
    let twice = Matrix3::identity() * (h * h / 2.0)
        + k * ((h - s / rate) / (rate * rate))
        + k * k * ((h * h / 2.0 - (1.0 - c) / (rate * rate)) / (rate * rate));
    let r_start = rotation::matrix(&q0);
    let g = Vector3::new(0.0, -params.gravity_mps2, 0.0);
    let dv_exact = r_start * once * f + g * h;
    let dr_exact = v0 * h + r_start * twice * f + g * (h * h / 2.0);
    let dv = Vector3::from(eskf.v_nue_mps) - v0;
    let dr = Vector3::from(eskf.r_nue_m) - r0;
    let held = (h * h / 2.0) * w.cross(&f).norm();
    assert!(held > 5e-5, "{held}");
    assert!(
        (dv - dv_exact).norm() < 2e-7,
        "{:e}",
        (dv - dv_exact).norm()
    );
    assert!(
        (dr - dr_exact).norm() < 1e-9,
        "{:e}",
        (dr - dr_exact).norm()
    );
    // AND the attitude is the start's turned by w h
    let q_exact = rotation::mul(&q0, &rotation::exp(&(w * h)));
    let turned: f64 = q_exact
        .iter()
        .zip(&eskf.q_body_to_nue)
        .map(|(a, b)| (a - b).abs())
        .sum();
    assert!(turned < 1e-15, "{turned:e}");
}
