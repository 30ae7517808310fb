//! The IMU's calibration errors in the filter: the compensation inverts LanderSensors' model
//! `m = (I + diag(s)) (x - mu x x) + b` to first order, and the propagation's Jacobian
//! columns of the biases and the four calibration triads are what a perturbed bias or
//! calibration does to the propagated state (finite differences).
use fmu_filter::model::covariance::{BA, N, R as IR, THETA, V as IV};
use fmu_filter::model::eskf::Calibration;
use fmu_filter::model::rotation::{self, mul};
use fmu_filter::model::{Eskf, FilterParameters, Imu};
use nalgebra::Vector3;

#[test]
fn the_compensation_inverts_the_sensors_model_to_first_order() {
    // GIVEN a body value, 300 ppm-class scale factors and 0.5 mrad-class misalignments
    let x = Vector3::new(0.2, 1.9, -0.1);
    let s = Vector3::new(3e-4, -2e-4, 1e-4);
    let mu = Vector3::new(5e-4, -3e-4, 4e-4);
    // WHEN the sensors measure it (no bias) and the filter compensates with the same errors
    let m = (x - mu.cross(&x)).component_mul(&(Vector3::repeat(1.0) + s));
    let calibration = Calibration {
        scale_factor: s.into(),
        misalignment_rad: mu.into(),
    };
    let back = calibration.compensate(&m);
    // THEN what is left is second order: |s|^2 and |mu|^2 times |x|, about 1e-6 here
    let left = (back - x).norm();
    assert!(left < 2e-6, "{left:e}");
    // AND without the compensation the error is first order, a hundred times larger
    assert!((m - x).norm() > 100.0 * left, "{:e}", (m - x).norm());
}

/// The attitude error `dtheta` with `q_true = q_est exp(dtheta)`, small angles.
fn attitude_error(q_true: &[f64; 4], q_est: &[f64; 4]) -> Vector3<f64> {
    let d = mul(&[q_est[0], -q_est[1], -q_est[2], -q_est[3]], q_true);
    let sign = if d[0] < 0.0 { -2.0 } else { 2.0 };
    Vector3::new(d[1], d[2], d[3]) * sign
}

#[test]
fn the_calibration_columns_of_the_transition_are_the_finite_differences() {
    // GIVEN a tilted, turning lander under thrust, the IMU noise off (no process noise)
    let mut params = FilterParameters::default();
    params.accel.noise_density = 0.0;
    params.gyro.noise_density = 0.0;
    params.accel.bias_random_walk = 0.0;
    params.gyro.bias_random_walk = 0.0;
    let start = Eskf::start(&FilterParameters {
        q0_body_to_nue: rotation::exp(&Vector3::new(0.05, 0.3, 0.2)),
        v0_nue_mps: [1.0, -8.0, 0.5],
        ..params.clone()
    });
    let imu = Imu {
        accel_body_mps2: [0.15, 2.1, -0.08],
        gyro_body_radps: [0.04, -0.3, 0.12],
    };
    let h = 0.01;
    for j in BA..N {
        // WHEN the covariance is one at calibration state j alone, F P F^T is F's column j
        // times itself: its column j is F's column j
        let mut unit = start.clone();
        unit.p = [[0.0; N]; N];
        unit.p[j][j] = 1.0;
        unit.propagate(&params, &imu, h, None);
        // AND a true calibration off the estimate by eps in state j propagates to a state
        // off the propagated estimate by F's column j times eps
        let eps = 1e-6;
        let mut truth = start.clone();
        let mut dx = [0.0; N];
        dx[j] = eps;
        truth.inject(&dx);
        let mut estimate = start.clone();
        truth.propagate(&params, &imu, h, None);
        estimate.propagate(&params, &imu, h, None);
        let dv = Vector3::from(truth.v_nue_mps) - Vector3::from(estimate.v_nue_mps);
        let dr = Vector3::from(truth.r_nue_m) - Vector3::from(estimate.r_nue_m);
        let dtheta = attitude_error(&truth.q_body_to_nue, &estimate.q_body_to_nue);
        // THEN they agree to the part of the body's turn over the step that F leaves out (a
        // fraction |w| h / 2 of the column, docs/filter.md) and the finite difference's own
        // rounding (a few ulps of the state, 800 m for the position, over eps)
        let turn = Vector3::from(imu.gyro_body_radps).norm() * h;
        let rounding = |x: &[f64; 3]| 4.0 * f64::EPSILON * Vector3::from(*x).amax().max(1.0) / eps;
        for (block, diff, size) in [
            (IV, dv, estimate.v_nue_mps),
            (IR, dr, estimate.r_nue_m),
            (THETA, dtheta, [1.0; 3]),
        ] {
            let column = Vector3::from_fn(|a, _| unit.p[block + a][j]);
            let fd = diff / eps;
            assert!(
                (column - fd).norm() <= turn * fd.norm() + rounding(&size),
                "state {j}, rows {block}..: F {column:?}, difference {fd:?}",
            );
        }
        // AND the column is not trivially zero: each calibration state moves the velocity
        // or the attitude
        let moved = (0..3).any(|a| unit.p[IV + a][j] != 0.0 || unit.p[THETA + a][j] != 0.0);
        assert!(moved, "state {j}");
    }
}
