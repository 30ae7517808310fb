//! The error models against their parameters, on the pure model (no FMI): mean, standard
//! deviation and autocorrelation of each error type, the random walk's linear variance
//! growth, the quantisation bound, the latency, and the identity when everything is off.
//!
//! Statistical bounds are 4 standard errors of the estimator for the sample size (mean:
//! sigma / sqrt(n); variance: sigma^2 sqrt(2 / n); autocorrelation: 1 / sqrt(n)), with
//! fixed seeds, so each test is deterministic and a wrong model misses by far more.
// std's transcendental functions here make test inputs and references, outside the model.
#![allow(clippy::disallowed_methods)]
use fmu_nav::errors::attitude::body_error;
use fmu_nav::errors::{Group, GroupErrors, NavErrors, NavParameters, Navigation};

const H: f64 = 0.01;

/// A truth that moves every step and is not unit-aligned: a slow tumble, a descent.
fn moving_truth(k: usize) -> Navigation {
    let s = k as f64 * H;
    let half = 0.3 * (0.2 * s).sin() + 0.1;
    let axis = [0.36, 0.48, 0.8];
    Navigation {
        r_nue_m: [3.0 * s.sin(), 800.0 - 2.0 * s, -0.5 * s],
        v_nue_mps: [3.0 * s.cos() * 0.01, -2.0, -0.5],
        q_body_to_nue: [
            half.cos(),
            axis[0] * half.sin(),
            axis[1] * half.sin(),
            axis[2] * half.sin(),
        ],
        omega_body_radps: [0.01 * s.cos(), -0.02, 0.005 * s],
        mass_kg: 900.0 - 0.5 * s,
    }
}

/// Truth and estimate at every communication point of `steps` steps of `h(k)`.
fn fly(
    params: &NavParameters,
    steps: usize,
    h: impl Fn(usize) -> f64,
    truth: impl Fn(usize) -> Navigation,
) -> Vec<(Navigation, Navigation)> {
    let mut errors = NavErrors::start(params);
    let mut out = Vec::with_capacity(steps);
    for k in 0..steps {
        let x = truth(k);
        out.push((x, errors.estimate(params, &x)));
        errors.step(params, &x, h(k)).unwrap();
    }
    out
}

/// The error of `group` on each of its axes: estimate minus truth, or for the attitude the
/// body-axis rotation from truth to estimate.
fn error(group: Group, truth: &Navigation, estimate: &Navigation) -> Vec<f64> {
    let minus = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(a, b)| a - b).collect();
    match group {
        Group::Position => minus(&estimate.r_nue_m, &truth.r_nue_m),
        Group::Velocity => minus(&estimate.v_nue_mps, &truth.v_nue_mps),
        Group::Attitude => body_error(truth.q_body_to_nue, estimate.q_body_to_nue).to_vec(),
        Group::Rate => minus(&estimate.omega_body_radps, &truth.omega_body_radps),
        Group::Mass => vec![estimate.mass_kg - truth.mass_kg],
    }
}

/// One axis of one group's error along a run.
fn series(run: &[(Navigation, Navigation)], group: Group, axis: usize) -> Vec<f64> {
    run.iter().map(|(x, y)| error(group, x, y)[axis]).collect()
}

fn mean(x: &[f64]) -> f64 {
    x.iter().sum::<f64>() / x.len() as f64
}

fn variance(x: &[f64]) -> f64 {
    let m = mean(x);
    x.iter().map(|v| (v - m).powi(2)).sum::<f64>() / (x.len() - 1) as f64
}

fn autocorrelation(x: &[f64], lag: usize) -> f64 {
    let m = mean(x);
    let c0: f64 = x.iter().map(|v| (v - m).powi(2)).sum();
    let c: f64 = x
        .iter()
        .zip(&x[lag..])
        .map(|(a, b)| (a - m) * (b - m))
        .sum();
    c / c0
}

fn group_mut(params: &mut NavParameters, group: Group) -> &mut GroupErrors {
    match group {
        Group::Position => &mut params.r_nue,
        Group::Velocity => &mut params.v_nue,
        Group::Attitude => &mut params.attitude,
        Group::Rate => &mut params.omega_body,
        Group::Mass => &mut params.mass,
    }
}

/// A different size for each group, in its own unit, so that a mix-up shows.
fn sigma_of(group: Group) -> f64 {
    match group {
        Group::Position => 0.5,
        Group::Velocity => 0.05,
        Group::Attitude => 2e-3,
        Group::Rate => 1e-4,
        Group::Mass => 3.0,
    }
}

#[test]
fn with_every_error_off_the_estimate_is_the_truth_bit_for_bit() {
    // GIVEN the defaults with a seed (the seed alone switches nothing on) and inputs with
    // signed zeros, subnormals, huge values and a degenerate quaternion
    let params = NavParameters {
        seed: 12345,
        max_latency_steps: 10,
        ..NavParameters::default()
    };
    let odd = |k: usize| {
        let mut x = moving_truth(k);
        if k % 7 == 3 {
            x.r_nue_m = [-0.0, 5e-324, -1.5e300];
            x.q_body_to_nue = [0.0, -0.0, 0.0, 0.0];
            x.mass_kg = -0.0;
        }
        x
    };
    // WHEN it flies
    let run = fly(&params, 2000, |_| H, odd);
    // THEN every estimate is its truth, bit for bit
    let bits = |n: &Navigation| format!("{n:?}");
    for (k, (x, y)) in run.iter().enumerate() {
        assert_eq!(bits(y), bits(x), "step {k}");
    }
}

#[test]
fn white_noise_has_the_declared_sigma_zero_mean_and_no_autocorrelation() {
    // GIVEN white noise only, a different sigma per group
    let mut params = NavParameters {
        seed: 7,
        ..NavParameters::default()
    };
    for g in Group::ALL {
        group_mut(&mut params, g).noise_sigma = sigma_of(g);
    }
    // WHEN 20 000 steps are flown on a moving truth
    let n = 20_000;
    let run = fly(&params, n, |_| H, moving_truth);
    let sqrt_n = (n as f64).sqrt();
    for g in Group::ALL {
        let sigma = sigma_of(g);
        for axis in 0..g.axes() {
            let e = series(&run, g, axis);
            // THEN each axis has mean 0, standard deviation sigma, and no correlation
            // between successive samples
            let (m, v) = (mean(&e), variance(&e));
            println!(
                "{g:?}[{axis}]: mean/sigma {:+.4}, std/sigma {:.4}, lag-1 autocorrelation {:+.4}",
                m / sigma,
                v.sqrt() / sigma,
                autocorrelation(&e, 1)
            );
            assert!(m.abs() < 4.0 * sigma / sqrt_n, "{g:?}[{axis}] mean {m}");
            let relative = (v / sigma.powi(2) - 1.0).abs();
            assert!(
                relative < 4.0 * (2.0 / n as f64).sqrt(),
                "{g:?}[{axis}] variance {v}"
            );
            for lag in [1, 2, 5] {
                let r = autocorrelation(&e, lag);
                assert!(r.abs() < 4.0 / sqrt_n, "{g:?}[{axis}] lag {lag}: {r}");
            }
        }
    }
    // AND the axes are independent of each other
    let (a, b) = (
        series(&run, Group::Position, 0),
        series(&run, Group::Position, 1),
    );
    let cross = a.iter().zip(&b).map(|(a, b)| a * b).sum::<f64>() / n as f64 / 0.25;
    assert!(cross.abs() < 4.0 / sqrt_n, "{cross}");
}

#[test]
fn a_bias_shifts_the_mean_by_exactly_the_bias() {
    // GIVEN a bias per axis, alone and then with white noise
    let bias = |g: Group| -> [f64; 3] {
        let s = sigma_of(g);
        [2.0 * s, -s, 0.5 * s]
    };
    let mut alone = NavParameters::default();
    for g in Group::ALL {
        group_mut(&mut alone, g).bias = bias(g);
    }
    let mut noisy = alone;
    for g in Group::ALL {
        group_mut(&mut noisy, g).noise_sigma = sigma_of(g);
    }
    let n = 10_000;
    let exact = fly(&alone, 500, |_| H, moving_truth);
    let run = fly(&noisy, n, |_| H, moving_truth);
    for g in Group::ALL {
        for axis in 0..g.axes() {
            let b = bias(g)[axis];
            // THEN alone, every error is the bias (to rounding of the truth's magnitude)
            for (k, e) in series(&exact, g, axis).iter().enumerate() {
                assert!(
                    (e - b).abs() <= 1e-9 * b.abs(),
                    "{g:?}[{axis}] step {k}: {e}"
                );
            }
            // AND with noise, the mean is the bias within 4 standard errors
            let m = mean(&series(&run, g, axis));
            let tolerance = 4.0 * sigma_of(g) / (n as f64).sqrt();
            assert!(
                (m - b).abs() < tolerance,
                "{g:?}[{axis}] mean {m}, bias {b}"
            );
        }
    }
}

/// Random walk only, `sigma` after 1 s on every group.
fn walk_params(seed: i32) -> NavParameters {
    let mut params = NavParameters {
        seed,
        ..NavParameters::default()
    };
    for g in Group::ALL {
        group_mut(&mut params, g).random_walk = sigma_of(g);
    }
    params
}

#[test]
fn random_walk_variance_grows_linearly_and_its_autocovariance_is_sigma_squared_min_s_t() {
    // GIVEN 1000 runs (seeds) of 1 s of random walk
    let (runs, steps) = (1000, 101);
    let checkpoints = [10, 25, 50, 100];
    let mut sum_sq = [[0.0; 4]; 5];
    let mut sum = [[0.0; 4]; 5];
    // Sum of the products of the walk at 0.25 s and at 1 s.
    let mut cross = [0.0; 5];
    for seed in 0..runs {
        let run = fly(&walk_params(seed), steps, |_| H, moving_truth);
        for g in Group::ALL {
            for (c, &k) in checkpoints.iter().enumerate() {
                let (x, y) = &run[k];
                let e = error(g, x, y)[0];
                sum[g as usize][c] += e;
                sum_sq[g as usize][c] += e * e;
            }
            let at = |k: usize| error(g, &run[k].0, &run[k].1)[0];
            cross[g as usize] += at(25) * at(100);
        }
    }
    // THEN at t = 0.1, 0.25, 0.5, 1 s the variance across runs is sigma^2 t (within 4
    // standard errors), and the walk starts at 0
    for g in Group::ALL {
        let sigma = sigma_of(g);
        for (c, &k) in checkpoints.iter().enumerate() {
            let t = k as f64 * H;
            let m = sum[g as usize][c] / runs as f64;
            let v = sum_sq[g as usize][c] / runs as f64 - m * m;
            let expected = sigma * sigma * t;
            println!(
                "{g:?} t = {t} s: variance / (sigma^2 t) = {:.4}",
                v / expected
            );
            let tolerance = 4.0 * expected * (2.0 / runs as f64).sqrt();
            assert!(
                (v - expected).abs() < tolerance,
                "{g:?} t = {t}: {v} vs {expected}"
            );
            assert!(
                m.abs() < 4.0 * expected.sqrt() / (runs as f64).sqrt(),
                "{g:?} mean {m}"
            );
        }
    }
    // AND the walk's autocovariance between 0.25 s and 1 s is its variance at 0.25 s
    // (sigma^2 min(s, t)): the walk keeps what it had, it is not re-drawn. The standard
    // error of that sample covariance is sigma^2 sqrt((0.25 * 1 + 0.25^2) / runs).
    for g in Group::ALL {
        let sigma2 = sigma_of(g).powi(2);
        let covariance = cross[g as usize] / runs as f64;
        let tolerance = 4.0 * sigma2 * ((0.25 + 0.0625) / runs as f64).sqrt();
        assert!(
            (covariance - 0.25 * sigma2).abs() < tolerance,
            "{g:?}: {covariance} vs {}",
            0.25 * sigma2
        );
    }
    let first = fly(&walk_params(3), 1, |_| H, moving_truth);
    assert_eq!(error(Group::Position, &first[0].0, &first[0].1)[0], 0.0);
}

#[test]
fn random_walk_increments_are_independent_with_variance_proportional_to_the_step() {
    // GIVEN one long run with steps alternating 0.01 s and 0.04 s
    let n = 40_000;
    let h = |k: usize| if k.is_multiple_of(2) { 0.01 } else { 0.04 };
    let run = fly(&walk_params(11), n + 1, h, moving_truth);
    for g in [Group::Position, Group::Attitude, Group::Mass] {
        let e = series(&run, g, 0);
        let increments: Vec<f64> = e.windows(2).map(|w| w[1] - w[0]).collect();
        // THEN the increment after a step of h has variance sigma^2 h
        let sigma = sigma_of(g);
        for (parity, step) in [(0, 0.01), (1, 0.04)] {
            let d: Vec<f64> = increments.iter().skip(parity).step_by(2).copied().collect();
            let expected = sigma * sigma * step;
            let tolerance = 4.0 * expected * (2.0 / d.len() as f64).sqrt();
            assert!(
                (variance(&d) - expected).abs() < tolerance,
                "{g:?} h = {step}"
            );
        }
        // AND successive increments are uncorrelated (normalised by their sigma)
        let z: Vec<f64> = increments
            .iter()
            .enumerate()
            .map(|(k, d)| d / (sigma * h(k).sqrt()))
            .collect();
        let r = autocorrelation(&z, 1);
        assert!(r.abs() < 4.0 / (z.len() as f64).sqrt(), "{g:?} lag 1: {r}");
    }
}

#[test]
fn quantisation_error_is_at_most_half_a_step_and_spread_evenly() {
    // GIVEN quantisation only, on a truth sweeping many steps of the quantum
    let mut params = NavParameters::default();
    let quantum = |g: Group| sigma_of(g) / 4.0;
    for g in [Group::Position, Group::Velocity, Group::Rate, Group::Mass] {
        group_mut(&mut params, g).quantum = quantum(g);
    }
    let n = 20_000;
    let sweep = |k: usize| {
        let mut x = moving_truth(k);
        let s = k as f64 * 0.001_37;
        x.r_nue_m[0] = 0.5 * s - 3.0;
        x.v_nue_mps[1] = 0.05 * s;
        x.omega_body_radps[2] = 1e-4 * s;
        x.mass_kg = 900.0 - 3.0 * s;
        x
    };
    let run = fly(&params, n, |_| H, sweep);
    for (g, axis) in [
        (Group::Position, 0),
        (Group::Velocity, 1),
        (Group::Rate, 2),
        (Group::Mass, 0),
    ] {
        let q = quantum(g);
        let e = series(&run, g, axis);
        // THEN |error| <= q / 2 (to rounding) and the estimate is a multiple of q
        for (k, e) in e.iter().enumerate() {
            assert!(e.abs() <= 0.5 * q * (1.0 + 1e-9), "{g:?} step {k}: {e}");
        }
        let (_, y) = &run[n / 2];
        let value = match g {
            Group::Position => y.r_nue_m[0],
            Group::Velocity => y.v_nue_mps[1],
            Group::Rate => y.omega_body_radps[2],
            _ => y.mass_kg,
        };
        assert!(
            ((value / q) - (value / q).round()).abs() < 1e-9,
            "{g:?} {value}"
        );
        // AND over the sweep the error is uniform on [-q/2, q/2]: mean 0, variance q^2/12
        // (a quantiser that truncated or used another step would miss both)
        let uniform_sigma = q / 12f64.sqrt();
        assert!(
            mean(&e).abs() < 4.0 * uniform_sigma / (n as f64).sqrt(),
            "{g:?}"
        );
        assert!((variance(&e) / (q * q / 12.0) - 1.0).abs() < 0.05, "{g:?}");
    }
}

#[test]
fn quantisation_rounds_the_noisy_value() {
    // GIVEN noise and quantisation on the position
    let mut params = NavParameters::default();
    params.r_nue.noise_sigma = 0.3;
    params.r_nue.quantum = 0.1;
    let mut errors = NavErrors::start(&params);
    for k in 0..1000 {
        let x = moving_truth(k);
        let y = errors.estimate(&params, &x);
        // THEN the estimate is the noisy value rounded: within half a step of truth + noise
        let noise = errors.error(Group::Position).total(&params.r_nue);
        for ((y, x), noise) in y.r_nue_m.iter().zip(x.r_nue_m).zip(noise) {
            assert!((y - (x + noise)).abs() <= 0.05 * (1.0 + 1e-9), "step {k}");
        }
        errors.step(&params, &x, H).unwrap();
    }
}

#[test]
fn latency_delays_each_group_by_exactly_its_steps() {
    // GIVEN position late by 3 steps, mass by 1, the others on time
    let mut params = NavParameters {
        max_latency_steps: 5,
        ..NavParameters::default()
    };
    params.r_nue.latency_steps = 3;
    params.mass.latency_steps = 1;
    let run = fly(&params, 200, |_| H, moving_truth);
    for (k, (x, y)) in run.iter().enumerate() {
        // THEN the position at t_k is the truth at t_k-3 (the first truth before that), bit
        // for bit; the mass that of t_k-1; the rest the truth at t_k
        let late = |n: usize| moving_truth(k.saturating_sub(n));
        assert_eq!(y.r_nue_m, late(3).r_nue_m, "step {k}");
        assert_eq!(y.mass_kg, late(1).mass_kg, "step {k}");
        assert_eq!(y.v_nue_mps, x.v_nue_mps, "step {k}");
        assert_eq!(y.q_body_to_nue, x.q_body_to_nue, "step {k}");
        assert_eq!(y.omega_body_radps, x.omega_body_radps, "step {k}");
    }
    assert_ne!(run[50].1.r_nue_m, run[50].0.r_nue_m, "the truth moves");
}

#[test]
fn attitude_errors_keep_the_quaternion_unit() {
    let params = NavParameters {
        attitude: GroupErrors {
            noise_sigma: 0.05,
            bias: [0.1, -0.2, 0.3],
            random_walk: 0.1,
            ..GroupErrors::default()
        },
        ..NavParameters::default()
    };
    for (k, (_, y)) in fly(&params, 3000, |_| H, moving_truth).iter().enumerate() {
        let norm = y.q_body_to_nue.iter().map(|c| c * c).sum::<f64>().sqrt();
        assert!((norm - 1.0).abs() < 1e-15, "step {k}: {norm}");
    }
}

#[test]
fn the_seed_decides_the_sequence_and_groups_draw_independently() {
    let mut position_only = NavParameters {
        seed: 5,
        ..NavParameters::default()
    };
    position_only.r_nue.noise_sigma = 1.0;
    position_only.r_nue.random_walk = 0.1;
    let run = |p: &NavParameters| fly(p, 300, |_| H, moving_truth);
    let positions = |r: Vec<(Navigation, Navigation)>| -> Vec<[f64; 3]> {
        r.iter().map(|(_, y)| y.r_nue_m).collect()
    };
    // The same seed, the same errors; another seed, other errors.
    let a = positions(run(&position_only));
    assert_eq!(a, positions(run(&position_only)));
    let other_seed = NavParameters {
        seed: 6,
        ..position_only
    };
    assert_ne!(a, positions(run(&other_seed)));
    // Switching on the velocity errors leaves the position errors as they were.
    let mut both = position_only;
    both.v_nue.noise_sigma = 0.2;
    both.v_nue.random_walk = 0.3;
    assert_eq!(a, positions(run(&both)));
}
