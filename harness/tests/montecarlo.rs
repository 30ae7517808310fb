//! Monte Carlo campaigns through the packaged FMUs (`target/fmu`, from `cargo xtask fmus`):
//! determinism across seeds, worker counts and shards, bit-exact replay, the dispersion
//! distribution, and the paper's trend over phi_cmd.
use crate::common;

use campaign::dispersion::{Dispersion, DispersionRanges};
use campaign::{manifest, merge, replay, runner, seed, summary};
use campaign::{CampaignSpec, Shard};
use lander::laws::Law;
use std::f64::consts::{PI, TAU};
use std::path::{Path, PathBuf};

fn small_campaign(seed: u64) -> CampaignSpec {
    CampaignSpec {
        scenario: "paper".into(),
        seed,
        phi_cmd_deg: vec![0.0, 150.0],
        laws: vec![Law::COUPLED, Law::DECOUPLED],
        runs_per_point: 2,
        dispersions: DispersionRanges::default(),
        sets: Vec::new(),
    }
}

fn run(spec: &CampaignSpec, out_dir: &Path, workers: usize, shard: Shard) -> runner::Outcome {
    let options = runner::RunOptions {
        fmu_dir: common::fmu_dir(),
        out_dir: out_dir.to_owned(),
        workers,
        shard,
        progress: false,
    };
    runner::run(spec, &options).unwrap()
}

/// The manifest's data lines sorted by flight index (rows are written as flights finish).
fn sorted_lines(manifest: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(manifest).unwrap();
    let mut lines: Vec<String> = text.lines().skip(1).map(str::to_owned).collect();
    let index = |line: &String| line.split(',').next().unwrap().parse::<u64>().unwrap();
    lines.sort_by_key(index);
    lines
}

#[test]
fn same_seed_same_rows_whatever_the_worker_count_and_sharding() {
    let spec = small_campaign(5);
    let dir = tempfile::tempdir().unwrap();
    let one = dir.path().join("one");
    let two = dir.path().join("two");
    let outcome = run(&spec, &one, 1, Shard::WHOLE);
    assert_eq!((outcome.flights, outcome.failed), (8, 0));
    run(&spec, &two, 2, Shard::WHOLE);
    let reference = sorted_lines(&one.join(manifest::FILE_NAME));
    assert_eq!(reference.len(), 8);
    assert_eq!(sorted_lines(&two.join(manifest::FILE_NAME)), reference);
    // The finished manifest is sorted by index: the files are the same byte for byte.
    let bytes = |dir: &Path| std::fs::read(dir.join(manifest::FILE_NAME)).unwrap();
    assert_eq!(bytes(&one), bytes(&two));

    // Another seed draws other dispersions.
    let other = dir.path().join("other");
    run(&small_campaign(6), &other, 2, Shard::WHOLE);
    assert_ne!(sorted_lines(&other.join(manifest::FILE_NAME)), reference);

    // Shards 1/2 and 2/2 merged give the unsharded manifest, in index order.
    let shards: Vec<PathBuf> = (1..=2)
        .map(|k| {
            let out = dir.path().join(format!("shard{k}"));
            let outcome = run(&spec, &out, 1, Shard { k, n: 2 });
            assert_eq!(outcome.flights, 4);
            out
        })
        .collect();
    let merged = merge::merge(&shards, false).unwrap();
    assert_eq!(
        merged.file.execution.workers, None,
        "a merge ran no workers"
    );
    let merged_dir = dir.path().join("merged");
    let path = merge::write(&merged, &merged_dir).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[0], manifest::header().join(","));
    assert_eq!(
        lines[1..],
        reference.iter().map(String::as_str).collect::<Vec<_>>()
    );
    assert_eq!(bytes(&merged_dir), bytes(&one));

    // A shard given twice, or one left out, is refused with the reason.
    let twice = [shards[0].clone(), shards[0].clone(), shards[1].clone()];
    let error = merge::merge(&twice, false).unwrap_err().to_string();
    assert!(error.contains("4 flights appear twice"), "{error}");
    let error = merge::merge(&shards[..1], false).unwrap_err().to_string();
    assert!(error.contains("4 of 8 flights are missing"), "{error}");
    let partial = merge::merge(&shards[..1], true).unwrap();
    assert_eq!(partial.missing, vec![1, 3, 5, 7]);
    // A shard of another campaign is refused too.
    let error = merge::merge(&[shards[0].clone(), other], false)
        .unwrap_err()
        .to_string();
    assert!(error.contains("another campaign"), "{error}");

    // Replay: the coupled law at 150 deg (the most sensitive flight) of the last run,
    // recording every output this time, gives the manifest's metrics bit for bit.
    let index = spec.flight_count() - 2;
    let flight = spec.flight(index);
    assert_eq!(
        (flight.law, flight.phi_cmd_deg, flight.run),
        (Law::COUPLED, 150.0, 1)
    );
    let replayed =
        replay::from_manifest(&one.join(manifest::FILE_NAME), index, &common::fmu_dir()).unwrap();
    assert!(replayed.matches(), "{replayed:?}");
    assert!(replayed.trajectory.column("gnc.thrust_cmd").is_some());
}

#[test]
fn a_campaign_with_a_bad_definition_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let mut spec = small_campaign(1);
    spec.scenario = "no-such-scenario.toml".into();
    let options = runner::RunOptions {
        fmu_dir: common::fmu_dir(),
        out_dir: dir.path().join("out"),
        workers: 1,
        shard: Shard::WHOLE,
        progress: false,
    };
    assert!(runner::run(&spec, &options).is_err());
    assert!(!dir.path().join("out").exists());
}

/// Sample mean of `values` within `k` standard errors of `mean`, for a statistic of known
/// standard deviation `std`.
fn assert_mean(name: &str, values: &[f64], mean: f64, std: f64) {
    const K: f64 = 5.0;
    let n = values.len() as f64;
    let sample = values.iter().sum::<f64>() / n;
    let bound = K * std / n.sqrt();
    assert!(
        (sample - mean).abs() < bound,
        "{name}: sample mean {sample}, expected {mean} +- {bound}"
    );
}

/// Every draw stays in its range, and the sample moments match the uniform distributions
/// the ranges define. Bound: 5 standard errors of each statistic (its standard deviation
/// known in closed form), which a correct sampler exceeds with probability < 1e-6 per
/// check; with 20,000 draws the central limit theorem makes the normal bound accurate.
#[test]
fn dispersion_draws_follow_the_configured_distributions() {
    let r = DispersionRanges::default();
    let draws: Vec<Dispersion> = (0..20_000)
        .map(|j| Dispersion::draw(seed::run_seed(2024, j), &r))
        .collect();
    let tilt_max = r.tilt_deg.to_radians();
    let roll_max = r.roll_deg.to_radians();
    let rate_max = r.rate_degps.to_radians();
    let misalignment_max = r.misalignment_deg.to_radians();
    for d in &draws {
        let [n, u, e] = d.delta_r0_nue_m;
        assert!(n.hypot(e) <= r.horizontal_position_m);
        assert!(u.abs() <= r.vertical_position_m);
        assert!(d.delta_v0_nue_mps.iter().all(|v| v.abs() <= r.velocity_mps));
        assert!((0.0..=tilt_max).contains(&d.tilt_rad));
        assert!((0.0..TAU).contains(&d.tilt_axis_azimuth_rad));
        assert!(d.roll_about_thrust_rad.abs() <= roll_max);
        assert!(d
            .delta_omega0_body_radps
            .iter()
            .all(|w| w.abs() <= rate_max));
        assert!((d.m0_scale - 1.0).abs() <= r.mass_fraction);
        assert!(d
            .inertia_scale
            .iter()
            .all(|s| (s - 1.0).abs() <= r.inertia_fraction));
        assert!((0.0..=misalignment_max).contains(&d.thrust_misalignment_rad));
        assert!((0.0..TAU).contains(&d.thrust_misalignment_azimuth_rad));
    }
    let col = |f: &dyn Fn(&Dispersion) -> f64| draws.iter().map(f).collect::<Vec<f64>>();
    // Symmetric uniform on [-a, a]: mean 0, std a/sqrt(3); its square: mean a^2/3,
    // std a^2 sqrt(4/45).
    let symmetric = |name: &str, a: f64, f: &dyn Fn(&Dispersion) -> f64| {
        let x = col(f);
        assert_mean(name, &x, 0.0, a / 3f64.sqrt());
        let x2: Vec<f64> = x.iter().map(|v| v * v).collect();
        assert_mean(
            &format!("{name}^2"),
            &x2,
            a * a / 3.0,
            a * a * (4.0f64 / 45.0).sqrt(),
        );
    };
    symmetric("vertical", r.vertical_position_m, &|d| d.delta_r0_nue_m[1]);
    for i in 0..3 {
        symmetric("velocity", r.velocity_mps, &|d| d.delta_v0_nue_mps[i]);
        symmetric("rate", rate_max, &|d| d.delta_omega0_body_radps[i]);
        symmetric("inertia", r.inertia_fraction, &|d| d.inertia_scale[i] - 1.0);
    }
    symmetric("roll", roll_max, &|d| d.roll_about_thrust_rad);
    symmetric("mass", r.mass_fraction, &|d| d.m0_scale - 1.0);
    // Uniform over a disc or cone of radius a: rho^2 / a^2 is uniform on [0, 1] (mean 1/2,
    // std 1/sqrt(12)); the azimuth uniform on [0, 2 pi) (mean pi, std 2 pi/sqrt(12)).
    let disc =
        |name: &str, a: f64, rho: &dyn Fn(&Dispersion) -> f64, az: &dyn Fn(&Dispersion) -> f64| {
            let u: Vec<f64> = col(rho).iter().map(|p| (p / a).powi(2)).collect();
            assert_mean(name, &u, 0.5, 1.0 / 12f64.sqrt());
            assert_mean(&format!("{name} azimuth"), &col(az), PI, TAU / 12f64.sqrt());
        };
    let horizontal = |d: &Dispersion| d.delta_r0_nue_m[0].hypot(d.delta_r0_nue_m[2]);
    let azimuth = |d: &Dispersion| {
        d.delta_r0_nue_m[2]
            .atan2(d.delta_r0_nue_m[0])
            .rem_euclid(TAU)
    };
    disc("horizontal", r.horizontal_position_m, &horizontal, &azimuth);
    disc("tilt", tilt_max, &|d| d.tilt_rad, &|d| {
        d.tilt_axis_azimuth_rad
    });
    disc(
        "misalignment",
        misalignment_max,
        &|d| d.thrust_misalignment_rad,
        &|d| d.thrust_misalignment_azimuth_rad,
    );
    // Draws of one run are independent of each other, and of the next run's: the products of
    // two independent symmetric uniforms have mean 0 and std a b / 3.
    let a = r.velocity_mps;
    let within: Vec<f64> = col(&|d| d.delta_v0_nue_mps[0] * d.delta_v0_nue_mps[2]);
    assert_mean("v_north v_east", &within, 0.0, a * a / 3.0);
    let across: Vec<f64> = draws
        .windows(2)
        .map(|w| w[0].delta_v0_nue_mps[1] * w[1].delta_v0_nue_mps[1])
        .collect();
    assert_mean("v_up of consecutive runs", &across, 0.0, a * a / 3.0);
}

/// The paper's claim, over dispersed runs. The decoupled law turns about the thrust axis
/// without moving it, so its horizontal deviation is what the 15 deg start tilt and the
/// small dispersions cause: about 1-2 m for any phi_cmd (1.6 m nominal at 150 deg), well
/// under 10 m. The coupled law's eigen-axis manoeuvre swings the thrust axis off vertical
/// for the duration of the roll, by more the larger phi_cmd is; at 150 deg that is about
/// 300 m nominally, more than 10 times the decoupled law. At phi_cmd = 0 there is no roll
/// manoeuvre and the laws see the same small errors, so they agree within a metre.
///
/// Each point is judged by its median over 3 runs, not its maximum: from the tilted start
/// the attitude loop saturates the RCS torque (+-116 N m, bang-bang for the first 6 s) and
/// overshoots (tilt error 15 deg, through 0 at 2 s, back to 14 deg at 3.5 s nominally),
/// and a few per cent of dispersed runs of *every* law, at any phi_cmd, tip over into a
/// guidance/attitude oscillation that ends 100-300 m off (seed 3, run 1, decoupled at
/// phi_cmd 0 here). That is a LanderGnc robustness matter, independent of the roll
/// coupling this test is about; the median of 3 is unaffected by one such run per point.
/// Horizontal position dispersions are left out for the same reason: a 1 m lateral offset
/// from the tilted start already diverges for every law.
#[test]
fn a_small_campaign_shows_the_papers_trend() {
    let spec = CampaignSpec {
        scenario: "paper".into(),
        seed: 3,
        phi_cmd_deg: vec![0.0, 90.0, 150.0],
        laws: vec![Law::COUPLED, Law::DECOUPLED],
        runs_per_point: 3,
        dispersions: DispersionRanges {
            horizontal_position_m: 0.0,
            vertical_position_m: 2.0,
            velocity_mps: 0.1,
            tilt_deg: 1.0,
            roll_deg: 2.0,
            rate_degps: 0.2,
            mass_fraction: 0.02,
            inertia_fraction: 0.10,
            misalignment_deg: 0.1,
            thrust_level_fraction: 0.0,
        },
        sets: Vec::new(),
    };
    let dir = tempfile::tempdir().unwrap();
    let outcome = run(&spec, dir.path(), 2, Shard::WHOLE);
    assert_eq!(outcome.failed, 0);
    let rows = manifest::read(&outcome.manifest).unwrap();
    let points = summary::summarise(&rows);
    let median = |law: Law, phi: f64| {
        points
            .iter()
            .find(|p| p.law == law && p.phi_cmd_deg == phi)
            .unwrap()
            .max_horizontal_deviation_m
            .median
    };
    for &phi in &spec.phi_cmd_deg {
        let d = median(Law::DECOUPLED, phi);
        assert!(d < 10.0, "decoupled at {phi} deg: median {d} m");
    }
    let coupled = spec
        .phi_cmd_deg
        .iter()
        .map(|&phi| median(Law::COUPLED, phi))
        .collect::<Vec<f64>>();
    assert!(
        coupled[0] < coupled[1] && coupled[1] < coupled[2],
        "coupled deviation grows with phi_cmd: {coupled:?}"
    );
    let decoupled_150 = median(Law::DECOUPLED, 150.0);
    assert!(
        coupled[2] > 10.0 * decoupled_150,
        "at 150 deg: coupled {} m vs decoupled {decoupled_150} m",
        coupled[2]
    );
    let gap = (coupled[0] - median(Law::DECOUPLED, 0.0)).abs();
    assert!(gap < 1.0, "at phi_cmd 0 the laws differ by {gap} m");
}
