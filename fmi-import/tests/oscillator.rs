//! The loader driving the export layer's test model, `Oscillator.fmu`, through the C ABI:
//! x'' = -k x - c x' + u, checked against the closed-form solution.
// std's transcendental functions here are a reference independent of the libm the model uses.
#![allow(clippy::disallowed_methods)]
use crate::common::{oscillator_fmu, unzip_to};
use fmi_import::{CallError, Failure, Fmu, Instance, Status, StepStatus, Success};
use tempfile::TempDir;

const STEP_S: f64 = 0.01;

#[derive(Clone, Copy)]
struct Case {
    x0: f64,
    k: f64,
    c: f64,
    u: f64,
}

impl Case {
    /// Closed-form (x, v) of the under-damped oscillator started at rest from `x0`:
    /// with y = x - u/k, y(t) = e^{-a t} (y0 cos wd t + (a y0 / wd) sin wd t), a = c/2,
    /// wd = sqrt(k - a^2); v is its derivative, e^{-a t} (-(k y0 / wd) sin wd t).
    fn analytic(self, t: f64) -> (f64, f64) {
        let a = self.c / 2.0;
        let wd = (self.k - a * a).sqrt();
        let y0 = self.x0 - self.u / self.k;
        let decay = (-a * t).exp();
        let (sin, cos) = (wd * t).sin_cos();
        let y = decay * (y0 * cos + a * y0 / wd * sin);
        let v = decay * (-(self.k * y0) / wd * sin);
        (y + self.u / self.k, v)
    }

    fn start(self, fmu: &Fmu, name: &str) -> Instance {
        let mut instance = fmu.instantiate(name, true).expect("instantiate");
        instance.setup_experiment(None, 0.0, None).unwrap();
        instance.enter_initialization_mode().unwrap();
        instance.set_real_by_name("x0", self.x0).unwrap();
        instance.set_real_by_name("k", self.k).unwrap();
        instance.set_real_by_name("c", self.c).unwrap();
        instance.set_real_by_name("u", self.u).unwrap();
        instance.exit_initialization_mode().unwrap();
        instance
    }
}

/// Steps `steps` times from `first_step` and returns (x, v) after each step.
fn run(instance: &mut Instance, first_step: u32, steps: u32) -> Vec<(f64, f64)> {
    let x = instance.variable("x").unwrap().value_reference;
    let v = instance.variable("v").unwrap().value_reference;
    (first_step..first_step + steps)
        .map(|step| {
            // Time from the step counter, as the master does, never accumulated.
            let t = f64::from(step) * STEP_S;
            let status = instance.do_step(t, STEP_S).unwrap();
            assert_eq!(status, StepStatus::Complete(Success::Ok));
            let mut xv = [0.0; 2];
            instance.get_real(&[x, v], &mut xv).unwrap();
            (xv[0], xv[1])
        })
        .collect()
}

fn assert_matches_analytic(fmu: &Fmu, case: Case) {
    let mut instance = case.start(fmu, "analytic");
    let trajectory = run(&mut instance, 0, 300);
    for (step, (x, v)) in trajectory.into_iter().enumerate() {
        let t = (step + 1) as f64 * STEP_S;
        let (x_exact, v_exact) = case.analytic(t);
        // RK4 sub-steps leave errors far below 1e-6 over 3 s for these frequencies.
        assert!((x - x_exact).abs() < 1e-6, "x({t}) = {x}, exact {x_exact}");
        assert!((v - v_exact).abs() < 1e-6, "v({t}) = {v}, exact {v_exact}");
    }
    assert_eq!(instance.get_integer_by_name("step_count").unwrap(), 300);
}

const UNDAMPED: Case = Case {
    x0: 1.0,
    k: 4.0,
    c: 0.0,
    u: 0.0,
};
const DAMPED_FORCED: Case = Case {
    x0: -0.5,
    k: 9.0,
    c: 0.6,
    u: 1.8,
};

#[test]
fn the_zipped_fmu_follows_the_closed_form_solution() {
    let file = oscillator_fmu();
    let fmu = Fmu::load(&file.path).unwrap();
    assert_eq!(
        fmu.model_description().co_simulation_identifier(),
        Some("Oscillator")
    );
    assert_matches_analytic(&fmu, UNDAMPED);
    assert_matches_analytic(&fmu, DAMPED_FORCED);
}

#[test]
fn the_unpacked_fmu_follows_the_closed_form_solution() {
    let file = oscillator_fmu();
    let dir = TempDir::new().unwrap();
    unzip_to(&file.path, dir.path());
    let fmu = Fmu::load(dir.path()).unwrap();
    assert_eq!(fmu.unpacked_dir(), dir.path());
    assert_matches_analytic(&fmu, DAMPED_FORCED);
}

fn bits(trajectory: &[(f64, f64)]) -> Vec<(u64, u64)> {
    trajectory
        .iter()
        .map(|(x, v)| (x.to_bits(), v.to_bits()))
        .collect()
}

#[test]
fn a_restored_state_continues_bit_for_bit() {
    let fmu = Fmu::load(oscillator_fmu().path).unwrap();
    let mut instance = DAMPED_FORCED.start(&fmu, "restore");
    run(&mut instance, 0, 100);
    let saved = instance.get_fmu_state().unwrap();
    let first = run(&mut instance, 100, 150);

    instance.set_fmu_state(&saved).unwrap();
    let again = run(&mut instance, 100, 150);
    assert_eq!(bits(&first), bits(&again));

    // Serialized, then continued in a second instance.
    let bytes = instance.serialize_fmu_state(&saved).unwrap();
    let mut other = UNDAMPED.start(&fmu, "other");
    let restored = other.deserialize_fmu_state(&bytes).unwrap();
    other.set_fmu_state(&restored).unwrap();
    assert_eq!(bits(&first), bits(&run(&mut other, 100, 150)));
    instance.free_fmu_state(saved).unwrap();
}

#[test]
fn a_corrupted_serialized_state_is_refused_with_the_fmus_reason() {
    let fmu = Fmu::load(oscillator_fmu().path).unwrap();
    let mut instance = UNDAMPED.start(&fmu, "corrupt");
    let state = instance.get_fmu_state().unwrap();
    let mut bytes = instance.serialize_fmu_state(&state).unwrap();
    let last = bytes.len() - 1;
    bytes[last] ^= 0xff;
    let error = instance.deserialize_fmu_state(&bytes).unwrap_err();
    assert_eq!(error.status, Failure::Error);
    assert!(!error.log.0.is_empty(), "the refusal is explained: {error}");
}

#[test]
fn a_refused_parameter_arrives_through_the_logger_and_in_the_error() {
    let fmu = Fmu::load(oscillator_fmu().path).unwrap();
    let mut instance = UNDAMPED.start(&fmu, "refused");
    // k has min 0 in the model's table.
    let error = instance.set_real_by_name("k", -1.0).unwrap_err();
    let CallError::Fmi(fmi) = &error else {
        panic!("expected an FMI error, got {error:?}");
    };
    assert_eq!(fmi.status, Failure::Error);
    assert_eq!(fmi.function, "fmi2SetReal");
    let logged = fmi
        .log
        .0
        .iter()
        .find(|message| message.status == Status::Error)
        .unwrap_or_else(|| panic!("no error line in {error}"));
    assert!(
        logged.message.contains('k') && logged.message.contains("-1"),
        "{logged}"
    );
    assert_eq!(logged.instance_name, "refused");
    assert!(instance
        .log_messages()
        .iter()
        .any(|message| message == logged));
    assert!(error.to_string().contains(&logged.message));
}

#[test]
fn crossing_the_threshold_stops_the_step_at_the_crossing_time() {
    let fmu = Fmu::load(oscillator_fmu().path).unwrap();
    let mut instance = fmu.instantiate("threshold", false).unwrap();
    instance.setup_experiment(None, 0.0, None).unwrap();
    instance.enter_initialization_mode().unwrap();
    instance.set_real_by_name("x0", 1.0).unwrap();
    instance.set_real_by_name("k", 4.0).unwrap();
    instance.set_real_by_name("c", 0.0).unwrap();
    instance
        .set_boolean_by_name("stop_at_threshold", true)
        .unwrap();
    instance.set_real_by_name("threshold", 0.5).unwrap();
    instance.exit_initialization_mode().unwrap();

    // x = cos 2t reaches 0.5 at t = pi/6.
    let crossing = std::f64::consts::FRAC_PI_6;
    for step in 0.. {
        let t = f64::from(step) * STEP_S;
        match instance.do_step(t, STEP_S).unwrap() {
            StepStatus::Complete(_) => assert!(t + STEP_S < crossing, "no stop by t = {t}"),
            other @ StepStatus::Terminated { .. } => panic!("an FMI 2.0 step: {other:?}"),
            StepStatus::Discarded {
                last_successful_time,
                terminated,
            } => {
                assert!(terminated);
                assert!((t..=t + STEP_S).contains(&last_successful_time));
                assert!(
                    t <= crossing && crossing <= t + STEP_S,
                    "stopped in [{t}, {}]",
                    t + STEP_S
                );
                assert!(
                    (last_successful_time - crossing).abs() < 1e-6,
                    "{last_successful_time}"
                );
                assert_eq!(
                    instance.last_successful_time().unwrap(),
                    last_successful_time
                );
                assert!(instance.terminated().unwrap());
                break;
            }
        }
    }
}

#[test]
fn instances_on_two_threads_match_a_serial_run() {
    let fmu = Fmu::load(oscillator_fmu().path).unwrap();
    let serial = bits(&run(&mut DAMPED_FORCED.start(&fmu, "serial"), 0, 500));
    let workers: Vec<_> = (0..2)
        .map(|worker| {
            let mut instance = DAMPED_FORCED.start(&fmu, &format!("worker{worker}"));
            std::thread::spawn(move || bits(&run(&mut instance, 0, 500)))
        })
        .collect();
    for worker in workers {
        assert_eq!(worker.join().unwrap(), serial);
    }
}
