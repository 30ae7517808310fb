// std's transcendental functions make the exact solution (cos) the solver is measured against here, outside any FMU (the
// workspace clippy.toml forbids them for the FMUs' sake).
#![allow(clippy::disallowed_methods)]
use crate::common;

use common::run_to;
use ode_solver::{Advance, Integrator, Method, OdeSystem, SolverError, Tolerances};

const METHODS: [Method; 2] = [Method::Bdf, Method::Tsit45];
const TOL: Tolerances = Tolerances {
    relative: 1e-6,
    absolute: 1e-9,
    event_time: 1e-9,
};

/// Configurable misbehaviour, to check errors come back as values.
struct Faulty {
    nan_after: f64,
    err_after: f64,
    omega: f64,
}

impl OdeSystem for Faulty {
    fn state_count(&self) -> usize {
        1
    }
    fn indicator_count(&self) -> usize {
        0
    }
    fn derivatives(&mut self, t: f64, _x: &[f64], dx: &mut [f64]) -> Result<(), String> {
        if t > self.err_after {
            return Err(format!("fmi2GetDerivatives failed at {t}"));
        }
        dx[0] = if t > self.nan_after {
            f64::NAN
        } else {
            self.omega * (self.omega * t).cos()
        };
        Ok(())
    }
    fn indicators(&mut self, _t: f64, _x: &[f64], _z: &mut [f64]) -> Result<(), String> {
        Ok(())
    }
}

#[test]
fn nan_derivative_is_an_error() {
    for method in METHODS {
        let mut sys = Faulty {
            nan_after: 0.5,
            err_after: f64::INFINITY,
            omega: 1.0,
        };
        let mut integ = Integrator::new(method, TOL, &mut sys, 0.0, &[0.0]).unwrap();
        let e = run_to(&mut integ, &mut sys, 2.0).unwrap_err();
        println!("{method:?}: {e}");
        assert!(
            matches!(e, SolverError::NonFiniteDerivative { index: 0, t } if t > 0.5),
            "{e:?}"
        );
        assert_eq!(integ.step(&mut sys, 2.0), Err(SolverError::NeedsReset));
        // A reset makes it usable again.
        sys.nan_after = f64::INFINITY;
        integ.reset(&mut sys, 0.0, &[0.0]).unwrap();
        run_to(&mut integ, &mut sys, 2.0).unwrap();
    }
}

#[test]
fn system_error_passes_through() {
    for method in METHODS {
        let mut sys = Faulty {
            nan_after: f64::INFINITY,
            err_after: 0.25,
            omega: 1.0,
        };
        let mut integ = Integrator::new(method, TOL, &mut sys, 0.0, &[0.0]).unwrap();
        let e = run_to(&mut integ, &mut sys, 1.0).unwrap_err();
        println!("{method:?}: {e}");
        match e {
            SolverError::System { message, .. } => {
                assert!(message.starts_with("fmi2GetDerivatives failed"))
            }
            other => panic!("{other:?}"),
        }
        // At construction too: the first derivative call happens in new().
        let mut sys = Faulty {
            nan_after: f64::INFINITY,
            err_after: -1.0,
            omega: 1.0,
        };
        assert!(matches!(
            Integrator::new(method, TOL, &mut sys, 0.0, &[0.0]),
            Err(SolverError::System { .. })
        ));
    }
}

#[test]
fn step_cap_stops_pathological_system() {
    for method in METHODS {
        // Oscillates a million times per second: needs millions of steps to reach t = 1000.
        let mut sys = Faulty {
            nan_after: f64::INFINITY,
            err_after: f64::INFINITY,
            omega: 1e6,
        };
        let mut integ = Integrator::new(method, TOL, &mut sys, 0.0, &[0.0]).unwrap();
        integ.set_max_steps(2_000);
        let e = run_to(&mut integ, &mut sys, 1000.0).unwrap_err();
        println!("{method:?}: {e} {:?}", integ.statistics());
        assert!(
            matches!(e, SolverError::TooManySteps { steps: 2_000, .. }),
            "{e:?}"
        );
        assert_eq!(integ.statistics().steps, 2_000);
    }
}

#[test]
fn invalid_inputs_are_errors() {
    let mut sys = common::Decay;
    let bad = Tolerances {
        relative: 0.0,
        ..TOL
    };
    assert!(matches!(
        Integrator::new(Method::Bdf, bad, &mut sys, 0.0, &[1.0]),
        Err(SolverError::InvalidInput(_))
    ));
    assert!(Integrator::new(Method::Bdf, TOL, &mut sys, 0.0, &[1.0, 2.0]).is_err());
    let mut integ = Integrator::new(Method::Bdf, TOL, &mut sys, 1.0, &[1.0]).unwrap();
    assert!(matches!(
        integ.step(&mut sys, 0.5),
        Err(SolverError::InvalidInput(_))
    ));
    assert!(integ.step(&mut sys, f64::NAN).is_err());
}

/// No continuous states, one time-dependent indicator (like a timer inside an FMU).
struct Clock;

impl OdeSystem for Clock {
    fn state_count(&self) -> usize {
        0
    }
    fn indicator_count(&self) -> usize {
        1
    }
    fn derivatives(&mut self, _t: f64, _x: &[f64], _dx: &mut [f64]) -> Result<(), String> {
        Ok(())
    }
    fn indicators(&mut self, t: f64, _x: &[f64], z: &mut [f64]) -> Result<(), String> {
        z[0] = 2.5 - t;
        Ok(())
    }
}

#[test]
fn zero_states_steps_to_stop_and_checks_indicators() {
    for method in METHODS {
        let mut sys = Clock;
        let mut integ = Integrator::new(method, TOL, &mut sys, 0.0, &[]).unwrap();
        assert_eq!(
            integ.step(&mut sys, 1.0).unwrap(),
            Advance::Reached { t: 1.0 }
        );
        let Advance::StateEvent { t, which } = integ.step(&mut sys, 5.0).unwrap() else {
            panic!("no event");
        };
        assert_eq!(which, vec![0]);
        assert!(t >= 2.5 && t - 2.5 <= 1e-9, "{t}");
        assert!(integ.state().is_empty());
        assert_eq!(
            integ.step(&mut sys, 5.0).unwrap(),
            Advance::Reached { t: 5.0 }
        );
        assert_eq!(integ.statistics().rhs_evaluations, 0);
    }
}

/// Two indicators crossing in one step: only those crossed by the located time are listed.
struct TwoThresholds;

impl OdeSystem for TwoThresholds {
    fn state_count(&self) -> usize {
        1
    }
    fn indicator_count(&self) -> usize {
        3
    }
    fn derivatives(&mut self, _t: f64, _x: &[f64], dx: &mut [f64]) -> Result<(), String> {
        dx[0] = 1.0;
        Ok(())
    }
    fn indicators(&mut self, _t: f64, x: &[f64], z: &mut [f64]) -> Result<(), String> {
        z[0] = x[0] - 3.0;
        z[1] = x[0] - 1.0;
        z[2] = x[0] - 1.0; // same as z[1]: both must be reported together
        Ok(())
    }
}

#[test]
fn events_reported_in_order_with_all_crossers() {
    for method in METHODS {
        let mut sys = TwoThresholds;
        let mut integ = Integrator::new(method, TOL, &mut sys, 0.0, &[0.0]).unwrap();
        let Advance::StateEvent { t, which } = run_to(&mut integ, &mut sys, 10.0).unwrap() else {
            panic!()
        };
        assert_eq!(which, vec![1, 2]);
        assert!((t - 1.0).abs() < 1e-8, "{t}");
        let Advance::StateEvent { t, which } = run_to(&mut integ, &mut sys, 10.0).unwrap() else {
            panic!()
        };
        assert_eq!(which, vec![0]);
        assert!((t - 3.0).abs() < 1e-8, "{t}");
        assert_eq!(
            run_to(&mut integ, &mut sys, 10.0).unwrap(),
            Advance::Reached { t: 10.0 }
        );
        assert!((integ.state()[0] - 10.0).abs() < 1e-8);
    }
}
