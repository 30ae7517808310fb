//! Analytic tests of the optional actuator effects (docs/plant-actuators.md): throttle rate
//! limit, engine lag, RCS valve delay, RCS propellant.
use fmu_plant::physics::parameters::{PlantParameters, RcsModelKind};
use fmu_plant::physics::plant::{Advance, Commands, Plant, PlantRun, RcsHistory};
use std::cell::RefCell;

thread_local! {
    /// The valve history of the run a test steps (one run per thread at a time).
    static HISTORY: RefCell<RcsHistory> = RefCell::new(RcsHistory::default());
}
use nalgebra::Vector3;

fn thrust(n: f64) -> Commands {
    Commands {
        thrust_cmd_n: n,
        torque_cmd_body_nm: Vector3::zeros(),
    }
}

fn step(plant: &Plant, run: &mut PlantRun, c: &Commands, duty: &[f64; 8], k: usize, h: f64) {
    if k == 0 {
        HISTORY.with(|h| *h.borrow_mut() = RcsHistory::default());
    }
    let adv = HISTORY.with(|history| {
        plant.advance_with_history(run, &mut history.borrow_mut(), c, duty, k as f64 * h, h)
    });
    assert_eq!(adv, Advance::Reached);
}

#[test]
fn a_rate_limited_throttle_ramps_linearly_and_reaches_the_target_at_delta_over_rate() {
    // GIVEN 800 N/s, no lag, a 1600 N command from engines off
    let mut p = PlantParameters::default();
    p.actuators.throttle_rate_limit_nps = 800.0;
    let (plant, mut run, _) = Plant::new(&p).unwrap();
    for k in 0..300 {
        step(&plant, &mut run, &thrust(1600.0), &[0.0; 8], k, 0.01);
        // THEN the thrust is 800 t up to t = 1600 / 800 = 2 s, and 1600 N from then on
        let t = (k + 1) as f64 * 0.01;
        let expected = (800.0 * t).min(1600.0);
        let got = plant.delivered(&run.state, &thrust(1600.0), false).thrust_n;
        assert!(
            (got - expected).abs() < 1e-9,
            "t = {t}: {got} vs {expected}"
        );
    }
    // AND the mass burnt is the integral of the ramp: (2 s x 1600 / 2 + 1 s x 1600) / (isp g0)
    let burnt = 900.0 - run.state.mass_kg;
    let expected = (1600.0 + 1600.0) / (300.0 * 9.81);
    assert!((burnt - expected).abs() < 1e-9, "{burnt} vs {expected}");
    // AND down again at the same rate
    for k in 300..400 {
        step(&plant, &mut run, &thrust(800.0), &[0.0; 8], k, 0.01);
    }
    let got = plant.delivered(&run.state, &thrust(800.0), false).thrust_n;
    assert!((got - 800.0).abs() < 1e-9, "{got}");
}

#[test]
fn with_a_lag_the_rate_limit_clips_the_lag_rate_and_the_exponential_takes_over() {
    // GIVEN tau = 0.5 s and 800 N/s: (1600 - x) / tau > 800 until x = 1200 N at t = 1.5 s
    let mut p = PlantParameters::default();
    p.engines.time_constant_s = 0.5;
    p.actuators.throttle_rate_limit_nps = 800.0;
    let (plant, mut run, _) = Plant::new(&p).unwrap();
    let at = |n: usize, run: &mut PlantRun, k0: usize| {
        for k in k0..n {
            step(&plant, run, &thrust(1600.0), &[0.0; 8], k, 0.01);
        }
        run.state.thrust_lag_n
    };
    let x1 = at(100, &mut run, 0);
    assert!((x1 - 800.0).abs() < 1e-9, "{x1}");
    // THEN after the kink, 1600 - 400 exp(-(t - 1.5) / 0.5)
    let x25 = at(250, &mut run, 100);
    let expected = 1600.0 - 400.0 * libm::exp(-2.0);
    println!("after the kink: {x25:.6} N vs {expected:.6} N");
    assert!((x25 - expected).abs() < 0.05, "{x25} vs {expected}");
}

#[test]
fn the_engine_lag_reaches_63_percent_at_its_time_constant() {
    let mut p = PlantParameters::default();
    p.engines.time_constant_s = 0.3;
    let (plant, mut run, _) = Plant::new(&p).unwrap();
    for k in 0..30 {
        step(&plant, &mut run, &thrust(1600.0), &[0.0; 8], k, 0.01);
    }
    let expected = 1600.0 * (1.0 - libm::exp(-1.0));
    assert!((run.state.thrust_lag_n / expected - 1.0).abs() < 1e-7);
}

fn torque_run(delay: f64, torque_at: impl Fn(usize) -> f64, n: usize) -> Vec<f64> {
    let mut p = PlantParameters::default();
    p.actuators.rcs_valve_delay_s = delay;
    let (plant, mut run, _) = Plant::new(&p).unwrap();
    (0..n)
        .map(|k| {
            let c = Commands {
                thrust_cmd_n: 0.0,
                torque_cmd_body_nm: Vector3::new(torque_at(k), 0.0, 0.0),
            };
            step(&plant, &mut run, &c, &[0.0; 8], k, 0.01);
            run.state.omega_body.0.x
        })
        .collect()
}

#[test]
fn the_valve_delay_shifts_the_torque_by_exactly_the_delay() {
    // GIVEN a constant 50 N m about x and a delay of 35 ms (not a whole number of steps)
    let omega = torque_run(0.035, |_| 50.0, 100);
    // THEN nothing happens before 35 ms, and omega_x = 50 / 400 (t - 0.035) after
    assert_eq!(omega[2], 0.0);
    let expected = 50.0 / 400.0 * (1.0 - 0.035);
    assert!(
        (omega[99] - expected).abs() < 1e-12,
        "{} vs {expected}",
        omega[99]
    );
    // AND a command that changes every step, delayed by 3 steps, gives the undelayed rate
    // history 3 steps later
    let command = |k: usize| 80.0 * libm::sin(0.37 * k as f64);
    let undelayed = torque_run(0.0, command, 200);
    let delayed = torque_run(0.03, command, 203);
    let worst = (0..200)
        .map(|k| (delayed[k + 3] - undelayed[k]).abs())
        .fold(0.0, f64::max);
    println!("largest difference of the 3-step shifted rates: {worst:e} rad/s");
    assert!(worst < 1e-12, "{worst}");
}

#[test]
fn the_valve_delay_shifts_a_thruster_pulse() {
    // GIVEN the thruster model, thrusters 5 and 6 (a +x couple of 116 N m) at duty 0.8 for
    // the first 10 ms step only, and a 13.7 ms delay: they fire over [13.7, 21.7] ms
    let mut p = PlantParameters {
        rcs_model: RcsModelKind::Thrusters as i32,
        ..Default::default()
    };
    p.actuators.rcs_valve_delay_s = 0.0137;
    let (plant, mut run, _) = Plant::new(&p).unwrap();
    let mut duty = [0.0; 8];
    duty[4] = 0.8;
    duty[5] = 0.8;
    step(&plant, &mut run, &thrust(0.0), &duty, 0, 0.01);
    assert_eq!(run.state.omega_body.0.x, 0.0, "nothing before 13.7 ms");
    step(&plant, &mut run, &thrust(0.0), &[0.0; 8], 1, 0.01);
    let partial = 116.0 / 400.0 * (0.02 - 0.0137);
    assert!((run.state.omega_body.0.x - partial).abs() < 1e-12);
    step(&plant, &mut run, &thrust(0.0), &[0.0; 8], 2, 0.01);
    let full = 116.0 / 400.0 * 0.008;
    assert!((run.state.omega_body.0.x - full).abs() < 1e-12);
}

#[test]
fn the_rcs_propellant_is_the_integral_of_the_thruster_force_over_isp_g0() {
    // Torque model: 100 N m about x through a 1 m arm is 100 N of thruster force, for 10 s
    let mut p = PlantParameters::default();
    p.actuators.rcs_isp_s = 220.0;
    let (plant, mut run, _) = Plant::new(&p).unwrap();
    let c = Commands {
        thrust_cmd_n: 0.0,
        torque_cmd_body_nm: Vector3::new(100.0, 0.0, 0.0),
    };
    for k in 0..1000 {
        step(&plant, &mut run, &c, &[0.0; 8], k, 0.01);
    }
    let expected = 100.0 * 10.0 / (220.0 * 9.81);
    let used = 900.0 - run.state.mass_kg;
    println!("torque model: {used:.9} kg, F t / (isp g0) = {expected:.9} kg");
    assert!((used - expected).abs() < 1e-9, "{used} vs {expected}");
    // Model Exchange sees the same flow
    let dm = plant.derivative(&run.state, &c, false).mass_kg;
    assert!((dm + 100.0 / (220.0 * 9.81)).abs() < 1e-15);
    // Thruster model: two 58 N thrusters at duty 1 for 1 s
    let mut p = PlantParameters {
        rcs_model: RcsModelKind::Thrusters as i32,
        ..Default::default()
    };
    p.actuators.rcs_isp_s = 220.0;
    let (plant, mut run, _) = Plant::new(&p).unwrap();
    let mut duty = [0.0; 8];
    duty[4] = 1.0;
    duty[5] = 1.0;
    for k in 0..100 {
        step(&plant, &mut run, &thrust(0.0), &duty, k, 0.01);
    }
    let expected = 2.0 * 58.0 * 1.0 / (220.0 * 9.81);
    let used = 900.0 - run.state.mass_kg;
    println!("thruster model: {used:.9} kg, F t / (isp g0) = {expected:.9} kg");
    assert!((used - expected).abs() < 1e-9, "{used} vs {expected}");
}
