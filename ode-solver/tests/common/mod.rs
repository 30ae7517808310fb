// Shared test systems; not every test file uses every item.
#![allow(dead_code)]

use ode_solver::{Advance, Integrator, OdeSystem, SolverError};

pub const G_MOON: f64 = 1.62;

/// x = [h, v]; h' = v, v' = -g; z = h.
pub struct FreeFall;

impl OdeSystem for FreeFall {
    fn state_count(&self) -> usize {
        2
    }
    fn indicator_count(&self) -> usize {
        1
    }
    fn derivatives(&mut self, _t: f64, x: &[f64], dx: &mut [f64]) -> Result<(), String> {
        dx[0] = x[1];
        dx[1] = -G_MOON;
        Ok(())
    }
    fn indicators(&mut self, _t: f64, x: &[f64], z: &mut [f64]) -> Result<(), String> {
        z[0] = x[0];
        Ok(())
    }
}

/// x' = -x.
pub struct Decay;

impl OdeSystem for Decay {
    fn state_count(&self) -> usize {
        1
    }
    fn indicator_count(&self) -> usize {
        0
    }
    fn derivatives(&mut self, _t: f64, x: &[f64], dx: &mut [f64]) -> Result<(), String> {
        dx[0] = -x[0];
        Ok(())
    }
    fn indicators(&mut self, _t: f64, _x: &[f64], _z: &mut [f64]) -> Result<(), String> {
        Ok(())
    }
}

/// Robertson's chemical kinetics, the classic stiff test.
pub struct Robertson;

impl OdeSystem for Robertson {
    fn state_count(&self) -> usize {
        3
    }
    fn indicator_count(&self) -> usize {
        0
    }
    fn derivatives(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), String> {
        dy[0] = -0.04 * y[0] + 1e4 * y[1] * y[2];
        dy[2] = 3e7 * y[1] * y[1];
        dy[1] = -dy[0] - dy[2];
        Ok(())
    }
    fn indicators(&mut self, _t: f64, _y: &[f64], _z: &mut [f64]) -> Result<(), String> {
        Ok(())
    }
}

/// Step until t_stop is reached or an event occurs.
pub fn run_to(
    integ: &mut Integrator,
    sys: &mut dyn OdeSystem,
    t_stop: f64,
) -> Result<Advance, SolverError> {
    loop {
        match integ.step(sys, t_stop)? {
            Advance::Step { t } => assert!(t < t_stop),
            other => return Ok(other),
        }
    }
}
