//! Filter consistency against a simulated truth, over 50 seeds (a Monte Carlo NEES / NIS
//! test). The truth is a constant-acceleration descent from 800 m to 150 m in 130 s (with a
//! drift North that ends at rest over the site), at a constant 3 degree tilt; its specific
//! force is analytic. LanderSensors' model (defaults: every error the filter models, none it
//! does not) measures it; the filter starts from an error drawn from its own initial
//! covariance. At every whole second the 50 runs' average NEES (all 15 error states, and the
//! 6 of position and velocity) and average NIS (altimeter: 1 degree of freedom, velocimeter:
//! 3) are compared with the two-sided 95 % band of the average of 50 chi-square values,
//! `chi2(50 dof; 0.025, 0.975) / 50`, the quantiles by Wilson and Hilferty's approximation.
//! At least 90 % of the 130 checks must lie inside (95 % expected of a consistent filter),
//! and the mean over time of each average within 10 % of its degrees of freedom.
//!
//! The step is 0.1 s (the sensors' imu_sample_period alike) to keep a debug run short.
// std's transcendental functions here make the truth and the statistics, outside the model.
#![allow(clippy::disallowed_methods)]
use fmu_filter::fmu::{step, Measurements};
use fmu_filter::model::rotation::{exp, mul};
use fmu_filter::model::{Eskf, FilterParameters, Imu};
use fmu_sensors::model::{SensorParameters, Sensors, Truth};
use nalgebra::{SMatrix, SVector, Vector3};
use rand::SeedableRng;
use rand_chacha::ChaCha12Rng;
use rand_distr::{Distribution, StandardNormal};

const RUNS: usize = 50;
const H: f64 = 0.1;
const DURATION_S: f64 = 130.0;
const TILT_RAD: f64 = 3.0 * std::f64::consts::PI / 180.0;

/// The truth at `t`: r = r0 + v0 t + a t^2 / 2.
struct Descent {
    r0: Vector3<f64>,
    v0: Vector3<f64>,
    a: Vector3<f64>,
    q: [f64; 4],
}

impl Descent {
    fn new() -> Descent {
        Descent {
            r0: Vector3::new(-325.0, 800.0, 0.0),
            v0: Vector3::new(5.0, -10.0, 0.0),
            a: Vector3::new(-5.0 / 130.0, 10.0 / 130.0, 0.0),
            q: exp(&Vector3::new(0.0, 0.0, TILT_RAD)),
        }
    }

    fn truth(&self, t: f64) -> Truth {
        let r = self.r0 + self.v0 * t + self.a * (0.5 * t * t);
        let v = self.v0 + self.a * t;
        // Specific force: the acceleration less gravity (0, -1.62, 0), in body axes.
        let f_nue = self.a + Vector3::new(0.0, 1.62, 0.0);
        let rot = fmu_filter::model::rotation::matrix(&self.q);
        let f_body = rot.transpose() * f_nue;
        Truth {
            r_nue_m: r.into(),
            v_nue_mps: v.into(),
            q_body_to_nue: self.q,
            omega_body_radps: [0.0; 3],
            specific_force_body_mps2: f_body.into(),
        }
    }
}

/// Wilson-Hilferty: the `z`-quantile of chi-square with `k` degrees of freedom.
fn chi2_quantile(k: f64, z: f64) -> f64 {
    let c = 2.0 / (9.0 * k);
    k * (1.0 - c + z * c.sqrt()).powi(3)
}

/// The 95 % band of the average of `RUNS` chi-square values of `dof` degrees of freedom.
fn band(dof: f64) -> (f64, f64) {
    let n = RUNS as f64 * dof;
    let z = 1.959_963_985;
    (
        chi2_quantile(n, -z) / RUNS as f64,
        chi2_quantile(n, z) / RUNS as f64,
    )
}

/// One second's statistics of one run.
#[derive(Clone, Copy, Default)]
struct Sample {
    /// NEES of each 3-state block (position, velocity, attitude, biases), for diagnosis.
    blocks: [f64; 5],
    nees15: f64,
    nees6: f64,
    nis_altimeter: f64,
    nis_velocimeter: f64,
}

/// A run's samples, and the NEES of the errors a run keeps for long: its initial horizontal
/// position error (North, East: never observed over a flat terrain) and the sensors'
/// constant biases (accelerometer, gyro), each against its initial 1-sigma.
fn fly(seed: u64) -> (Vec<Sample>, [f64; 3]) {
    let descent = Descent::new();
    let sensor_params = SensorParameters {
        seed: seed as i32,
        sample_period_s: H,
        ..SensorParameters::default()
    };
    let mut filter_params = FilterParameters {
        sample_period_s: H,
        ..FilterParameters::default()
    };
    // The initial estimate: the truth plus an error drawn from the initial covariance.
    let mut rng = ChaCha12Rng::seed_from_u64(1000 + seed);
    let mut normal = || -> f64 { StandardNormal.sample(&mut rng) };
    let t0 = descent.truth(0.0);
    for i in 0..3 {
        filter_params.r0_nue_m[i] = t0.r_nue_m[i] + filter_params.r0_sigma_m * normal();
        filter_params.v0_nue_mps[i] = t0.v_nue_mps[i] + filter_params.v0_sigma_mps * normal();
    }
    let s = filter_params.attitude0_sigma_rad;
    let dtheta = Vector3::new(s * normal(), s * normal(), s * normal());
    // q_true = q_est exp(dtheta): q_est = q_true exp(-dtheta).
    filter_params.q0_body_to_nue = mul(&descent.q, &exp(&-dtheta));
    let horizontal = [0, 2]
        .iter()
        .map(|&i| ((filter_params.r0_nue_m[i] - t0.r_nue_m[i]) / filter_params.r0_sigma_m).powi(2))
        .sum::<f64>();

    let mut sensors = Sensors::start(&sensor_params);
    let squared = |b: &[f64; 3], sigma: f64| b.iter().map(|x| (x / sigma).powi(2)).sum::<f64>();
    let persistent = [
        horizontal,
        squared(&sensors.accel_bias_mps2, filter_params.accel.bias_sigma),
        squared(&sensors.gyro_bias_radps, filter_params.gyro.bias_sigma),
    ];
    let mut eskf = Eskf::start(&filter_params);
    let steps = (DURATION_S / H).round() as usize;
    let per_second = (1.0 / H).round() as usize;
    let mut out = Vec::new();
    for k in 0..steps {
        let truth = descent.truth(k as f64 * H);
        let m = sensors.measure(&sensor_params, &truth).expect("finite");
        let meas = Measurements {
            imu: Imu {
                accel_body_mps2: m.accel_body_meas_mps2,
                gyro_body_radps: m.gyro_body_meas_radps,
            },
            altimeter_range_m: m.altimeter_range_m,
            altimeter_valid: m.altimeter_valid,
            velocimeter_los_velocity_mps: m.velocimeter_los_velocity_mps,
            velocimeter_valid: m.velocimeter_valid,
        };
        let checkpoint = k > 0 && k % per_second == 0;
        let nees = checkpoint.then(|| nees(&eskf, &truth, &sensors));
        let blocks = checkpoint.then(|| block_nees(&eskf, &truth, &sensors));
        let innovations = step(&mut eskf, &filter_params, &meas, H);
        if let Some((nees15, nees6)) = nees {
            assert_eq!(innovations.altimeter_dof, 1);
            assert_eq!(innovations.velocimeter_dof, 3);
            out.push(Sample {
                blocks: blocks.unwrap(),
                nees15,
                nees6,
                nis_altimeter: innovations.nis_altimeter,
                nis_velocimeter: innovations.nis_velocimeter,
            });
        }
        sensors.step(&sensor_params, H).unwrap();
    }
    (out, persistent)
}

/// The NEES of each 3-state block on its own.
fn block_nees(eskf: &Eskf, truth: &Truth, sensors: &Sensors) -> [f64; 5] {
    let dx = error(eskf, truth, sensors);
    let p = SMatrix::<f64, 15, 15>::from_fn(|i, j| eskf.p[i][j]);
    std::array::from_fn(|b| {
        let pb = p.fixed_view::<3, 3>(3 * b, 3 * b).into_owned();
        let db = dx.fixed_rows::<3>(3 * b).into_owned();
        db.dot(&pb.cholesky().expect("positive definite").solve(&db))
    })
}

/// The true error state `x_true - x_est`.
fn error(eskf: &Eskf, truth: &Truth, sensors: &Sensors) -> SVector<f64, 15> {
    let q = eskf.q_body_to_nue;
    let conj = [q[0], -q[1], -q[2], -q[3]];
    let dq = mul(&conj, &truth.q_body_to_nue);
    let sign = if dq[0] < 0.0 { -1.0 } else { 1.0 };
    let mut dx = SVector::<f64, 15>::zeros();
    for i in 0..3 {
        dx[i] = truth.r_nue_m[i] - eskf.r_nue_m[i];
        dx[3 + i] = truth.v_nue_mps[i] - eskf.v_nue_mps[i];
        // Small angles: dtheta = 2 vec(q_est* q_true).
        dx[6 + i] = 2.0 * sign * dq[1 + i];
        dx[9 + i] = sensors.accel_bias_mps2[i] - eskf.accel_bias_mps2[i];
        dx[12 + i] = sensors.gyro_bias_radps[i] - eskf.gyro_bias_radps[i];
    }
    dx
}

/// The NEES of the estimate against the truth: all 15 error states, and position and
/// velocity alone.
fn nees(eskf: &Eskf, truth: &Truth, sensors: &Sensors) -> (f64, f64) {
    let dx = error(eskf, truth, sensors);
    let p = SMatrix::<f64, 15, 15>::from_fn(|i, j| eskf.p[i][j]);
    let full = dx.dot(&p.cholesky().expect("positive definite").solve(&dx));
    let p6 = p.fixed_view::<6, 6>(0, 0).into_owned();
    let dx6 = dx.fixed_rows::<6>(0).into_owned();
    let six = dx6.dot(&p6.cholesky().expect("positive definite").solve(&dx6));
    (full, six)
}

#[test]
fn average_nees_and_nis_over_50_runs_lie_in_their_95_percent_bands() {
    let start = std::time::Instant::now();
    // Two threads: the runs are independent.
    let flown: Vec<(Vec<Sample>, [f64; 3])> = std::thread::scope(|scope| {
        let halves: Vec<_> = (0..2)
            .map(|half| {
                scope.spawn(move || {
                    (half..RUNS)
                        .step_by(2)
                        .map(|s| fly(s as u64))
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        halves.into_iter().flat_map(|h| h.join().unwrap()).collect()
    });
    let persistent: [f64; 3] =
        std::array::from_fn(|i| flown.iter().map(|(_, p)| p[i]).sum::<f64>() / RUNS as f64);
    let runs: Vec<Vec<Sample>> = flown.into_iter().map(|(r, _)| r).collect();
    let checks = runs[0].len();
    let average = |f: fn(&Sample) -> f64| -> Vec<f64> {
        (0..checks)
            .map(|c| runs.iter().map(|r| f(&r[c])).sum::<f64>() / RUNS as f64)
            .collect()
    };
    let mut report = String::new();
    for (b, name) in [
        "position",
        "velocity",
        "attitude",
        "accel bias",
        "gyro bias",
    ]
    .iter()
    .enumerate()
    {
        let mean = runs.iter().flatten().map(|s| s.blocks[b]).sum::<f64>() / (RUNS * checks) as f64;
        report += &format!("NEES of the {name} alone: mean {mean:.3} (dof 3)\n");
    }
    let mut failures = Vec::new();
    for (name, dof, values) in [
        ("NEES (15 states)", 15.0, average(|s| s.nees15)),
        ("NEES (position, velocity)", 6.0, average(|s| s.nees6)),
        ("NIS altimeter", 1.0, average(|s| s.nis_altimeter)),
        ("NIS velocimeter", 3.0, average(|s| s.nis_velocimeter)),
    ] {
        let (lo, hi) = band(dof);
        let inside = values.iter().filter(|v| (lo..=hi).contains(*v)).count();
        let mean = values.iter().sum::<f64>() / checks as f64;
        if std::env::var_os("CONSISTENCY_PROFILE").is_some() {
            let every: Vec<String> = values
                .iter()
                .step_by(5)
                .map(|v| format!("{v:.2}"))
                .collect();
            println!("{name} every 5 s: {}", every.join(" "));
        }
        let fraction = inside as f64 / checks as f64;
        report += &format!(
            "{name}: band [{lo:.3}, {hi:.3}], {inside} of {checks} inside ({:.0} %), mean over time {mean:.3} (dof {dof})\n",
            100.0 * fraction
        );
        if fraction < 0.9 || (mean - dof).abs() > 0.1 * dof {
            failures.push(name);
        }
    }
    let sd = |dof: f64| (2.0 * dof / RUNS as f64).sqrt();
    report += &format!(
        "errors drawn once per run, average NEES over the runs: initial horizontal position \
         {:.3} (2 expected, 1-sigma {:.3}), accelerometer bias {:.3} and gyro bias {:.3} (3 \
         expected, 1-sigma {:.3})\n",
        persistent[0],
        sd(2.0),
        persistent[1],
        persistent[2],
        sd(3.0)
    );
    println!(
        "{report}{RUNS} runs of {DURATION_S} s in {:.1} s",
        start.elapsed().as_secs_f64()
    );
    assert!(failures.is_empty(), "inconsistent: {failures:?}\n{report}");
}
