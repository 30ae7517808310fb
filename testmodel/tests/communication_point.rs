//! A communication point that cannot be stepped from is refused, whatever the instance's
//! time: a step whose end overflows, or that is lost in the rounding of a huge time; for
//! both FMI versions.
// std's transcendental functions here are a reference independent of the libm the model uses.
#![allow(clippy::disallowed_methods)]
use crate::common;

use common::{Osc, Status};

fn a_step_that_does_not_advance_a_finite_time_is_refused_and_changes_nothing<D: Osc>() {
    for (start, h) in [(1e308, 1e308), (2f64.powi(60), 1.0), (f64::MAX, 1e292)] {
        // GIVEN an instance started at a huge time
        let fmu = D::open(false);
        assert_eq!(fmu.enter_initialization_mode(start, None), Status::Ok);
        assert_eq!(fmu.exit_initialization_mode(), Status::Ok);
        // WHEN a step would end at infinity or not move at all
        let step = fmu.step(start, h);
        // THEN it is refused, naming both numbers, and the instance can still step sensibly
        let message = fmu.last_message();
        if (start + h).is_finite() && start + h > start {
            assert_eq!(step.status, Status::Ok, "{start} + {h}: {message}");
            continue;
        }
        assert_eq!(step.status, Status::Error, "{start} + {h}");
        assert!(
            message.contains(&format!("{}: ", D::f("DoStep")))
                && message.contains("does not advance a finite time")
                && message.contains(&fmi_model::readable(h)),
            "{message}"
        );
        assert_eq!(fmu.own_time(), start);
    }
}

both!(a_step_that_does_not_advance_a_finite_time_is_refused_and_changes_nothing);
