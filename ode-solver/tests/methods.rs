//! The two methods against closed-form solutions: non-stiff, stiff, with events the
//! integration continues through, and stop times that must be hit exactly.

// std's transcendental functions make the exact solutions (cos, sin, exp) the solver is
// measured against here, outside any FMU (the workspace clippy.toml forbids them for the
// FMUs' sake).
#![allow(clippy::disallowed_methods)]
use crate::common;

use common::{run_to, Decay};
use ode_solver::{Advance, Integrator, Method, OdeSystem, SolverError, Statistics, Tolerances};

const METHODS: [Method; 2] = [Method::Bdf, Method::Tsit45];

fn tolerances(relative: f64) -> Tolerances {
    Tolerances {
        relative,
        absolute: relative * 1e-2,
        event_time: 1e-12,
    }
}

/// x'' = -x as [x, v], from [1, 0]: x = cos t, v = -sin t. The indicator is x, so it
/// crosses zero at π/2 + kπ.
struct Oscillator;

impl OdeSystem for Oscillator {
    fn state_count(&self) -> usize {
        2
    }
    fn indicator_count(&self) -> usize {
        1
    }
    fn derivatives(&mut self, _t: f64, x: &[f64], dx: &mut [f64]) -> Result<(), String> {
        dx[0] = x[1];
        dx[1] = -x[0];
        Ok(())
    }
    fn indicators(&mut self, _t: f64, x: &[f64], z: &mut [f64]) -> Result<(), String> {
        z[0] = x[0];
        Ok(())
    }
}

const LAMBDA: f64 = 1000.0;

/// y' = -λ (y - cos t) from y(0) = 0: stiff, a transient of 1/λ s and then a slow cosine.
struct StiffCosine;

impl StiffCosine {
    fn exact(t: f64) -> f64 {
        let l2 = LAMBDA * LAMBDA;
        (l2 * t.cos() + LAMBDA * t.sin()) / (l2 + 1.0) - l2 / (l2 + 1.0) * (-LAMBDA * t).exp()
    }
}

impl OdeSystem for StiffCosine {
    fn state_count(&self) -> usize {
        1
    }
    fn indicator_count(&self) -> usize {
        0
    }
    fn derivatives(&mut self, t: f64, x: &[f64], dx: &mut [f64]) -> Result<(), String> {
        dx[0] = -LAMBDA * (x[0] - t.cos());
        Ok(())
    }
    fn indicators(&mut self, _t: f64, _x: &[f64], _z: &mut [f64]) -> Result<(), String> {
        Ok(())
    }
}

/// Worst error at the stop times 1, 2, ..., t_end in units of rtol * scale + atol, where
/// `scale` is the solution's magnitude (1 for these problems: a global error is compared with
/// the local tolerance on the solution's size, not on its value near a zero crossing).
fn worst_error(
    method: Method,
    tol: Tolerances,
    sys: &mut dyn OdeSystem,
    x0: &[f64],
    t_end: u32,
    exact: impl Fn(f64) -> Vec<f64>,
) -> (f64, Statistics) {
    let mut integ = Integrator::new(method, tol, sys, 0.0, x0).unwrap();
    let weight = tol.relative + tol.absolute;
    let mut worst = 0.0f64;
    for k in 1..=t_end {
        let t = f64::from(k);
        // Events (the oscillator's zero crossings) are stepped through: that is move_back
        // inside the last step and continuing from there.
        loop {
            match run_to(&mut integ, sys, t).unwrap() {
                Advance::Reached { .. } => break,
                Advance::StateEvent { .. } => continue,
                Advance::Step { .. } => unreachable!(),
            }
        }
        for (got, want) in integ.state().iter().zip(exact(t)) {
            worst = worst.max((got - want).abs() / weight);
        }
    }
    (worst, integ.statistics())
}

/// How far above the tolerance a method's global error may go on the undamped oscillator.
/// Tsitouras propagates its 5th-order solution while its error estimate is of the 4th, so
/// its actual local errors are far below the tolerance. BDF has no such margin: each step's
/// local error is up to the tolerance, and an undamped oscillator keeps all of them, so
/// its global error grows with the number of steps (measured: 14x, 37x and 89x at rtol 1e-5,
/// 1e-7 and 1e-9; the diffsol BDF this crate used before: 22x, 54x and 106x). For BDF the
/// bound is that sum: one tolerance per step taken.
fn oscillator_bound(method: Method, stats: &Statistics) -> f64 {
    match method {
        Method::Tsit45 => 10.0,
        Method::Bdf => stats.steps as f64,
    }
}

#[test]
fn harmonic_oscillator_within_the_tolerance_each_method_can_keep() {
    let mut failures = Vec::new();
    for method in METHODS {
        for rtol in [1e-5, 1e-7, 1e-9] {
            let (worst, stats) = worst_error(
                method,
                tolerances(rtol),
                &mut Oscillator,
                &[1.0, 0.0],
                20,
                |t| vec![t.cos(), -t.sin()],
            );
            println!("{method:?} rtol {rtol:e}: worst {worst:.2} x tolerance, {stats:?}");
            if worst >= oscillator_bound(method, &stats) {
                failures.push(format!("{method:?} rtol {rtol}: {worst} x tolerance"));
            }
        }
    }
    assert!(failures.is_empty(), "{failures:?}");
}

#[test]
fn stiff_linear_problem_within_ten_times_the_tolerance_and_bdf_far_cheaper() {
    let mut steps = Vec::new();
    for method in METHODS {
        for rtol in [1e-4, 1e-6, 1e-8] {
            let (worst, stats) = worst_error(
                method,
                tolerances(rtol),
                &mut StiffCosine,
                &[0.0],
                10,
                |t| vec![StiffCosine::exact(t)],
            );
            println!("{method:?} rtol {rtol:e}: worst {worst:.2} x tolerance, {stats:?}");
            assert!(worst < 10.0, "{method:?} rtol {rtol}: {worst} x tolerance");
            if rtol == 1e-6 {
                steps.push(stats.steps);
            }
        }
    }
    // Tsitouras is held below h = 3.5 / λ (its stability limit on the negative real axis)
    // over the whole interval, long after the transient that needs accuracy.
    let (bdf, tsit) = (steps[0], steps[1]);
    assert!(bdf * 10 < tsit, "Bdf {bdf} steps vs Tsit45 {tsit}");
    assert!(
        tsit as f64 > 10.0 * LAMBDA / 3.5 * 0.9,
        "Tsit45 {tsit} steps"
    );
}

#[test]
fn events_are_located_and_integration_continues_through_them() {
    let tol = tolerances(1e-8);
    let weight = tol.relative + tol.absolute;
    for method in METHODS {
        let mut sys = Oscillator;
        let mut integ = Integrator::new(method, tol, &mut sys, 0.0, &[1.0, 0.0]).unwrap();
        // See oscillator_bound: BDF's global error on this problem grows by 10 to 30 times its
        // tolerance per period.
        let bound = match method {
            Method::Tsit45 => 10.0 * weight,
            Method::Bdf => 100.0 * weight,
        };
        let mut events = Vec::new();
        while let Advance::StateEvent { t, which } = run_to(&mut integ, &mut sys, 10.0).unwrap() {
            assert_eq!(which, vec![0]);
            // The state handed back at the event is the dense output there, and integration
            // goes on from it (move_back) without a reset.
            let (x, v) = (integ.state()[0], integ.state()[1]);
            let err = (x - t.cos()).abs().max((v + t.sin()).abs());
            assert!(
                err < bound,
                "{method:?}: state at the event at {t} off by {err:e}"
            );
            // The indicator already shows its new sign: x <= 0 after the 1st and 3rd zero.
            assert_eq!(x > 0.0, events.len() % 2 == 1, "{method:?}: x = {x} at {t}");
            events.push(t);
        }
        println!("{method:?}: events {events:?}, {:?}", integ.statistics());
        let zeros: Vec<f64> = (0..3)
            .map(|k| std::f64::consts::FRAC_PI_2 + f64::from(k) * std::f64::consts::PI)
            .collect();
        assert_eq!(events.len(), 3, "{method:?}: {events:?}");
        for (t, zero) in events.iter().zip(&zeros) {
            // |x'| = 1 at the zeros: a state error e moves the zero by about e.
            assert!(
                (t - zero).abs() < bound,
                "{method:?}: event at {t}, zero at {zero}"
            );
        }
        let (x, v) = (integ.state()[0], integ.state()[1]);
        let err = (x - 10f64.cos()).abs().max((v + 10f64.sin()).abs());
        println!("{method:?}: error {err:e} at t = 10");
        assert!(err < bound, "{method:?}: {err}");
    }
}

#[test]
fn stop_times_are_hit_bit_exactly_far_from_zero_and_a_hair_apart() {
    let tol = tolerances(1e-6);
    for method in METHODS {
        let mut sys = Decay;
        let t0 = 1e9;
        let mut integ = Integrator::new(method, tol, &mut sys, t0, &[1.0]).unwrap();
        let mut t = t0;
        for k in 1..50 {
            // Steps of 0.1 s are a few hundred thousand units in the last place at 1e9; every
            // fifth stop time is the next float after the previous one.
            let t_stop = if k % 5 == 0 { t.next_up() } else { t + 0.1 };
            assert_eq!(
                run_to(&mut integ, &mut sys, t_stop).unwrap(),
                Advance::Reached { t: t_stop }
            );
            assert_eq!(integ.time().to_bits(), t_stop.to_bits());
            t = t_stop;
        }
        let exact = (-(t - t0)).exp();
        let err = (integ.state()[0] - exact).abs();
        assert!(
            err < 10.0 * (tol.relative * exact + tol.absolute),
            "{method:?}: {err}"
        );
    }
}

/// y' = y², y(0) = 1: y = 1 / (1 - t) blows up at t = 1.
struct BlowUp;

impl OdeSystem for BlowUp {
    fn state_count(&self) -> usize {
        1
    }
    fn indicator_count(&self) -> usize {
        0
    }
    fn derivatives(&mut self, _t: f64, x: &[f64], dx: &mut [f64]) -> Result<(), String> {
        dx[0] = x[0] * x[0];
        Ok(())
    }
    fn indicators(&mut self, _t: f64, _x: &[f64], _z: &mut [f64]) -> Result<(), String> {
        Ok(())
    }
}

/// NaN as soon as the state leaves [-1, 1], as an FMU outside its valid range might answer.
struct NanOutside;

impl OdeSystem for NanOutside {
    fn state_count(&self) -> usize {
        2
    }
    fn indicator_count(&self) -> usize {
        0
    }
    fn derivatives(&mut self, _t: f64, x: &[f64], dx: &mut [f64]) -> Result<(), String> {
        let outside = x.iter().any(|v| v.abs() > 1.0);
        dx[0] = if outside { f64::NAN } else { 1.0 };
        dx[1] = 0.0;
        Ok(())
    }
    fn indicators(&mut self, _t: f64, _x: &[f64], _z: &mut [f64]) -> Result<(), String> {
        Ok(())
    }
}

#[test]
fn a_blow_up_or_a_nan_ends_in_an_error_not_a_hang() {
    for method in METHODS {
        let mut sys = BlowUp;
        let mut integ = Integrator::new(method, tolerances(1e-6), &mut sys, 0.0, &[1.0]).unwrap();
        let e = run_to(&mut integ, &mut sys, 2.0).unwrap_err();
        println!("{method:?} blow-up: {e} {:?}", integ.statistics());
        assert!(
            matches!(
                e,
                SolverError::StepSizeUnderflow { .. }
                    | SolverError::ConvergenceFailure { .. }
                    | SolverError::NonFiniteDerivative { .. }
            ),
            "{e:?}"
        );

        // x0 grows at 1/s and leaves [-1, 1] at t = 1; the Jacobian's perturbation of x1 = 1
        // already leaves it, so BDF meets the NaN at its first Jacobian.
        let mut sys = NanOutside;
        let mut integ =
            Integrator::new(method, tolerances(1e-6), &mut sys, 0.0, &[0.0, 1.0]).unwrap();
        let e = run_to(&mut integ, &mut sys, 2.0).unwrap_err();
        println!("{method:?} NaN outside: {e} {:?}", integ.statistics());
        assert!(
            matches!(e, SolverError::NonFiniteDerivative { index: 0, .. }),
            "{e:?}"
        );
        assert!(integ.statistics().rhs_evaluations < 1000);
    }
}

/// The decay, recording the latest time it was asked about.
struct Watched {
    latest: f64,
}

impl OdeSystem for Watched {
    fn state_count(&self) -> usize {
        1
    }
    fn indicator_count(&self) -> usize {
        0
    }
    fn derivatives(&mut self, t: f64, x: &[f64], dx: &mut [f64]) -> Result<(), String> {
        self.latest = self.latest.max(t);
        dx[0] = -x[0];
        Ok(())
    }
    fn indicators(&mut self, _t: f64, _x: &[f64], _z: &mut [f64]) -> Result<(), String> {
        Ok(())
    }
}

#[test]
fn the_system_is_never_evaluated_past_the_stop_time() {
    // A stop time may be an FMU's time event: it must not be asked about the time after it,
    // not by the first step's probe, a stage, or a Jacobian.
    for method in METHODS {
        let mut sys = Watched { latest: 0.0 };
        let mut integ = Integrator::new(method, tolerances(1e-6), &mut sys, 0.0, &[1.0]).unwrap();
        for t_stop in [1e-3, 0.1 + 0.2, 0.7, 5.0, 5.0 + 1e-9, 30.0] {
            run_to(&mut integ, &mut sys, t_stop).unwrap();
            assert!(
                sys.latest <= t_stop,
                "{method:?}: asked at {} for {t_stop}",
                sys.latest
            );
        }
    }
}
