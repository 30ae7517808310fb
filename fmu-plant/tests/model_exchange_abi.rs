//! LanderPlant as a Model Exchange FMU through its exported C functions, driven by a solver
//! of this file: classical RK4 at a fixed step over fmi2SetTime / fmi2SetContinuousStates /
//! fmi2GetDerivatives, events located by bisection on fmi2GetEventIndicators and handled
//! with fmi2EnterEventMode / fmi2NewDiscreteStates, as an ME master does.
#![allow(unsafe_code)]
mod common;

use common::Plant;
use fmi2_export::ffi::*;
use fmu_plant as fmu;

const G: f64 = 1.62;
const NX: usize = 18;
const NZ: usize = 2;

fn ok(status: fmi2Status, what: &str, plant: &Plant) {
    assert_eq!(status, fmi2Status::fmi2OK, "{what}: {:?}", plant.messages());
}

/// The master's side: time, state vector and the calls that move them.
struct Solver<'a> {
    plant: &'a Plant,
    t: f64,
    x: Vec<f64>,
}

impl Solver<'_> {
    fn derivatives(&self, t: f64, x: &[f64]) -> Vec<f64> {
        let c = self.plant.c;
        let mut dx = vec![f64::NAN; NX];
        unsafe {
            ok(fmu::fmi2SetTime(c, t), "fmi2SetTime", self.plant);
            ok(
                fmu::fmi2SetContinuousStates(c, x.as_ptr(), NX),
                "fmi2SetContinuousStates",
                self.plant,
            );
            ok(
                fmu::fmi2GetDerivatives(c, dx.as_mut_ptr(), NX),
                "fmi2GetDerivatives",
                self.plant,
            );
        }
        dx
    }

    fn indicators_at(&self, t: f64, x: &[f64]) -> [f64; NZ] {
        let c = self.plant.c;
        let mut z = [f64::NAN; NZ];
        unsafe {
            ok(fmu::fmi2SetTime(c, t), "fmi2SetTime", self.plant);
            ok(
                fmu::fmi2SetContinuousStates(c, x.as_ptr(), NX),
                "fmi2SetContinuousStates",
                self.plant,
            );
            ok(
                fmu::fmi2GetEventIndicators(c, z.as_mut_ptr(), NZ),
                "fmi2GetEventIndicators",
                self.plant,
            );
        }
        z
    }

    fn rk4(&self, h: f64) -> Vec<f64> {
        let (t, x) = (self.t, &self.x);
        let at =
            |k: &[f64], s: f64| -> Vec<f64> { x.iter().zip(k).map(|(a, b)| a + s * b).collect() };
        let k1 = self.derivatives(t, x);
        let k2 = self.derivatives(t + h / 2.0, &at(&k1, h / 2.0));
        let k3 = self.derivatives(t + h / 2.0, &at(&k2, h / 2.0));
        let k4 = self.derivatives(t + h, &at(&k3, h));
        (0..NX)
            .map(|i| x[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]))
            .collect()
    }

    /// One step of `h`, cut at an indicator crossing; returns whether the FMU ended the run.
    fn step(&mut self, h: f64) -> bool {
        let z0 = self.indicators_at(self.t, &self.x);
        let crossed = |z1: [f64; NZ]| z0.iter().zip(z1).any(|(a, b)| *a > 0.0 && b <= 0.0);
        let x1 = self.rk4(h);
        if !crossed(self.indicators_at(self.t + h, &x1)) {
            self.t += h;
            self.x = x1;
            return false;
        }
        let (mut lo, mut hi) = (0.0, h);
        while hi - lo > 1e-13 {
            let mid = 0.5 * (lo + hi);
            let xm = self.rk4(mid);
            if crossed(self.indicators_at(self.t + mid, &xm)) {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        self.x = self.rk4(hi);
        self.t += hi;
        self.event()
    }

    fn event(&mut self) -> bool {
        let c = self.plant.c;
        let mut info = fmi2EventInfo::default();
        unsafe {
            ok(fmu::fmi2SetTime(c, self.t), "fmi2SetTime", self.plant);
            ok(
                fmu::fmi2SetContinuousStates(c, self.x.as_ptr(), NX),
                "fmi2SetContinuousStates",
                self.plant,
            );
            ok(fmu::fmi2EnterEventMode(c), "fmi2EnterEventMode", self.plant);
            let status = fmu::fmi2NewDiscreteStates(c, &mut info);
            assert!(
                status <= fmi2Status::fmi2Warning,
                "{:?}",
                self.plant.messages()
            );
            if info.valuesOfContinuousStatesChanged == fmi2True {
                ok(
                    fmu::fmi2GetContinuousStates(c, self.x.as_mut_ptr(), NX),
                    "fmi2GetContinuousStates",
                    self.plant,
                );
            }
            if info.terminateSimulation == fmi2False {
                ok(
                    fmu::fmi2EnterContinuousTimeMode(c),
                    "fmi2EnterContinuousTimeMode",
                    self.plant,
                );
            }
        }
        info.terminateSimulation == fmi2True
    }
}

/// An ME instance initialized and in continuous-time mode, with its initial states.
fn started(plant: &Plant) -> Solver<'_> {
    plant.init();
    let c = plant.c;
    let mut info = fmi2EventInfo::default();
    let mut x = vec![f64::NAN; NX];
    unsafe {
        ok(
            fmu::fmi2NewDiscreteStates(c, &mut info),
            "fmi2NewDiscreteStates",
            plant,
        );
        assert_eq!(info.terminateSimulation, fmi2False);
        ok(
            fmu::fmi2EnterContinuousTimeMode(c),
            "fmi2EnterContinuousTimeMode",
            plant,
        );
        ok(
            fmu::fmi2GetContinuousStates(c, x.as_mut_ptr(), NX),
            "fmi2GetContinuousStates",
            plant,
        );
    }
    Solver { plant, t: 0.0, x }
}

#[test]
fn free_fall_touches_down_at_the_analytic_time_under_a_foreign_solver() {
    // GIVEN the default plant at 800 m, engines off, as a Model Exchange instance
    let plant = Plant::model_exchange();
    let mut solver = started(&plant);
    assert_eq!(
        solver.x[1], 800.0,
        "state 2 is the altitude of the flat model"
    );
    // WHEN the solver runs in 0.01 s steps until the FMU ends the run
    let mut terminated = false;
    while !terminated {
        terminated = solver.step(0.01);
        if !terminated {
            // THEN the output follows 800 - 0.81 t^2 (RK4 is exact on a parabola)
            let t = solver.t;
            assert!((plant.get("r_nue[2]") - (800.0 - 0.5 * G * t * t)).abs() < 1e-9);
        }
        assert!(solver.t < 40.0, "no touchdown");
    }
    // AND the touchdown is at sqrt(800 / 0.81) = 31.42697 s, frozen in the outputs
    let exact = (800.0 / (0.5 * G)).sqrt();
    assert!((plant.get("touchdown_time") - exact).abs() < 1e-9);
    assert!((plant.get("touchdown_v_nue[2]") + G * exact).abs() < 1e-8);
    assert!(plant.get_boolean("touchdown"));
}

#[test]
fn model_exchange_matches_co_simulation_under_thrust_and_torque() {
    // GIVEN the same plant as a CS and as an ME instance, tumbling under constant commands
    let cs = Plant::new();
    let me = Plant::model_exchange();
    for p in [&cs, &me] {
        p.enter_init();
        p.set("omega0_body[1]", 0.3);
        p.set("omega0_body[3]", -0.2);
        p.set("r0_nue[2]", 5000.0);
        p.set("thrust_cmd", 1400.0);
        p.set("torque_cmd_body[2]", 40.0);
        ok(p.exit_init(), "exit", p);
    }
    let mut solver = {
        let c = me.c;
        let mut info = fmi2EventInfo::default();
        let mut x = vec![f64::NAN; NX];
        unsafe {
            ok(fmu::fmi2NewDiscreteStates(c, &mut info), "new", &me);
            ok(fmu::fmi2EnterContinuousTimeMode(c), "ct", &me);
            ok(
                fmu::fmi2GetContinuousStates(c, x.as_mut_ptr(), NX),
                "x",
                &me,
            );
        }
        Solver {
            plant: &me,
            t: 0.0,
            x,
        }
    };
    // WHEN both run 5 s at 0.01 s
    for k in 0..500 {
        assert_eq!(cs.step(k as f64 * 0.01, 0.01), fmi2Status::fmi2OK);
        assert!(!solver.step(0.01));
    }
    // THEN the outputs agree (the same RK4 method, the ME one without renormalisation)
    for name in [
        "r_nue[1]",
        "r_nue[2]",
        "v_nue[2]",
        "q_body_to_nue[1]",
        "q_body_to_nue[2]",
        "q_body_to_nue[4]",
        "omega_body[1]",
        "omega_body[2]",
        "mass",
    ] {
        let (a, b) = (cs.get(name), me.get(name));
        assert!(
            (a - b).abs() <= 1e-9 * (1.0 + a.abs()),
            "{name}: CS {a} vs ME {b}"
        );
    }
}

#[test]
fn bad_calls_are_refused_with_a_log_line_and_change_nothing() {
    let plant = Plant::model_exchange();
    let mut solver = started(&plant);
    let c = plant.c;
    let before = solver.x.clone();
    unsafe {
        // a state vector of the wrong length
        assert_eq!(
            fmu::fmi2SetContinuousStates(c, before.as_ptr(), NX - 1),
            fmi2Status::fmi2Error
        );
        // a non-finite state
        let mut bad = before.clone();
        bad[3] = f64::NAN;
        assert_eq!(
            fmu::fmi2SetContinuousStates(c, bad.as_ptr(), NX),
            fmi2Status::fmi2Error
        );
        // a Co-Simulation step on a Model Exchange instance
        assert_eq!(
            fmu::fmi2DoStep(c, 0.0, 0.1, fmi2True),
            fmi2Status::fmi2Error
        );
        let mut x = vec![0.0; NX];
        ok(
            fmu::fmi2GetContinuousStates(c, x.as_mut_ptr(), NX),
            "x",
            &plant,
        );
        assert_eq!(x, before, "refusals change nothing");
    }
    let log = plant.messages().join("\n");
    assert!(
        log.contains("fmi2SetContinuousStates: 17 states given, LanderPlant has 18"),
        "{log}"
    );
    assert!(log.contains("state 3 is NaN: not finite"), "{log}");
    assert!(
        log.contains("fmi2DoStep: illegal call in state ContinuousTimeMode"),
        "{log}"
    );
    // and the instance still works
    assert!(!solver.step(0.01));
}

#[test]
fn a_co_simulation_instance_refuses_the_model_exchange_functions() {
    let plant = Plant::new();
    plant.init();
    let x = [0.0; NX];
    unsafe {
        assert_eq!(
            fmu::fmi2SetContinuousStates(plant.c, x.as_ptr(), NX),
            fmi2Status::fmi2Error
        );
        assert_eq!(fmu::fmi2EnterEventMode(plant.c), fmi2Status::fmi2Error);
    }
    assert!(plant
        .messages()
        .iter()
        .any(|m| m.contains("fmi2SetContinuousStates: illegal call in state StepComplete")));
}
