//! Filter consistency against a simulated truth, over 50 seeds (a Monte Carlo NEES / NIS
//! test). The truth is a constant-acceleration descent from 800 m to 150 m in 130 s (with a
//! drift North that ends at rest over the site), at a constant 3 degree tilt; its specific
//! force is analytic. LanderSensors' model (defaults: every error the filter models, none it
//! does not) measures it; the filter starts from an error drawn from its own initial
//! covariance. At every check the 50 runs' average NEES (all the error states the filter
//! carries, all but the horizontal position, the 4 of Up position and velocity, and each
//! block: Up position, velocity, attitude, accelerometer bias, gyro bias) and average NIS
//! (altimeter: 1 degree of freedom, velocimeter: 3) are compared with the two-sided 95 % band
//! of the average of 50 chi-square values, `chi2(50 dof; 0.025, 0.975) / 50`, the quantiles
//! by Wilson and Hilferty's approximation. A given fraction of the checks must lie inside
//! (95 % expected of a consistent filter), and the mean over time of each average within
//! 10 % of its degrees of freedom (of a block, inside the band). An error that no
//! measurement reduces keeps its initial draw all run: its NEES is one draw per run, not one
//! per check, so a count of it would rise or fall with that draw alone. The horizontal
//! position (never observed over a flat terrain) is therefore left out of the checks and
//! reported once, and the calibration errors, which the measurements reduce only slowly, are
//! checked once, at the end of the runs, against the band of their 12 degrees of freedom and
//! each block's 3.
//!
//! A second case draws the IMU's scale factors and misalignments too and lets the filter
//! estimate them (all 27 error states), on a lander that also turns at 10 deg/s about its
//! specific force: the gyro's calibration errors act only while the body turns.
//!
//! Each case flies at the step of 0.1 s over the 130 s (129 checks, one a second, 90 % of them
//! inside), and at the master's step of 0.01 s over the first 20 s (99 checks, one every
//! 0.2 s, 85 % inside); the sensors' imu_sample_period is the step.
// std's transcendental functions here make the truth and the statistics, outside the model.
#![allow(clippy::disallowed_methods)]
use fmu_filter::fmu::{step, Measurements};
use fmu_filter::model::rotation::{exp, mul};
use fmu_filter::model::{Eskf, FilterParameters, Imu};
use fmu_sensors::model::{SensorParameters, Sensors, Truth};
use nalgebra::{DMatrix, DVector, Vector3};
use rand::SeedableRng;
use rand_chacha::ChaCha12Rng;
use rand_distr::{Distribution, StandardNormal};

const RUNS: usize = 50;
const DURATION_S: f64 = 130.0;
/// The runs at 0.01 s fly the first 20 s of the descent, checked every 0.2 s: ten
/// times the steps per second cost ten times the time, and an over-confidence that grows with
/// the update rate shows in the first seconds, while the initial errors converge.
const FLOWN_STEP_DURATION_S: f64 = 20.0;
/// At 0.01 s, 85 % of the 99 checks inside: checks 0.2 s apart on errors that persist for
/// seconds are far from independent, and the count inside spreads about as that of some 20
/// independent checks would, of which a consistent filter has 85 % or fewer inside with a
/// probability of 7.5 % (binomial, 95 % each). The filter that counts its linearisation
/// error once per update has 33 % to 72 % of the combined statistics' checks inside.
const FLOWN_STEP_INSIDE: f64 = 0.85;
const TILT_RAD: f64 = 3.0 * std::f64::consts::PI / 180.0;

/// The IMU calibration errors of the second case, 1-sigma per axis: scale factor
/// (1000 ppm) and misalignment (1 mrad), large enough that a filter that ignored them
/// would be visibly inconsistent within the 130 s.
const SCALE_FACTOR_SIGMA: f64 = 1e-3;
const MISALIGNMENT_SIGMA_RAD: f64 = 1e-3;

/// The truth at `t`: r = r0 + v0 t + a t^2 / 2, the attitude `q0 exp(w t)`.
struct Descent {
    r0: Vector3<f64>,
    v0: Vector3<f64>,
    a: Vector3<f64>,
    q0: [f64; 4],
    /// Constant body rate about the specific force (body axes), so that the specific
    /// force, constant in NUE, is constant in body axes too.
    omega_body: Vector3<f64>,
}

impl Descent {
    fn new(rate_radps: f64) -> Descent {
        let a = Vector3::new(-5.0 / 130.0, 10.0 / 130.0, 0.0);
        let q0 = exp(&Vector3::new(0.0, 0.0, TILT_RAD));
        let f_body = fmu_filter::model::rotation::matrix(&q0).transpose() * Self::f_nue(&a);
        Descent {
            r0: Vector3::new(-325.0, 800.0, 0.0),
            v0: Vector3::new(5.0, -10.0, 0.0),
            a,
            q0,
            omega_body: f_body.normalize() * rate_radps,
        }
    }

    /// Specific force: the acceleration less gravity (0, -1.62, 0).
    fn f_nue(a: &Vector3<f64>) -> Vector3<f64> {
        a + Vector3::new(0.0, 1.62, 0.0)
    }

    fn truth(&self, t: f64) -> Truth {
        let r = self.r0 + self.v0 * t + self.a * (0.5 * t * t);
        let v = self.v0 + self.a * t;
        let q = mul(&self.q0, &exp(&(self.omega_body * t)));
        let rot = fmu_filter::model::rotation::matrix(&q);
        let f_body = rot.transpose() * Self::f_nue(&self.a);
        Truth {
            r_nue_m: r.into(),
            v_nue_mps: v.into(),
            q_body_to_nue: q,
            omega_body_radps: self.omega_body.into(),
            specific_force_body_mps2: f_body.into(),
        }
    }
}

/// What a run draws and estimates, and how the filter flies it.
#[derive(Clone, Copy)]
struct Case {
    /// Scale factors and misalignments drawn by the sensors and estimated by the filter.
    calibration: bool,
    rate_radps: f64,
    /// The communication step and the IMU's sample period, s.
    step_s: f64,
    /// How long each run flies, s (at most `DURATION_S`, the descent's length).
    duration_s: f64,
    /// The time between checks, s.
    check_every_s: f64,
    /// The fraction of the checks that must lie inside the band.
    inside: f64,
}

impl Case {
    /// The error states the filter carries with uncertainty: 15, or 27 with calibration.
    fn states(&self) -> usize {
        if self.calibration {
            27
        } else {
            15
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
    /// NEES of each block of [`BLOCKS`].
    blocks: [f64; 5],
    /// NEES of each block of [`CALIBRATION_BLOCKS`] (NaN without calibration).
    calibration_blocks: [f64; 4],
    nees_all: f64,
    /// All the navigation states and biases but the horizontal position (13 of them).
    nees_navigation: f64,
    nees4: f64,
    /// The 12 calibration states (NaN without calibration).
    nees_calibration: f64,
    nis_altimeter: f64,
    nis_velocimeter: f64,
}

/// A run's samples, and the NEES of the errors a run keeps for long: its initial horizontal
/// position error (North, East: never observed over a flat terrain) and the sensors'
/// constant biases (accelerometer, gyro), each against its initial 1-sigma.
fn fly(seed: u64, case: Case) -> (Vec<Sample>, [f64; 3]) {
    let descent = Descent::new(case.rate_radps);
    let mut sensor_params = SensorParameters {
        seed: seed as i32,
        sample_period_s: case.step_s,
        ..SensorParameters::default()
    };
    let mut filter_params = FilterParameters {
        sample_period_s: case.step_s,
        ..FilterParameters::default()
    };
    if case.calibration {
        for imu in [&mut sensor_params.accel, &mut sensor_params.gyro] {
            imu.scale_factor_sigma = SCALE_FACTOR_SIGMA;
            imu.misalignment_sigma = MISALIGNMENT_SIGMA_RAD;
        }
        for imu in [&mut filter_params.accel, &mut filter_params.gyro] {
            imu.scale_factor_sigma = SCALE_FACTOR_SIGMA;
            imu.misalignment_sigma = MISALIGNMENT_SIGMA_RAD;
        }
    }
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
    filter_params.q0_body_to_nue = mul(&descent.q0, &exp(&-dtheta));
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
    let h = case.step_s;
    let steps = (case.duration_s / h).round() as usize;
    let per_second = (case.check_every_s / h).round() as usize;
    let mut out = Vec::new();
    for k in 0..steps {
        let truth = descent.truth(k as f64 * h);
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
        let n = case.states();
        let nees = checkpoint.then(|| nees(&eskf, &truth, &sensors, n));
        let blocks = checkpoint.then(|| block_nees(&eskf, &truth, &sensors, n));
        let innovations = step(&mut eskf, &filter_params, &meas, h);
        if let Some([nees_all, nees_navigation, nees4, nees_calibration]) = nees {
            assert_eq!(innovations.altimeter_dof, 1);
            assert_eq!(innovations.velocimeter_dof, 3);
            let (blocks, calibration_blocks) = blocks.unwrap();
            out.push(Sample {
                blocks,
                calibration_blocks,
                nees_all,
                nees_navigation,
                nees4,
                nees_calibration,
                nis_altimeter: innovations.nis_altimeter,
                nis_velocimeter: innovations.nis_velocimeter,
            });
        }
        sensors.step(&sensor_params, h).unwrap();
    }
    (out, persistent)
}

/// `dx^T P^-1 dx` over the error states `states`.
fn quadratic(eskf: &Eskf, dx: &DVector<f64>, states: &[usize]) -> f64 {
    let n = states.len();
    let p = DMatrix::from_fn(n, n, |i, j| eskf.p[states[i]][states[j]]);
    let d = DVector::from_fn(n, |i, _| dx[states[i]]);
    d.dot(&p.cholesky().expect("positive definite").solve(&d))
}

/// Up position and velocity: the observed part of position and velocity. The horizontal
/// position, which nothing measures over a flat terrain, keeps its initial draw for the
/// whole run: its NEES is one draw per run, not one per second, and it is checked once
/// (`persistent`).
const OBSERVED_POSITION_VELOCITY: [usize; 4] = [1, 3, 4, 5];

/// The NEES of each block of [`BLOCKS`] and [`CALIBRATION_BLOCKS`] on its own (NaN for
/// the calibration blocks beyond the first `n` states).
fn block_nees(eskf: &Eskf, truth: &Truth, sensors: &Sensors, n: usize) -> ([f64; 5], [f64; 4]) {
    let dx = error(eskf, truth, sensors);
    (
        BLOCKS.map(|(_, states)| quadratic(eskf, &dx, states)),
        CALIBRATION_BLOCKS.map(|(_, states)| {
            if states[0] < n {
                quadratic(eskf, &dx, states)
            } else {
                f64::NAN
            }
        }),
    )
}

/// The true error state `x_true - x_est`, all 27 states in the filter's order.
fn error(eskf: &Eskf, truth: &Truth, sensors: &Sensors) -> DVector<f64> {
    let q = eskf.q_body_to_nue;
    let conj = [q[0], -q[1], -q[2], -q[3]];
    let dq = mul(&conj, &truth.q_body_to_nue);
    let sign = if dq[0] < 0.0 { -1.0 } else { 1.0 };
    let (sa, se) = (&sensors.accel_calibration, &eskf.accel_calibration);
    let (sg, eg) = (&sensors.gyro_calibration, &eskf.gyro_calibration);
    let mut dx = DVector::zeros(27);
    for i in 0..3 {
        dx[i] = truth.r_nue_m[i] - eskf.r_nue_m[i];
        dx[3 + i] = truth.v_nue_mps[i] - eskf.v_nue_mps[i];
        // Small angles: dtheta = 2 vec(q_est* q_true).
        dx[6 + i] = 2.0 * sign * dq[1 + i];
        dx[9 + i] = sensors.accel_bias_mps2[i] - eskf.accel_bias_mps2[i];
        dx[12 + i] = sensors.gyro_bias_radps[i] - eskf.gyro_bias_radps[i];
        dx[15 + i] = sa.scale_factor[i] - se.scale_factor[i];
        dx[18 + i] = sg.scale_factor[i] - eg.scale_factor[i];
        dx[21 + i] = sa.misalignment_rad[i] - se.misalignment_rad[i];
        dx[24 + i] = sg.misalignment_rad[i] - eg.misalignment_rad[i];
    }
    dx
}

/// The NEES of the estimate against the truth: the first `n` error states; the navigation
/// states less the horizontal position; Up position and velocity; the calibration states
/// (NaN where `n` holds none).
fn nees(eskf: &Eskf, truth: &Truth, sensors: &Sensors, n: usize) -> [f64; 4] {
    let dx = error(eskf, truth, sensors);
    let all: Vec<usize> = (0..n).collect();
    let navigation: Vec<usize> = [1].into_iter().chain(3..15).collect();
    let calibration: Vec<usize> = (15..n).collect();
    [
        quadratic(eskf, &dx, &all),
        quadratic(eskf, &dx, &navigation),
        quadratic(eskf, &dx, &OBSERVED_POSITION_VELOCITY),
        if calibration.is_empty() {
            f64::NAN
        } else {
            quadratic(eskf, &dx, &calibration)
        },
    ]
}

#[test]
fn average_nees_and_nis_over_50_runs_lie_in_their_95_percent_bands() {
    check(Case {
        calibration: false,
        rate_radps: 0.0,
        step_s: 0.1,
        duration_s: DURATION_S,
        check_every_s: 1.0,
        inside: 0.9,
    });
}

#[test]
fn with_scale_factors_and_misalignments_drawn_and_estimated_on_a_turning_lander_the_27_state_nees_and_nis_lie_in_their_bands(
) {
    check(Case {
        calibration: true,
        rate_radps: 10f64.to_radians(),
        step_s: 0.1,
        duration_s: DURATION_S,
        check_every_s: 1.0,
        inside: 0.9,
    });
}

/// At the master's step of 0.01 s, ten updates a second more: over the first 30 s, where a
/// linearisation error counted once per update made the velocity and attitude NEES a third
/// too high and left the excess in the accelerometer bias.
#[test]
fn at_the_flown_step_of_0_01_s_every_block_s_average_nees_lies_in_its_band() {
    check(Case {
        calibration: false,
        rate_radps: 0.0,
        step_s: 0.01,
        duration_s: FLOWN_STEP_DURATION_S,
        check_every_s: 0.2,
        inside: FLOWN_STEP_INSIDE,
    });
}

#[test]
fn at_the_flown_step_of_0_01_s_on_a_turning_lander_with_calibration_every_block_s_average_nees_lies_in_its_band(
) {
    check(Case {
        calibration: true,
        rate_radps: 10f64.to_radians(),
        step_s: 0.01,
        duration_s: FLOWN_STEP_DURATION_S,
        check_every_s: 0.2,
        inside: FLOWN_STEP_INSIDE,
    });
}

/// The navigation blocks checked at every whole second: name, error states (with the
/// horizontal position, never observed over the flat terrain, left out).
const BLOCKS: [(&str, &[usize]); 5] = [
    ("Up position", &[1]),
    ("velocity", &[3, 4, 5]),
    ("attitude", &[6, 7, 8]),
    ("accelerometer bias", &[9, 10, 11]),
    ("gyro bias", &[12, 13, 14]),
];

/// The calibration blocks, checked at the end of the runs.
const CALIBRATION_BLOCKS: [(&str, &[usize]); 4] = [
    ("accelerometer scale factor", &[15, 16, 17]),
    ("gyro scale factor", &[18, 19, 20]),
    ("accelerometer misalignment", &[21, 22, 23]),
    ("gyro misalignment", &[24, 25, 26]),
];

/// Flies the case's 50 runs and asserts the average NEES (all the states the case
/// estimates, the navigation states but the horizontal position, Up position-velocity, and
/// each block of [`BLOCKS`]) and NIS in their bands, and the calibration's (all 12 and each
/// block) at the end.
fn check(case: Case) {
    let start = std::time::Instant::now();
    // Two threads: the runs are independent.
    let flown: Vec<(Vec<Sample>, [f64; 3])> = std::thread::scope(|scope| {
        let halves: Vec<_> = (0..2)
            .map(|half| {
                scope.spawn(move || {
                    (half..RUNS)
                        .step_by(2)
                        .map(|s| fly(s as u64, case))
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
    let average = |f: &dyn Fn(&Sample) -> f64| -> Vec<f64> {
        (0..checks)
            .map(|c| runs.iter().map(|r| f(&r[c])).sum::<f64>() / RUNS as f64)
            .collect()
    };
    let mut report = format!("step {} s, {} s per run\n", case.step_s, case.duration_s);
    let mut failures = Vec::new();
    // (name, degrees of freedom, the averages at each check, whether 90 % of them must lie
    // inside, whether their mean over time must lie within 10 % of the degrees of freedom (else
    // inside the band: of a block's few degrees of freedom the 50 runs' average has a
    // 1-sigma of 12 % (3) to 20 % (1), which the checks' strong correlation in time does not
    // shrink much))
    let mut statistics: Vec<(String, f64, Vec<f64>, bool, bool)> = vec![
        (
            "NEES (all states)".into(),
            case.states() as f64,
            average(&|s| s.nees_all),
            false,
            true,
        ),
        (
            "NEES (all but the horizontal position)".into(),
            case.states().min(15) as f64 - 2.0,
            average(&|s| s.nees_navigation),
            true,
            true,
        ),
        (
            "NEES (Up position, velocity)".into(),
            4.0,
            average(&|s| s.nees4),
            true,
            true,
        ),
    ];
    for (b, (name, states)) in BLOCKS.iter().enumerate() {
        statistics.push((
            format!("NEES ({name})"),
            states.len() as f64,
            average(&|s| s.blocks[b]),
            true,
            false,
        ));
    }
    statistics.push((
        "NIS altimeter".into(),
        1.0,
        average(&|s| s.nis_altimeter),
        true,
        true,
    ));
    statistics.push((
        "NIS velocimeter".into(),
        3.0,
        average(&|s| s.nis_velocimeter),
        true,
        true,
    ));
    for (name, dof, values, per_second, tight) in statistics {
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
        let mean_off = if tight {
            (mean - dof).abs() > 0.1 * dof
        } else {
            !(lo..=hi).contains(&mean)
        };
        if (per_second && fraction < case.inside) || mean_off {
            failures.push(name);
        }
    }
    if case.calibration {
        let last = |f: &dyn Fn(&Sample) -> f64| average(f)[checks - 1];
        let mut at_end = vec![(
            "NEES (calibration)".to_string(),
            12.0,
            last(&|s| s.nees_calibration),
        )];
        for (b, (name, _)) in CALIBRATION_BLOCKS.iter().enumerate() {
            at_end.push((
                format!("NEES ({name})"),
                3.0,
                last(&|s| s.calibration_blocks[b]),
            ));
        }
        for (name, dof, end) in at_end {
            let (lo, hi) = band(dof);
            report += &format!(
                "{name} at {} s: {end:.3}, band [{lo:.3}, {hi:.3}] (dof {dof})\n",
                case.duration_s
            );
            if !(lo..=hi).contains(&end) {
                failures.push(format!("{name} at the end"));
            }
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
        "{report}{RUNS} runs in {:.1} s",
        start.elapsed().as_secs_f64()
    );
    assert!(failures.is_empty(), "inconsistent: {failures:?}\n{report}");
}
