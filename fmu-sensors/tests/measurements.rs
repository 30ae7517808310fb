//! The sensor models against analytic values: exact truth with every error off, slant range
//! over a flat and a sloped plane, line-of-sight velocity, bias / scale factor / misalignment
//! as documented, noise and dropout statistics, and the validity limits.
//!
//! Statistical bounds: a sample mean of N values of 1-sigma s lies within 4 s/sqrt(N) of the
//! true mean, a sample standard deviation within 4 s/sqrt(2N) of s, a count of events of
//! probability p within 4 sqrt(N p (1-p)) of N p (each fails with probability below 1e-4;
//! the seeds are fixed, so the tests are deterministic).
// std's transcendental functions here make test inputs and references, outside the model.
#![allow(clippy::disallowed_methods)]
use fmu_sensors::model::draws::bias_draws;
use fmu_sensors::model::parameters::{BeamErrors, ImuErrors};
use fmu_sensors::model::{SensorParameters, Sensors, Truth};

const OFF_IMU: ImuErrors = ImuErrors {
    bias_sigma: 0.0,
    scale_factor_error: [0.0; 3],
    scale_factor_sigma: 0.0,
    misalignment_rad: [0.0; 3],
    misalignment_sigma: 0.0,
    noise_density: 0.0,
    bias_random_walk: 0.0,
};

/// Every error off: the measurements are the truth.
fn perfect() -> SensorParameters {
    let mut p = SensorParameters {
        accel: OFF_IMU,
        gyro: OFF_IMU,
        ..SensorParameters::default()
    };
    for beam in [&mut p.altimeter, &mut p.velocimeter] {
        *beam = BeamErrors {
            noise_sigma: 0.0,
            noise_proportional: 0.0,
            ..*beam
        };
    }
    p
}

/// The Hamilton product, written here independently of the crate's rotation matrix.
fn mul(a: [f64; 4], b: [f64; 4]) -> [f64; 4] {
    [
        a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
        a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
        a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
        a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0],
    ]
}

/// `q v q*`.
fn rotate(q: [f64; 4], v: [f64; 3]) -> [f64; 3] {
    let r = mul(mul(q, [0.0, v[0], v[1], v[2]]), [q[0], -q[1], -q[2], -q[3]]);
    [r[1], r[2], r[3]]
}

/// Rotation by `angle` about the unit `axis`.
fn about(axis: [f64; 3], angle: f64) -> [f64; 4] {
    let (s, c) = (angle / 2.0).sin_cos();
    [c, s * axis[0], s * axis[1], s * axis[2]]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn truth(r: [f64; 3], v: [f64; 3], q: [f64; 4]) -> Truth {
    Truth {
        r_nue_m: r,
        v_nue_mps: v,
        q_body_to_nue: q,
        omega_body_radps: [0.01, -0.02, 0.003],
        specific_force_body_mps2: [0.1, 1.62, -0.05],
    }
}

fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * b.abs().max(1.0)
}

#[test]
fn with_every_error_off_the_measurements_are_the_truth() {
    let p = perfect();
    let s = Sensors::start(&p);
    let t = truth([3.0, 700.0, -2.0], [1.0, -12.0, 0.5], [1.0, 0.0, 0.0, 0.0]);
    let m = s.measure(&p, &t).unwrap();
    assert_eq!(m.accel_body_meas_mps2, t.specific_force_body_mps2);
    assert_eq!(m.gyro_body_meas_radps, t.omega_body_radps);
    assert!(m.altimeter_valid);
    assert_eq!(m.altimeter_range_m, 700.0);
    for (i, b) in p.velocimeter_beams_body().iter().enumerate() {
        assert!(m.velocimeter_valid[i]);
        assert!(close(
            m.velocimeter_los_velocity_mps[i],
            dot(t.v_nue_mps, *b),
            1e-15
        ));
    }
}

#[test]
fn over_a_flat_plane_a_tilted_beam_measures_height_over_cosine() {
    let p = perfect();
    let s = Sensors::start(&p);
    for tilt_deg in [0.0f64, 5.0, 30.0, 60.0] {
        let tilt = tilt_deg.to_radians();
        let q = about([0.0, 0.0, 1.0], tilt);
        let m = s
            .measure(&p, &truth([0.0, 800.0, 0.0], [0.0; 3], q))
            .unwrap();
        assert!(
            close(m.altimeter_range_m, 800.0 / tilt.cos(), 1e-12),
            "{tilt_deg}: {}",
            m.altimeter_range_m
        );
    }
}

#[test]
fn over_a_sloped_plane_the_range_is_height_along_the_normal_over_cosine() {
    // GIVEN a plane through (0, 50, 0) sloping by 10 deg about East, and a lander 400 m North
    let alpha = 10f64.to_radians();
    let mut p = perfect();
    p.terrain_height_m = 50.0;
    p.terrain_slope_normal_nue = [alpha.sin(), alpha.cos(), 0.0];
    let s = Sensors::start(&p);
    for tilt_deg in [0.0f64, 15.0, -25.0] {
        let q = about([0.0, 0.0, 1.0], tilt_deg.to_radians());
        let r = [400.0, 900.0, 30.0];
        let m = s.measure(&p, &truth(r, [0.0; 3], q)).unwrap();
        // THEN rho = h / cos(angle between the beam and -n), h the height along the normal
        let n = p.terrain_slope_normal_nue;
        let h = dot(n, [r[0], r[1] - 50.0, r[2]]);
        let d = rotate(q, [0.0, -1.0, 0.0]);
        let expected = h / -dot(n, d);
        assert!(close(m.altimeter_range_m, expected, 1e-12), "{tilt_deg}");
        // AND upright, the vertical drop to the plane: 850 m plus 400 tan(alpha)
        if tilt_deg == 0.0 {
            assert!(close(
                m.altimeter_range_m,
                850.0 + 400.0 * alpha.tan(),
                1e-12
            ));
        }
    }
}

#[test]
fn the_line_of_sight_velocity_is_the_velocity_along_each_beam() {
    let p = perfect();
    let s = Sensors::start(&p);
    let q = about([0.6, 0.0, 0.8], 0.3);
    let v = [4.0, -15.0, 2.5];
    let m = s.measure(&p, &truth([0.0, 500.0, 0.0], v, q)).unwrap();
    for (i, b) in p.velocimeter_beams_body().iter().enumerate() {
        let d = rotate(q, *b);
        assert!(m.velocimeter_valid[i]);
        assert!(
            close(m.velocimeter_los_velocity_mps[i], dot(v, d), 1e-13),
            "{i}"
        );
    }
}

#[test]
fn bias_scale_factor_and_misalignment_apply_as_documented() {
    // m = (1 + s_i) (x - mu x x)_i + b_i
    let mut p = perfect();
    p.seed = 11;
    p.accel.bias_sigma = 0.01;
    p.accel.scale_factor_error = [1e-3, -2e-3, 5e-4];
    p.accel.misalignment_rad = [1e-3, 0.0, -2e-3];
    p.gyro.bias_sigma = 1e-4;
    p.gyro.scale_factor_error = [0.0, 3e-3, 0.0];
    p.gyro.misalignment_rad = [0.0, 4e-3, 0.0];
    let s = Sensors::start(&p);
    let t = truth([0.0, 500.0, 0.0], [0.0; 3], [1.0, 0.0, 0.0, 0.0]);
    let m = s.measure(&p, &t).unwrap();
    let (wa, wg) = bias_draws(11);
    let expect = |x: [f64; 3], e: &ImuErrors, w: [f64; 3]| -> [f64; 3] {
        let mu = e.misalignment_rad;
        let cross = [
            mu[1] * x[2] - mu[2] * x[1],
            mu[2] * x[0] - mu[0] * x[2],
            mu[0] * x[1] - mu[1] * x[0],
        ];
        std::array::from_fn(|i| {
            (1.0 + e.scale_factor_error[i]) * (x[i] - cross[i]) + e.bias_sigma * w[i]
        })
    };
    let ea = expect(t.specific_force_body_mps2, &p.accel, wa);
    let eg = expect(t.omega_body_radps, &p.gyro, wg);
    for i in 0..3 {
        assert!(close(m.accel_body_meas_mps2[i], ea[i], 1e-14), "accel {i}");
        assert!(close(m.gyro_body_meas_radps[i], eg[i], 1e-14), "gyro {i}");
    }
}

fn mean_std(x: &[f64]) -> (f64, f64) {
    let n = x.len() as f64;
    let mean = x.iter().sum::<f64>() / n;
    let var = x.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / (n - 1.0);
    (mean, var.sqrt())
}

fn assert_normal(x: &[f64], mean: f64, sigma: f64, what: &str) {
    let n = x.len() as f64;
    let (m, s) = mean_std(x);
    assert!(
        (m - mean).abs() < 4.0 * sigma / n.sqrt(),
        "{what}: mean {m}, expected {mean}"
    );
    assert!(
        (s - sigma).abs() < 4.0 * sigma / (2.0 * n).sqrt(),
        "{what}: std {s}, expected {sigma}"
    );
}

#[test]
fn the_constant_biases_have_their_one_sigma_over_seeds() {
    let mut p = perfect();
    p.accel.bias_sigma = 2e-3;
    p.gyro.bias_sigma = 3e-5;
    let mut accel = Vec::new();
    let mut gyro = Vec::new();
    for seed in 0..3000 {
        p.seed = seed;
        let s = Sensors::start(&p);
        accel.extend(s.accel_bias_mps2);
        gyro.extend(s.gyro_bias_radps);
    }
    assert_normal(&accel, 0.0, 2e-3, "accel bias");
    assert_normal(&gyro, 0.0, 3e-5, "gyro bias");
}

#[test]
fn the_drawn_calibration_errors_have_their_one_sigma_over_seeds_around_the_fixed_values() {
    // GIVEN fixed scale factors and misalignments, and 1-sigmas of the drawn parts
    let mut p = perfect();
    p.accel.scale_factor_error = [1e-3, 0.0, -1e-3];
    p.accel.scale_factor_sigma = 3e-4;
    p.accel.misalignment_sigma = 5e-4;
    p.accel.bias_sigma = 1e-3;
    p.gyro.misalignment_rad = [0.0, 2e-3, 0.0];
    p.gyro.scale_factor_sigma = 2e-4;
    p.gyro.misalignment_sigma = 1e-3;
    let (mut sa, mut ma, mut sg, mut mg) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for seed in 0..3000 {
        p.seed = seed;
        let s = Sensors::start(&p);
        // THEN each run's errors are the fixed value plus a normal draw of that 1-sigma
        for i in 0..3 {
            sa.push(s.accel_calibration.scale_factor[i] - p.accel.scale_factor_error[i]);
            ma.push(s.accel_calibration.misalignment_rad[i]);
            sg.push(s.gyro_calibration.scale_factor[i]);
            mg.push(s.gyro_calibration.misalignment_rad[i] - p.gyro.misalignment_rad[i]);
        }
        // AND the constant biases are drawn as without calibration draws (their own stream)
        let (wa, _) = bias_draws(seed);
        assert_eq!(s.accel_bias_mps2, wa.map(|w| p.accel.bias_sigma * w));
    }
    assert_normal(&sa, 0.0, 3e-4, "accel scale factor");
    assert_normal(&ma, 0.0, 5e-4, "accel misalignment");
    assert_normal(&sg, 0.0, 2e-4, "gyro scale factor");
    assert_normal(&mg, 0.0, 1e-3, "gyro misalignment");
    // AND a run measures with its drawn errors: m = (1 + s) (x - mu x x) for an upright,
    // still lander under thrust along body y
    p.seed = 5;
    let s = Sensors::start(&p);
    let t = truth([0.0, 500.0, 0.0], [0.0; 3], [1.0, 0.0, 0.0, 0.0]);
    let m = s.measure(&p, &t).unwrap();
    let x = t.specific_force_body_mps2;
    let (sf, mu) = (
        s.accel_calibration.scale_factor,
        s.accel_calibration.misalignment_rad,
    );
    let sensed = [
        x[0] - (mu[1] * x[2] - mu[2] * x[1]),
        x[1] - (mu[2] * x[0] - mu[0] * x[2]),
        x[2] - (mu[0] * x[1] - mu[1] * x[0]),
    ];
    for i in 0..3 {
        let want = (1.0 + sf[i]) * sensed[i] + s.accel_bias_mps2[i];
        assert!(close(m.accel_body_meas_mps2[i], want, 1e-14), "accel {i}");
    }
}

/// The measurements of `n` successive samples of one run.
fn run(p: &SensorParameters, t: &Truth, n: usize, h: f64) -> Vec<fmu_sensors::model::Measurements> {
    let mut s = Sensors::start(p);
    (0..n)
        .map(|_| {
            let m = s.measure(p, t).unwrap();
            s.step(p, h).unwrap();
            m
        })
        .collect()
}

#[test]
fn white_noise_has_the_density_over_the_root_of_the_sample_period() {
    let mut p = perfect();
    p.seed = 3;
    p.accel.noise_density = 5e-4;
    p.gyro.noise_density = 1.5e-5;
    p.altimeter.noise_sigma = 0.1;
    p.altimeter.noise_proportional = 1e-3;
    p.velocimeter.noise_sigma = 0.02;
    let t = truth([0.0, 800.0, 0.0], [0.0, -10.0, 0.0], [1.0, 0.0, 0.0, 0.0]);
    let n = 20_000;
    let runs = run(&p, &t, n, 0.01);
    let sigma_a = 5e-4 / 0.01f64.sqrt();
    let sigma_g = 1.5e-5 / 0.01f64.sqrt();
    for i in 0..3 {
        let a: Vec<f64> = runs.iter().map(|m| m.accel_body_meas_mps2[i]).collect();
        assert_normal(&a, t.specific_force_body_mps2[i], sigma_a, "accel");
        let g: Vec<f64> = runs.iter().map(|m| m.gyro_body_meas_radps[i]).collect();
        assert_normal(&g, t.omega_body_radps[i], sigma_g, "gyro");
        let v: Vec<f64> = runs
            .iter()
            .map(|m| m.velocimeter_los_velocity_mps[i])
            .collect();
        let los = dot(t.v_nue_mps, p.velocimeter_beams_body()[i]);
        assert_normal(&v, los, 0.02, "velocimeter");
    }
    let r: Vec<f64> = runs.iter().map(|m| m.altimeter_range_m).collect();
    assert_normal(&r, 800.0, (0.1f64 * 0.1 + 0.8 * 0.8).sqrt(), "altimeter");
}

#[test]
fn the_bias_random_walk_spreads_as_the_root_of_time() {
    let mut p = perfect();
    p.accel.bias_random_walk = 1e-3;
    p.gyro.bias_random_walk = 2e-5;
    let (steps, h) = (100, 0.01);
    let mut accel = Vec::new();
    let mut gyro = Vec::new();
    for seed in 0..1000 {
        p.seed = seed;
        let mut s = Sensors::start(&p);
        for _ in 0..steps {
            s.step(&p, h).unwrap();
        }
        accel.extend(s.accel_bias_mps2);
        gyro.extend(s.gyro_bias_radps);
    }
    let t = (steps as f64 * h).sqrt();
    assert_normal(&accel, 0.0, 1e-3 * t, "accel walk");
    assert_normal(&gyro, 0.0, 2e-5 * t, "gyro walk");
}

#[test]
fn samples_drop_out_at_the_set_rate() {
    let mut p = perfect();
    p.altimeter.dropout_probability = 0.2;
    p.velocimeter.dropout_probability = 0.05;
    let t = truth([0.0, 600.0, 0.0], [0.0; 3], [1.0, 0.0, 0.0, 0.0]);
    let n = 20_000usize;
    let runs = run(&p, &t, n, 0.01);
    let check = |lost: usize, prob: f64, what: &str| {
        let nf = n as f64;
        let band = 4.0 * (nf * prob * (1.0 - prob)).sqrt();
        assert!(
            (lost as f64 - nf * prob).abs() < band,
            "{what}: {lost} of {n} lost"
        );
    };
    let lost = runs.iter().filter(|m| !m.altimeter_valid).count();
    check(lost, 0.2, "altimeter");
    assert!(runs
        .iter()
        .filter(|m| !m.altimeter_valid)
        .all(|m| m.altimeter_range_m == 0.0));
    for i in 0..3 {
        let lost = runs.iter().filter(|m| !m.velocimeter_valid[i]).count();
        check(lost, 0.05, "velocimeter");
    }
}

#[test]
fn beyond_the_maximum_range_a_beam_is_invalid() {
    let p = perfect();
    let s = Sensors::start(&p);
    let at = |up: f64| {
        s.measure(&p, &truth([0.0, up, 0.0], [0.0; 3], [1.0, 0.0, 0.0, 0.0]))
            .unwrap()
    };
    // The altimeter reaches 2000 m straight down; the beams 1000 m along a 20 deg cant,
    // 939.7 m of height.
    assert!(at(1999.0).altimeter_valid && !at(2001.0).altimeter_valid);
    let cos20 = 20f64.to_radians().cos();
    assert!(at(999.0 * cos20).velocimeter_valid.iter().all(|v| *v));
    assert!(at(1001.0 * cos20).velocimeter_valid.iter().all(|v| !*v));
    assert_eq!(at(2001.0).altimeter_range_m, 0.0);
}

#[test]
fn a_beam_at_or_above_the_horizon_or_a_lander_below_the_terrain_is_invalid() {
    let p = perfect();
    let s = Sensors::start(&p);
    // Upside down: every beam points up.
    let inverted = about([0.0, 0.0, 1.0], std::f64::consts::PI);
    let m = s
        .measure(&p, &truth([0.0, 100.0, 0.0], [0.0; 3], inverted))
        .unwrap();
    assert!(!m.altimeter_valid && m.velocimeter_valid.iter().all(|v| !*v));
    // Pitched 100 deg about body z: the altimeter points above the horizon; of the canted
    // beams, beam 1 (azimuth 0, towards +x) tilts further up, the others too.
    let pitched = about([0.0, 0.0, 1.0], 100f64.to_radians());
    let m = s
        .measure(&p, &truth([0.0, 100.0, 0.0], [0.0; 3], pitched))
        .unwrap();
    assert!(!m.altimeter_valid);
    for (i, b) in p.velocimeter_beams_body().iter().enumerate() {
        let d = rotate(pitched, *b);
        assert_eq!(
            m.velocimeter_valid[i],
            d[1] < 0.0 && 100.0 / -d[1] <= 1000.0,
            "{i}"
        );
    }
    // Below the terrain.
    let m = s
        .measure(&p, &truth([0.0, -1.0, 0.0], [0.0; 3], [1.0, 0.0, 0.0, 0.0]))
        .unwrap();
    assert!(!m.altimeter_valid && m.velocimeter_valid.iter().all(|v| !*v));
}

#[test]
fn a_non_unit_quaternion_or_a_non_finite_input_is_refused_by_name() {
    let mut t = truth([0.0, 100.0, 0.0], [0.0; 3], [1.0, 0.0, 0.0, 1e-2]);
    let e = t.validate().unwrap_err();
    assert_eq!(e.field, "truth.q_body_to_nue");
    t.q_body_to_nue = [1.0, 0.0, 0.0, 0.0];
    t.v_nue_mps[2] = f64::NAN;
    let e = t.validate().unwrap_err();
    assert_eq!((e.field, e.index), ("truth.v_nue_mps", Some(2)));
}
