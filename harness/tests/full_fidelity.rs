//! The full-fidelity scenario: the descent and landing with LanderSensors and LanderFilter
//! between the plant and the GNC, thrusters, actuator dynamics, slosh and landing gear. It
//! lands with its verdict taken at the first foot contact, settles upright, and the
//! filter's position, velocity and attitude estimates are consistent with its covariance
//! over 50 seeded runs.
use crate::common;

use campaign::attitude::{self, Quat};
use campaign::estimator_start::{self, ClaimedStartError, Start};
use cosim::master::{Simulation, Trajectory};
use cosim::system::ParamValue;
use lander::laws::{Law, Laws};

fn flown(system: cosim::system::SystemDescription) -> (Trajectory, cosim::master::RunEnd) {
    let mut simulation = Simulation::new(system, &common::fmu_dir()).unwrap();
    let mut trajectory = Trajectory {
        names: simulation.column_names().to_vec(),
        ..Default::default()
    };
    let end = simulation.run(&mut trajectory).unwrap();
    (trajectory, end)
}

#[test]
fn it_lands_on_its_footpads_inside_the_envelope_and_settles_upright() {
    // GIVEN the built-in scenario
    let (system, spec) = lander::scenarios::spec::load("full-fidelity").unwrap();
    // WHEN it is flown
    let (run, end) = flown(system);
    // THEN it lands inside the envelope
    let verdict = lander::verdict::judge(&run, &end, &spec.envelope);
    assert!(
        matches!(verdict, lander::verdict::Verdict::Landed(_)),
        "{verdict:?}"
    );
    let column = |name: &str| run.column_index(name).unwrap();
    let at = |k: usize, name: &str| run.row(k)[column(name)];
    // AND the touchdown is the first foot contact: at the recorded touchdown time a footpad
    // touches while the centre of mass is still about a leg's length (1 m) up
    let t_touch = at(run.len() - 1, "plant.touchdown_time");
    let k = run.times.iter().position(|&t| t >= t_touch).unwrap();
    let feet: f64 = (1..=4)
        .map(|i| at(k, &format!("plant.foot_contact[{i}]")))
        .sum();
    assert!(feet >= 1.0, "no footpad on the ground at t = {t_touch}");
    let altitude = at(k, "plant.r_nue[2]");
    assert!(altitude > 0.8 && altitude < 1.2, "{altitude}");
    // AND the touchdown sensor cut the engines: no thrust after it
    let last = run.len() - 1;
    assert_eq!(at(last, "plant.thrust_actual"), 0.0);
    // AND the lander ends at rest on all four footpads, not tipped over
    assert_eq!(at(last, "plant.settled"), 1.0);
    assert_eq!(at(last, "plant.tipped_over"), 0.0);
    for i in 1..=4 {
        assert_eq!(at(last, &format!("plant.foot_contact[{i}]")), 1.0);
    }
    // AND the propellant sloshed (the turn about the thrust axis excites it)
    let slosh = (0..run.len())
        .map(|k| at(k, "plant.slosh_displacement[2]").abs())
        .fold(0.0, f64::max);
    assert!(slosh > 1e-3, "{slosh}");
}

/// Two-sided 95 % band of the mean of `runs` independent chi-square(1) values:
/// chi2(runs; 2.5 %, 97.5 %) / runs, by Wilson-Hilferty.
fn band(runs: f64) -> (f64, f64) {
    let quantile = |z: f64| {
        let a = 2.0 / (9.0 * runs);
        runs * (1.0 - a + z * a.sqrt()).powi(3) / runs
    };
    (quantile(-1.959964), quantile(1.959964))
}

#[test]
fn the_filter_position_velocity_and_attitude_errors_are_consistent_with_its_covariance_over_50_seeded_runs(
) {
    // GIVEN the full-fidelity scenario's first 60 s (hover, then descent), and 50 runs,
    // each with its own sensor noise seed and an initial estimate off the truth by an error
    // drawn from the filter's claimed initial 1-sigma (10 m, 1 m/s, 0.01 rad per axis), as a
    // campaign starts it
    let (mut system, _) = lander::scenarios::spec::load("full-fidelity").unwrap();
    system.stop_time = 60.0;
    // Per axis: position truth, estimate, variance; then the same of velocity
    // (covariance_diag[4..6]); then both attitudes and the attitude variances
    // (covariance_diag[7..9], about the body axes).
    let triple = |truth: &str, i: usize, at: usize| {
        [
            format!("plant.{truth}[{i}]"),
            format!("filter.{truth}[{i}]"),
            format!("filter.covariance_diag[{}]", at + i),
        ]
    };
    let record: Vec<String> = (1..=3)
        .flat_map(|i| triple("r_nue", i, 0))
        .chain((1..=3).flat_map(|i| triple("v_nue", i, 3)))
        .chain((1..=4).map(|k| format!("plant.q_body_to_nue[{k}]")))
        .chain((1..=4).map(|k| format!("filter.q_body_to_nue[{k}]")))
        .chain((7..=9).map(|k| format!("filter.covariance_diag[{k}]")))
        .collect();
    system.record = Some(record);
    let mut simulation = Simulation::new(system, &common::fmu_dir()).unwrap();
    let claimed = ClaimedStartError {
        r0_sigma_m: 10.0,
        v0_sigma_mps: 1.0,
        attitude0_sigma_rad: 0.01,
    };
    let truth = Start {
        r0_nue_m: [0.0, 800.0, 0.0],
        v0_nue_mps: [0.0; 3],
        q0_body_to_nue: [0.9914448613738104, 0.0, 0.0, -0.13052619222005157],
    };
    let runs = 50;
    let samples = 61; // one per second
    let mut nees = vec![[0.0; 9]; samples];
    for seed in 1..=runs {
        simulation
            .set_parameter("sensors", "seed", ParamValue::Integer(seed))
            .unwrap();
        let estimate = estimator_start::estimate(seed as u64, &truth, &claimed);
        for (name, value) in estimator_start::parameters(&estimate) {
            simulation
                .set_parameter("filter", &name, ParamValue::Real(value))
                .unwrap();
        }
        let mut run = Trajectory {
            names: simulation.column_names().to_vec(),
            ..Default::default()
        };
        simulation.run(&mut run).unwrap();
        assert_eq!(run.len(), 6001);
        for (s, sample) in nees.iter_mut().enumerate() {
            let row = run.row(100 * s);
            for (i, n) in sample.iter_mut().take(6).enumerate() {
                let error = row[3 * i + 1] - row[3 * i];
                *n += error * error / row[3 * i + 2] / runs as f64;
            }
            let q = |at: usize| -> Quat { std::array::from_fn(|k| row[at + k]) };
            let error = attitude_error_body(q(18), q(22));
            for (i, n) in sample.iter_mut().skip(6).enumerate() {
                *n += error[i] * error[i] / row[26 + i] / runs as f64;
            }
        }
    }
    // THEN for each axis of position, velocity and attitude the mean normalised squared
    // error over the runs lies inside the two-sided 95 % band of chi2(50)/50 at (nearly)
    // every second: at least 90 % of the 61 samples (5 % are outside by chance when the
    // filter is consistent)
    let (low, high) = band(runs as f64);
    assert!((low - 0.647).abs() < 0.01 && (high - 1.428).abs() < 0.01);
    let names = ["r_nue", "v_nue", "attitude body"];
    let mut failed = Vec::new();
    for axis in 0..9 {
        let inside = nees
            .iter()
            .filter(|n| (low..=high).contains(&n[axis]))
            .count();
        let mean = nees.iter().map(|n| n[axis]).sum::<f64>() / samples as f64;
        let name = format!("{}[{}]", names[axis / 3], axis % 3 + 1);
        println!("{name}: {inside} of {samples} inside [{low:.3}, {high:.3}], mean {mean:.3}");
        if inside * 10 < samples * 9 {
            failed.push(format!("{name}: {inside} of {samples}, mean {mean:.3}"));
        }
    }
    assert!(failed.is_empty(), "{failed:?}; {nees:?}");
}

/// The filter's attitude error about the body axes, `dtheta` with
/// `q_true = q_estimate exp(dtheta)` (its error state), to first order.
fn attitude_error_body(q_true: Quat, q_estimate: Quat) -> [f64; 3] {
    let [w, x, y, z] = q_estimate;
    let d = attitude::multiply([w, -x, -y, -z], q_true);
    let sign = if d[0] < 0.0 { -2.0 } else { 2.0 };
    [sign * d[1], sign * d[2], sign * d[3]]
}

#[test]
fn every_law_lands_and_the_decoupled_laws_deviate_least() {
    // GIVEN the full-fidelity scenario, flown with every law
    let fly = |name: &str| {
        let (system, spec) = lander::scenarios::spec::load(name).unwrap();
        let laws = Laws::of_instance(&system, "gnc", &common::fmu_dir()).unwrap();
        lander::paper::fly_all(system, &common::fmu_dir(), &laws.all(), &spec.envelope, &[])
            .unwrap()
    };
    let full = fly("full-fidelity");
    // THEN with every effect on each law lands
    for flight in &full {
        assert!(
            matches!(flight.verdict, lander::verdict::Verdict::Landed(_)),
            "{:?}: {:?}",
            flight.law,
            flight.verdict
        );
    }
    // AND the paper's ordering holds: the coupled law deviates more than twice as far
    let deviation = |flights: &[lander::paper::Flight], law: Law| {
        flights
            .iter()
            .find(|f| f.law == law)
            .unwrap()
            .metrics
            .max_horizontal_deviation_descent_m
    };
    for other in [Law::DECOUPLED, Law::new("reduced")] {
        assert!(
            deviation(&full, Law::COUPLED) > 2.0 * deviation(&full, other),
            "{other:?}"
        );
    }
    // The README's sentence on these deviations carries each number's source and is checked
    // against it by `results_inline.rs`.
}
