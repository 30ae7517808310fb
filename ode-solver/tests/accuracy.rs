// std's transcendental functions make the exact solutions (exp) the solver is measured against here, outside any FMU (the
// workspace clippy.toml forbids them for the FMUs' sake).
#![allow(clippy::disallowed_methods)]
use crate::common;

use common::{run_to, Decay, FreeFall, Robertson, G_MOON};
use ode_solver::{Advance, Integrator, Method, Tolerances};

const METHODS: [Method; 2] = [Method::Bdf, Method::Tsit45];

#[test]
fn free_fall_hits_ground_at_analytic_time() {
    let tol = Tolerances {
        relative: 1e-10,
        absolute: 1e-10,
        event_time: 1e-10,
    };
    let t_ground = (800.0 / (G_MOON / 2.0)).sqrt();
    assert!((t_ground - 31.426968052735447_f64).abs() < 1e-12);
    for method in METHODS {
        let mut sys = FreeFall;
        let mut integ = Integrator::new(method, tol, &mut sys, 0.0, &[800.0, 0.0]).unwrap();
        for t in [10.0, 20.0, 30.0] {
            assert_eq!(
                run_to(&mut integ, &mut sys, t).unwrap(),
                Advance::Reached { t }
            );
            let h_err = integ.state()[0] - (800.0 - 0.81 * t * t);
            let v_err = integ.state()[1] + G_MOON * t;
            println!("{method:?} t={t}: h error {h_err:.3e} m, v error {v_err:.3e} m/s");
            assert!(h_err.abs() < 1e-6, "{method:?} h error {h_err} at {t}");
        }
        let Advance::StateEvent { t, which } = run_to(&mut integ, &mut sys, 40.0).unwrap() else {
            panic!("{method:?}: no ground contact before 40 s");
        };
        let t_err = t - t_ground;
        println!(
            "{method:?} event at {t:.15} (error {t_err:.3e} s), h = {:.3e}, {:?}",
            integ.state()[0],
            integ.statistics()
        );
        assert_eq!(which, vec![0]);
        assert!(t_err.abs() < 1e-6, "{method:?} event time error {t_err}");
        // Just after the crossing: the indicator already has its new sign.
        assert!(integ.state()[0] <= 0.0);
        assert_eq!(integ.time(), t);
        // Integration may continue from the event without a reset.
        assert_eq!(
            run_to(&mut integ, &mut sys, 40.0).unwrap(),
            Advance::Reached { t: 40.0 }
        );
        assert!((integ.state()[0] - (800.0 - 0.81 * 1600.0)).abs() < 1e-5);
    }
}

#[test]
fn exponential_decay_within_tolerance() {
    for method in METHODS {
        for rtol in [1e-4, 1e-6, 1e-8] {
            let tol = Tolerances {
                relative: rtol,
                absolute: rtol * 1e-2,
                event_time: 1e-9,
            };
            let mut sys = Decay;
            let mut integ = Integrator::new(method, tol, &mut sys, 0.0, &[1.0]).unwrap();
            let mut worst = 0.0f64;
            for k in 1..=10 {
                let t = k as f64;
                run_to(&mut integ, &mut sys, t).unwrap();
                // Global error in units of the local error weight rtol*|x| + atol.
                let exact = (-t).exp();
                let weight = tol.relative * exact + tol.absolute;
                worst = worst.max((integ.state()[0] - exact).abs() / weight);
            }
            println!(
                "{method:?} rtol {rtol:e}: worst error {worst:.2} x (rtol|x| + atol), {:?}",
                integ.statistics()
            );
            assert!(worst < 20.0, "{method:?} rtol {rtol}: {worst} x weight");
        }
    }
}

#[test]
fn reset_restarts_from_new_state() {
    let tol = Tolerances {
        relative: 1e-8,
        absolute: 1e-10,
        event_time: 1e-9,
    };
    for method in METHODS {
        let mut sys = Decay;
        let mut integ = Integrator::new(method, tol, &mut sys, 0.0, &[1.0]).unwrap();
        run_to(&mut integ, &mut sys, 1.0).unwrap();
        integ.reset(&mut sys, 1.0, &[2.0]).unwrap();
        run_to(&mut integ, &mut sys, 2.0).unwrap();
        let err = integ.state()[0] - 2.0 * (-1.0f64).exp();
        assert!(err.abs() < 1e-6, "{method:?}: {err}");
        assert_eq!(integ.statistics().restarts, 1);
    }
}

fn robertson(method: Method, tol: Tolerances, t_end: f64) -> (Vec<f64>, ode_solver::Statistics) {
    let mut sys = Robertson;
    let mut integ = Integrator::new(method, tol, &mut sys, 0.0, &[1.0, 0.0, 0.0]).unwrap();
    run_to(&mut integ, &mut sys, t_end).unwrap();
    (integ.state().to_vec(), integ.statistics())
}

#[test]
fn stiff_robertson_bdf_beats_explicit() {
    let tol = Tolerances {
        relative: 1e-6,
        absolute: 1e-10,
        event_time: 1e-9,
    };
    let tight = Tolerances {
        relative: 1e-11,
        absolute: 1e-15,
        event_time: 1e-9,
    };
    let t_end = 40.0;
    let (y_bdf, s_bdf) = robertson(Method::Bdf, tol, t_end);
    let (y_rk, s_rk) = robertson(Method::Tsit45, tol, t_end);
    let (y_ref, s_ref) = robertson(Method::Bdf, tight, t_end);
    println!("Bdf    {y_bdf:?} {s_bdf:?}");
    println!("Tsit45 {y_rk:?} {s_rk:?}");
    println!("ref    {y_ref:?} {s_ref:?}");
    // Literature values at t = 40 (Hairer & Wanner), 10 digits.
    let lit = [0.7158270687, 9.185534764e-6, 0.2841637457];
    for i in 0..3 {
        assert!((y_ref[i] - lit[i]).abs() <= 1e-9 * lit[i].abs().max(1e-3));
        let rel = (y_bdf[i] - y_ref[i]).abs() / y_ref[i].abs();
        assert!(rel < 1e-4, "Bdf component {i} off by {rel:e}");
    }
    assert!(
        s_bdf.steps * 20 < s_rk.steps,
        "Bdf {} steps vs Tsit45 {}",
        s_bdf.steps,
        s_rk.steps
    );
    assert!(s_bdf.rhs_evaluations * 10 < s_rk.rhs_evaluations);
    assert!(s_bdf.jacobian_evaluations > 0);
    assert_eq!(s_rk.jacobian_evaluations, 0);
}

#[test]
fn reached_is_bit_exact() {
    let tol = Tolerances {
        relative: 1e-6,
        absolute: 1e-9,
        event_time: 1e-9,
    };
    for method in METHODS {
        let mut sys = Decay;
        let mut integ = Integrator::new(method, tol, &mut sys, 0.0, &[1.0]).unwrap();
        let mut t = 0.0;
        for k in 1..200 {
            t += 0.1; // accumulates rounding: not a multiple of anything nice
            let t_stop = if k % 7 == 0 { t + 1.0 / 3.0 } else { t };
            let r = run_to(&mut integ, &mut sys, t_stop).unwrap();
            assert_eq!(r, Advance::Reached { t: t_stop });
            assert_eq!(integ.time().to_bits(), t_stop.to_bits());
            t = t_stop;
        }
        // Asking again at the current time is a no-op.
        assert_eq!(integ.step(&mut sys, t).unwrap(), Advance::Reached { t });
    }
}
