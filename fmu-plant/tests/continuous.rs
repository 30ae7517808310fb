//! The plant as a flat ODE (the Model Exchange view), driven by an integrator of this file:
//! the 3/8-rule Runge-Kutta method, a different method from the Co-Simulation RK4, with
//! events located by bisection on the event indicators. Cross-checked against analytic
//! solutions and against the Co-Simulation plant.
// std's transcendental functions here are a reference independent of the libm the model uses.
#![allow(clippy::disallowed_methods)]
use fmu_plant::physics::continuous::{StateLayout, EVENT_INDICATOR_COUNT};
use fmu_plant::physics::frames::Body;
use fmu_plant::physics::parameters::PlantParameters;
use fmu_plant::physics::plant::{Advance, Commands, Plant, PlantRun};
use fmu_plant::physics::state::PlantState;
use nalgebra::{Quaternion, Vector3};

const G: f64 = 1.62;

fn start(p: &PlantParameters) -> (Plant, PlantRun) {
    let (plant, run, _) = Plant::new(p).expect("valid parameters");
    (plant, run)
}

fn thrust(n: f64) -> Commands {
    Commands {
        thrust_cmd_n: n,
        torque_cmd_body_nm: Vector3::zeros(),
    }
}

/// A foreign integrator: it knows only the flat vector, the derivative and the indicators.
struct Integrator<'a> {
    plant: &'a Plant,
    layout: StateLayout,
    run: PlantRun,
    t: f64,
}

impl Integrator<'_> {
    fn derivative(&self, run: &PlantRun, x: &[f64], commands: &Commands) -> Vec<f64> {
        let mut probe = *run;
        self.plant
            .set_continuous_states(&self.layout, &mut probe, x)
            .unwrap();
        let mut d = vec![0.0; self.layout.len()];
        self.plant
            .continuous_derivative(&self.layout, &probe, commands, &mut d)
            .unwrap();
        d
    }

    /// The 3/8-rule step of size `h` from `run`, as a new run.
    fn stepped(&self, run: &PlantRun, commands: &Commands, h: f64) -> PlantRun {
        let mut x0 = vec![0.0; self.layout.len()];
        self.layout.pack(&run.state, &mut x0).unwrap();
        let comb = |terms: &[(f64, &Vec<f64>)]| -> Vec<f64> {
            (0..x0.len())
                .map(|i| x0[i] + terms.iter().map(|(c, k)| c * k[i]).sum::<f64>())
                .collect()
        };
        let k1 = self.derivative(run, &x0, commands);
        let k2 = self.derivative(run, &comb(&[(h / 3.0, &k1)]), commands);
        let k3 = self.derivative(run, &comb(&[(-h / 3.0, &k1), (h, &k2)]), commands);
        let k4 = self.derivative(run, &comb(&[(h, &k1), (-h, &k2), (h, &k3)]), commands);
        let x1 = comb(&[
            (h / 8.0, &k1),
            (3.0 * h / 8.0, &k2),
            (3.0 * h / 8.0, &k3),
            (h / 8.0, &k4),
        ]);
        let mut next = *run;
        self.plant
            .set_continuous_states(&self.layout, &mut next, &x1)
            .unwrap();
        next
    }

    /// Advances by `h`, stopping at the first indicator crossing (located by bisection on the
    /// step length to 1e-13 s) and running the event update there. Returns true on touchdown.
    fn step(&mut self, commands: &Commands, h: f64) -> bool {
        let before = self.plant.event_indicators(&self.run);
        let candidate = self.stepped(&self.run, commands, h);
        let after = self.plant.event_indicators(&candidate);
        let crossed = |z0: &[f64; EVENT_INDICATOR_COUNT], z1: &[f64; EVENT_INDICATOR_COUNT]| {
            z0.iter().zip(z1).any(|(a, b)| *a > 0.0 && *b <= 0.0)
        };
        if !crossed(&before, &after) {
            self.run = candidate;
            self.t += h;
            return false;
        }
        let (mut lo, mut hi) = (0.0, h);
        while hi - lo > 1e-13 {
            let mid = 0.5 * (lo + hi);
            let probe = self.stepped(&self.run, commands, mid);
            if crossed(&before, &self.plant.event_indicators(&probe)) {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        self.run = self.stepped(&self.run, commands, hi);
        self.t += hi;
        self.plant.update_at_event(&mut self.run, self.t).touchdown
    }
}

fn integrator(plant: &Plant, run: PlantRun) -> Integrator<'_> {
    Integrator {
        plant,
        layout: StateLayout::ALL,
        run,
        t: 0.0,
    }
}

#[test]
fn compact_layout_holds_the_lag_states_only_when_their_lag_is_on() {
    for (engine_tau, rcs_tau, len) in [
        (0.0, 0.0, 14),
        (0.2, 0.0, 15),
        (0.0, 0.1, 17),
        (0.2, 0.1, 18),
    ] {
        let mut p = PlantParameters::default();
        p.engines.time_constant_s = engine_tau;
        p.rcs.time_constant_s = rcs_tau;
        let (plant, _) = start(&p);
        assert_eq!(StateLayout::compact(&plant).len(), len);
    }
    assert_eq!(StateLayout::ALL.len(), 18);
}

#[test]
fn pack_and_unpack_round_trip_and_refuse_a_wrong_length() {
    let x = PlantState {
        translation: nalgebra::Vector6::new(1.0, 2.0, 3.0, 4.0, 5.0, 6.0),
        q_body_to_nue: Quaternion::new(0.5, -0.5, 0.5, 0.5),
        omega_body: Body::new(0.1, 0.2, 0.3),
        mass_kg: 800.0,
        thrust_lag_n: 900.0,
        torque_lag_body_nm: Body::new(-1.0, -2.0, -3.0),
    };
    let mut v = vec![0.0; 18];
    StateLayout::ALL.pack(&x, &mut v).unwrap();
    // scalar first, then the lags
    assert_eq!(&v[6..10], &[0.5, -0.5, 0.5, 0.5]);
    assert_eq!(&v[14..], &[900.0, -1.0, -2.0, -3.0]);
    assert_eq!(StateLayout::ALL.unpack(&v).unwrap(), x);

    let rcs_only = StateLayout {
        engine_lag: false,
        rcs_lag: true,
    };
    let mut v = vec![0.0; 17];
    rcs_only.pack(&x, &mut v).unwrap();
    let back = rcs_only.unpack(&v).unwrap();
    assert_eq!(back.torque_lag_body_nm, x.torque_lag_body_nm);
    assert_eq!(back.thrust_lag_n, 0.0);

    let err = StateLayout::ALL.pack(&x, &mut [0.0; 14]).unwrap_err();
    assert_eq!((err.expected, err.got), (18, 14));
    assert!(StateLayout::ALL.unpack(&[0.0; 19]).is_err());
}

#[test]
fn flat_derivative_is_the_co_simulation_derivative_on_the_unit_sphere() {
    // GIVEN a state with everything moving and both lags on
    let mut p = PlantParameters {
        v0_nue_mps: Vector3::new(2.0, -7.0, 1.0),
        q0_body_to_nue: [0.9, 0.1, -0.3, 0.2].map(|c| c / 0.974_679_434_480_896_4),
        omega0_body_radps: Vector3::new(0.1, -0.3, 0.2),
        ..Default::default()
    };
    p.engines.time_constant_s = 0.3;
    p.rcs.time_constant_s = 0.1;
    p.thrust_line.misalignment_rad = 0.02;
    let (plant, mut run) = start(&p);
    run.state.thrust_lag_n = 1100.0;
    run.state.torque_lag_body_nm = Body::new(10.0, -20.0, 5.0);
    let cmd = Commands {
        thrust_cmd_n: 1300.0,
        torque_cmd_body_nm: Vector3::new(50.0, 200.0, -10.0),
    };
    // WHEN both views evaluate it
    let mut flat = vec![0.0; 18];
    plant
        .continuous_derivative(&StateLayout::ALL, &run, &cmd, &mut flat)
        .unwrap();
    let mut expected = vec![0.0; 18];
    StateLayout::ALL
        .pack(&plant.derivative(&run.state, &cmd, false), &mut expected)
        .unwrap();
    // THEN they agree (the norm term is zero to round-off on a unit quaternion)
    for (i, (a, b)) in flat.iter().zip(&expected).enumerate() {
        assert!(
            (a - b).abs() <= 1e-15 * (1.0 + b.abs()),
            "state {i}: {a} vs {b}"
        );
    }
    // and the lags move: the RCS x lag state heads for its saturated target of 50 N m
    assert!((flat[15] - (50.0 - 10.0) / 0.1).abs() < 1e-12);
    assert!(
        (flat[16] - (116.0 + 20.0) / 0.1).abs() < 1e-12,
        "saturated at 116"
    );
}

#[test]
fn lag_states_have_no_rate_when_the_lags_are_off() {
    let (plant, run) = start(&PlantParameters::default());
    let mut d = vec![f64::NAN; 18];
    let cmd = Commands {
        thrust_cmd_n: 1500.0,
        torque_cmd_body_nm: Vector3::new(30.0, 0.0, 0.0),
    };
    plant
        .continuous_derivative(&StateLayout::ALL, &run, &cmd, &mut d)
        .unwrap();
    assert_eq!(&d[14..], &[0.0; 4]);
    // while the thrust acts directly
    assert!((d[4] - (1500.0 / 900.0 - G)).abs() < 1e-12);
}

#[test]
fn free_fall_follows_the_parabola_and_touches_down_at_the_analytic_time() {
    // GIVEN engines off at 800 m, at rest
    let (plant, run) = start(&PlantParameters::default());
    let mut ode = integrator(&plant, run);
    // WHEN the foreign integrator runs in 0.01 s steps
    let mut touchdown = false;
    while !touchdown {
        touchdown = ode.step(&thrust(0.0), 0.01);
        let (r, v) = plant.translation.to_nue(&ode.run.state.translation);
        let (r, v) = (r.0, v.0);
        // THEN the path is 800 - 0.81 t^2 (the method is exact for a quadratic)
        if !touchdown {
            assert!((r.y - (800.0 - 0.5 * G * ode.t * ode.t)).abs() < 1e-9);
            assert!((v.y + G * ode.t).abs() < 1e-11);
        }
        assert!(ode.t < 40.0, "no touchdown found");
    }
    // AND the touchdown is at sqrt(800 / 0.81) = 31.42697 s and is recorded and frozen
    let t_exact = (800.0 / (0.5 * G)).sqrt();
    assert!((t_exact - 31.42697).abs() < 1e-5);
    let td = ode.run.touchdown.expect("recorded");
    assert!(
        (td.time_s - t_exact).abs() < 1e-9,
        "{} vs {t_exact}",
        td.time_s
    );
    assert!((td.v_nue_mps.0.y + G * t_exact).abs() < 1e-8);
    assert_eq!(plant.event_indicators(&ode.run)[0], -1.0);
    let frozen = ode.run;
    ode.step(&thrust(1600.0), 0.5);
    assert_eq!(ode.run, frozen, "after touchdown the lander does not move");
}

/// Runs the Co-Simulation plant and the foreign integrator side by side for `seconds` in
/// steps of `h` under `commands(k)`; returns the largest state difference seen.
fn co_simulation_vs_flat(
    p: &PlantParameters,
    seconds: f64,
    commands: impl Fn(usize) -> Commands,
) -> f64 {
    let (plant, cs) = start(p);
    let mut cs = cs;
    let mut ode = integrator(&plant, cs);
    let h = 0.01;
    let steps = (seconds / h).round() as usize;
    let mut worst: f64 = 0.0;
    for k in 0..steps {
        let cmd = commands(k);
        assert_eq!(
            plant.advance(&mut cs, &cmd, k as f64 * h, h),
            Advance::Reached
        );
        assert!(!ode.step(&cmd, h));
        let (mut a, mut b) = (vec![0.0; 18], vec![0.0; 18]);
        StateLayout::ALL.pack(&cs.state, &mut a).unwrap();
        StateLayout::ALL
            .pack(&ode.run.state.renormalised(), &mut b)
            .unwrap();
        for (x, y) in a.iter().zip(&b) {
            worst = worst.max((x - y).abs() / (1.0 + x.abs()));
        }
    }
    worst
}

#[test]
fn hover_matches_the_co_simulation_plant() {
    // GIVEN a thrust of m g, recomputed from the mass each step, and a real mass flow
    let p = PlantParameters::default();
    let worst = co_simulation_vs_flat(&p, 30.0, |_| thrust(900.0 * G));
    // THEN both interfaces give the same trajectory
    assert!(worst < 1e-9, "relative difference {worst}");
    // (and it is a hover: checked on a fresh CS run)
    let (plant, mut run) = start(&p);
    for k in 0..100 {
        plant.advance(&mut run, &thrust(900.0 * G), k as f64 * 0.01, 0.01);
    }
    assert!((plant.altitude(&run.state) - 800.0).abs() < 1e-3);
}

#[test]
fn pure_torque_tumbling_matches_the_co_simulation_plant() {
    // GIVEN a tumbling body under a varying, partly saturated torque, high up
    let p = PlantParameters {
        r0_nue_m: Vector3::new(0.0, 1e6, 0.0),
        omega0_body_radps: Vector3::new(0.8, 0.02, 0.03),
        ..Default::default()
    };
    let worst = co_simulation_vs_flat(&p, 20.0, |k| Commands {
        thrust_cmd_n: 0.0,
        torque_cmd_body_nm: Vector3::new(
            40.0 * (k as f64 * 0.01).sin(),
            -150.0,
            20.0 * (k as f64 * 0.03).cos(),
        ),
    });
    assert!(worst < 1e-6, "relative difference {worst}");
}

#[test]
fn a_drifted_quaternion_norm_returns_to_one_without_changing_the_rotation() {
    // GIVEN a foreign integrator that left |q| = 1.05 on a spinning body
    let p = PlantParameters {
        r0_nue_m: Vector3::new(0.0, 1e6, 0.0),
        omega0_body_radps: Vector3::new(0.0, 0.5, 0.0),
        ..Default::default()
    };
    let (plant, mut run) = start(&p);
    run.state.q_body_to_nue *= 1.05;
    // THEN the norm term points back towards the sphere
    let mut d = vec![0.0; 18];
    plant
        .continuous_derivative(&StateLayout::ALL, &run, &thrust(0.0), &mut d)
        .unwrap();
    let q = run.state.q_body_to_nue;
    let radial = q.w * d[6] + q.i * d[7] + q.j * d[8] + q.k * d[9];
    assert!(radial < 0.0);
    // WHEN integrating for 10 s (time constant 1 / (2 k) = 0.5 s)
    let mut ode = integrator(&plant, run);
    for _ in 0..1000 {
        ode.step(&thrust(0.0), 0.01);
    }
    // THEN |q| is back to 1 and the attitude is the spin about y by 0.5 rad/s x 10 s
    let q = ode.run.state.q_body_to_nue;
    assert!((q.norm() - 1.0).abs() < 1e-6, "|q| = {}", q.norm());
    let angle: f64 = 5.0;
    let exact = Quaternion::new((0.5 * angle).cos(), 0.0, (0.5 * angle).sin(), 0.0);
    assert!((q.normalize() - exact).norm() < 1e-6, "{q} vs {exact}");
    // and the event update renormalises exactly
    let mut run = ode.run;
    plant.update_at_event(&mut run, ode.t);
    assert!((run.state.q_body_to_nue.norm() - 1.0).abs() < 4.0 * f64::EPSILON);
}

#[test]
fn exhaustion_event_pins_the_dry_mass_and_cuts_the_engines() {
    // GIVEN 1 kg of propellant at full thrust (burn-out at 1 kg / (1600 / (300 * 9.81)) s)
    let p = PlantParameters {
        m0_kg: 601.0,
        ..Default::default()
    };
    let (plant, run) = start(&p);
    let mut ode = integrator(&plant, run);
    // (an event ends a step early: step on to exactly 4 s)
    while 4.0 - ode.t > 1e-12 {
        assert!(!ode.step(&thrust(1600.0), (4.0 - ode.t).min(0.1)));
    }
    // THEN the flag is up, the indicator is spent, the mass is the dry mass,
    assert!(ode.run.propellant_exhausted);
    assert_eq!(plant.event_indicators(&ode.run)[1], -1.0);
    assert_eq!(ode.run.state.mass_kg, 600.0);
    // and the velocity is the rocket equation to burn-out, then a coast, as in CS
    let isp_g0 = 300.0 * 9.81;
    let v_exact = isp_g0 * (601.0f64 / 600.0).ln() - G * 4.0;
    let v = plant.translation.to_nue(&ode.run.state.translation).1 .0;
    assert!((v.y - v_exact).abs() < 1e-8, "{} vs {v_exact}", v.y);
}

#[test]
fn engine_lag_follows_the_same_exponential_as_co_simulation() {
    let mut p = PlantParameters {
        isp_s: 1e15,
        ..Default::default()
    };
    p.engines.time_constant_s = 0.5;
    p.rcs.time_constant_s = 0.2;
    let worst = co_simulation_vs_flat(&p, 5.0, |k| Commands {
        thrust_cmd_n: if k < 200 { 1500.0 } else { 800.0 },
        torque_cmd_body_nm: Vector3::new(20.0, 0.0, -20.0),
    });
    assert!(worst < 1e-6, "relative difference {worst}");
}

#[test]
fn published_attitude_is_unit_and_keeps_the_bits_of_a_unit_state() {
    use fmu_plant::physics::continuous::unit_attitude;
    let (plant, mut run) = start(&PlantParameters {
        r0_nue_m: Vector3::new(0.0, 1e6, 0.0),
        omega0_body_radps: Vector3::new(0.3, -0.7, 0.2),
        ..Default::default()
    });
    for k in 0..100 {
        plant.advance(&mut run, &thrust(0.0), k as f64 * 0.01, 0.01);
        let q = run.state.q_body_to_nue;
        assert_eq!(unit_attitude(&q), q, "a CS state is published as it is");
    }
    let drifted = run.state.q_body_to_nue * (1.0 + 1e-9);
    let published = unit_attitude(&drifted);
    assert!((published.norm() - 1.0).abs() < 4.0 * f64::EPSILON);
    assert!((published - run.state.q_body_to_nue).norm() < 1e-15);
}
