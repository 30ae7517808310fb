//! A hostile or merely foreign Model Exchange master, through the C functions of FMI 2.0 and
//! FMI 3.0: a state vector the equations cannot evaluate is refused by name and changes
//! nothing; the states an ordinary integrator (explicit Euler, RK4) leaves, and a mass just
//! past the dry mass, are states the instance accepts back as FMU states.
#![allow(unsafe_code)]
use crate::common;

use fmi3_export::ffi::*;
use fmi_testkit::fmi2::*;
use fmi_testkit::{fmi2_me_functions, MeSolver};
use fmu_plant as fmu;
use std::ffi::{c_void, CStr, CString};
use std::sync::Mutex;

const NX: usize = 18;
const NZ: usize = 2;
/// Where the elements sit in the state vector.
const Q: usize = 6;
const OMEGA: usize = 10;
const MASS: usize = 13;
const THRUST_LAG: usize = 14;

/// What a master needs of a Model Exchange instance, FMI version aside.
trait Me {
    fn set_time(&self, t: f64);
    /// Whether `fmi*SetContinuousStates` answered OK.
    fn set_states(&self, x: &[f64]) -> bool;
    fn states(&self) -> Vec<f64>;
    /// The derivatives, or `None` when the call did not answer OK.
    fn derivatives(&self) -> Option<Vec<f64>>;
    fn indicators(&self) -> Vec<f64>;
    fn completed_step(&self);
    fn log(&self) -> String;
    fn clear_log(&self);
    /// Get, set, serialize, deserialize and set the FMU state: the first refusal's log.
    fn round_trip(&self) -> Result<(), String>;
}

// ---- FMI 2.0 ----

struct Me2(MeSolver);

fn me2(settings: &[(&str, f64)]) -> Me2 {
    me2_with(settings, &[])
}

/// An FMI 2.0 ME instance with these Reals and Integers set in initialization.
fn me2_with(reals: &[(&str, f64)], integers: &[(&str, i32)]) -> Me2 {
    let guid = fmi2_export::guid::<fmu::LanderPlant>();
    let mut me = MeSolver::instantiate(
        &common::FUNCTIONS,
        fmi2_me_functions!(fmu_plant),
        &guid,
        NX,
        NZ,
    );
    for (name, value) in reals {
        assert_eq!(me.instance.set_real(common::vr(name), *value), fmi2OK);
    }
    for (name, value) in integers {
        assert_eq!(me.instance.set_integer(common::vr(name), *value), fmi2OK);
    }
    me.start();
    Me2(me)
}

impl Me for Me2 {
    fn set_time(&self, t: f64) {
        // SAFETY: a live instance.
        assert_eq!(
            unsafe { fmu::fmi2SetTime(self.0.instance.component(), t) },
            fmi2OK
        );
    }

    fn set_states(&self, x: &[f64]) -> bool {
        let c = self.0.instance.component();
        // SAFETY: a live instance, x.len() values.
        unsafe { fmu::fmi2SetContinuousStates(c, x.as_ptr(), x.len()) == fmi2OK }
    }

    fn states(&self) -> Vec<f64> {
        let mut x = vec![f64::NAN; NX];
        let c = self.0.instance.component();
        // SAFETY: as above.
        let status = unsafe { fmu::fmi2GetContinuousStates(c, x.as_mut_ptr(), NX) };
        assert_eq!(status, fmi2OK, "{}", self.log());
        x
    }

    fn derivatives(&self) -> Option<Vec<f64>> {
        let mut dx = vec![f64::NAN; NX];
        let c = self.0.instance.component();
        // SAFETY: as above.
        let status = unsafe { fmu::fmi2GetDerivatives(c, dx.as_mut_ptr(), NX) };
        (status == fmi2OK).then_some(dx)
    }

    fn indicators(&self) -> Vec<f64> {
        let mut z = vec![f64::NAN; NZ];
        let c = self.0.instance.component();
        // SAFETY: as above.
        let status = unsafe { fmu::fmi2GetEventIndicators(c, z.as_mut_ptr(), NZ) };
        assert_eq!(status, fmi2OK, "{}", self.log());
        z
    }

    fn completed_step(&self) {
        let (mut enter, mut terminate) = (fmi2False, fmi2False);
        let c = self.0.instance.component();
        // SAFETY: as above, valid out-parameters.
        let status =
            unsafe { fmu::fmi2CompletedIntegratorStep(c, fmi2True, &mut enter, &mut terminate) };
        assert_eq!(status, fmi2OK, "{}", self.log());
        assert_eq!((enter, terminate), (fmi2False, fmi2False));
    }

    fn log(&self) -> String {
        self.0.instance.messages().join("\n")
    }

    fn clear_log(&self) {
        self.0.instance.clear_log();
    }

    fn round_trip(&self) -> Result<(), String> {
        let instance = &self.0.instance;
        let state = instance.get_state();
        let refused = |what: &str| Err(format!("{what}: {}", self.log()));
        if instance.set_state(state) != fmi2OK {
            return refused("fmi2SetFMUstate");
        }
        let bytes = instance.serialize(state);
        assert_eq!(instance.free_state(state), fmi2OK);
        let (status, restored) = instance.deserialize(&bytes);
        if status != fmi2OK {
            return refused("fmi2DeSerializeFMUstate");
        }
        let status = instance.set_state(restored);
        assert_eq!(instance.free_state(restored), fmi2OK);
        if status != fmi2OK {
            return refused("fmi2SetFMUstate of the deserialized state");
        }
        Ok(())
    }
}

// ---- FMI 3.0 ----

/// What `instanceEnvironment` points to: every message the FMU logged.
#[derive(Default)]
struct Sink(Mutex<Vec<String>>);

unsafe extern "C" fn record(
    environment: fmi3InstanceEnvironment,
    _status: fmi3Status,
    _category: fmi3String,
    message: fmi3String,
) {
    // SAFETY: the environment is our Sink, the message a NUL-terminated string.
    let sink = unsafe { &*(environment as *const Sink) };
    let text = unsafe { CStr::from_ptr(message) }.to_string_lossy();
    sink.0.lock().unwrap().push(text.into_owned());
}

struct Me3 {
    c: fmi3Instance,
    sink: Box<Sink>,
}

impl Drop for Me3 {
    fn drop(&mut self) {
        // SAFETY: created by instantiate, freed once.
        unsafe { fmu::fmi3FreeInstance(self.c) };
    }
}

fn me3(settings: &[(&str, f64)]) -> Me3 {
    let sink = Box::<Sink>::default();
    let token = CString::new(fmi3_export::instantiation_token::<fmu::LanderPlant>()).unwrap();
    // SAFETY: valid strings; the sink outlives the instance.
    let c = unsafe {
        fmu::fmi3InstantiateModelExchange(
            c"plant".as_ptr(),
            token.as_ptr(),
            std::ptr::null(),
            false,
            false,
            &*sink as *const Sink as *mut c_void,
            Some(record),
        )
    };
    assert!(!c.is_null(), "{:?}", sink.0.lock().unwrap());
    let me = Me3 { c, sink };
    // SAFETY: a live instance; one value per scalar reference.
    unsafe {
        assert_eq!(
            fmu::fmi3EnterInitializationMode(c, false, 0.0, 0.0, false, 0.0),
            fmi3OK
        );
        for (name, value) in settings {
            let (base, element) = match name.split_once('[') {
                Some((base, rest)) => (base, rest.trim_end_matches(']').parse::<usize>().unwrap()),
                None => (*name, 1),
            };
            use fmi_model::Model;
            let declaration = fmu::LanderPlant::declarations()
                .iter()
                .find(|d| d.name == base)
                .unwrap();
            let mut values = vec![0.0; declaration.shape().len()];
            let vr = declaration.value_reference;
            let status = fmu::fmi3GetFloat64(c, &vr, 1, values.as_mut_ptr(), values.len());
            assert_eq!(status, fmi3OK, "{}", me.log());
            values[element - 1] = *value;
            let status = fmu::fmi3SetFloat64(c, &vr, 1, values.as_ptr(), values.len());
            assert_eq!(status, fmi3OK, "{}", me.log());
        }
        assert_eq!(fmu::fmi3ExitInitializationMode(c), fmi3OK, "{}", me.log());
        assert_eq!(fmu::fmi3EnterContinuousTimeMode(c), fmi3OK, "{}", me.log());
    }
    me
}

impl Me for Me3 {
    fn set_time(&self, t: f64) {
        // SAFETY: a live instance.
        assert_eq!(unsafe { fmu::fmi3SetTime(self.c, t) }, fmi3OK);
    }

    fn set_states(&self, x: &[f64]) -> bool {
        // SAFETY: a live instance, x.len() values.
        unsafe { fmu::fmi3SetContinuousStates(self.c, x.as_ptr(), x.len()) == fmi3OK }
    }

    fn states(&self) -> Vec<f64> {
        let mut x = vec![f64::NAN; NX];
        // SAFETY: as above.
        let status = unsafe { fmu::fmi3GetContinuousStates(self.c, x.as_mut_ptr(), NX) };
        assert_eq!(status, fmi3OK, "{}", self.log());
        x
    }

    fn derivatives(&self) -> Option<Vec<f64>> {
        let mut dx = vec![f64::NAN; NX];
        // SAFETY: as above.
        let status = unsafe { fmu::fmi3GetContinuousStateDerivatives(self.c, dx.as_mut_ptr(), NX) };
        (status == fmi3OK).then_some(dx)
    }

    fn indicators(&self) -> Vec<f64> {
        let mut z = vec![f64::NAN; NZ];
        // SAFETY: as above.
        let status = unsafe { fmu::fmi3GetEventIndicators(self.c, z.as_mut_ptr(), NZ) };
        assert_eq!(status, fmi3OK, "{}", self.log());
        z
    }

    fn completed_step(&self) {
        let (mut enter, mut terminate) = (true, true);
        // SAFETY: as above, valid out-parameters.
        let status =
            unsafe { fmu::fmi3CompletedIntegratorStep(self.c, true, &mut enter, &mut terminate) };
        assert_eq!(status, fmi3OK, "{}", self.log());
        assert_eq!((enter, terminate), (false, false));
    }

    fn log(&self) -> String {
        self.sink.0.lock().unwrap().join("\n")
    }

    fn clear_log(&self) {
        self.sink.0.lock().unwrap().clear();
    }

    fn round_trip(&self) -> Result<(), String> {
        let refused = |what: &str| Err(format!("{what}: {}", self.log()));
        let mut state: fmi3FMUState = std::ptr::null_mut();
        // SAFETY: a live instance; states from its own get, buffers of the sizes told.
        unsafe {
            assert_eq!(fmu::fmi3GetFMUState(self.c, &mut state), fmi3OK);
            if fmu::fmi3SetFMUState(self.c, state) != fmi3OK {
                return refused("fmi3SetFMUState");
            }
            let mut size = 0;
            assert_eq!(
                fmu::fmi3SerializedFMUStateSize(self.c, state, &mut size),
                fmi3OK
            );
            let mut bytes = vec![0u8; size];
            assert_eq!(
                fmu::fmi3SerializeFMUState(self.c, state, bytes.as_mut_ptr(), size),
                fmi3OK
            );
            assert_eq!(fmu::fmi3FreeFMUState(self.c, &mut state), fmi3OK);
            let mut restored: fmi3FMUState = std::ptr::null_mut();
            if fmu::fmi3DeserializeFMUState(self.c, bytes.as_ptr(), size, &mut restored) != fmi3OK {
                return refused("fmi3DeserializeFMUState");
            }
            let status = fmu::fmi3SetFMUState(self.c, restored);
            assert_eq!(fmu::fmi3FreeFMUState(self.c, &mut restored), fmi3OK);
            if status != fmi3OK {
                return refused("fmi3SetFMUState of the deserialized state");
            }
        }
        Ok(())
    }
}

// ---- the checks, on either version ----

fn finite(values: &[f64]) -> bool {
    values.iter().all(|v| v.is_finite())
}

/// Each `(element, value, name)` edit of the instance's valid state is refused, naming
/// `name`, and leaves the state as it was; the valid state is then accepted again and gives
/// finite derivatives, indicators and outputs.
fn hostile_states_are_refused_by_name(me: &dyn Me, cases: &[(&[(usize, f64)], &str)]) {
    let valid = me.states();
    assert!(finite(&me.derivatives().expect("valid state")));
    for (edits, name) in cases {
        let mut hostile = valid.clone();
        for (i, v) in edits.iter() {
            hostile[*i] = *v;
        }
        me.clear_log();
        // WHEN the master sets the hostile vector
        let accepted = me.set_states(&hostile);
        // THEN it is refused with a line naming the element
        let log = me.log();
        assert!(
            !accepted,
            "{edits:?} accepted; derivatives {:?}",
            me.derivatives()
        );
        assert!(log.contains(name), "{edits:?}: {name} not in {log}");
        // AND the state is the one before
        assert_eq!(me.states(), valid, "{edits:?}");
        // AND the instance takes the valid state again, with finite values
        assert!(me.set_states(&valid), "{}", me.log());
        let dx = me.derivatives().unwrap_or_else(|| panic!("{}", me.log()));
        assert!(finite(&dx), "{edits:?}: {dx:?}");
        assert!(finite(&me.indicators()), "{edits:?}");
    }
}

/// The flat plant's hostile vectors: a zero or denormal quaternion, a huge one, a body rate
/// whose gyroscopic term overflows, positions and velocities beyond any physics, a mass of
/// zero or below, a thrust lag state far past the engines.
const FLAT_CASES: &[(&[(usize, f64)], &str)] = &[
    (
        &[(Q, 0.0), (Q + 1, 0.0), (Q + 2, 0.0), (Q + 3, 0.0)],
        "attitude_state",
    ),
    (
        &[(Q, 5e-324), (Q + 1, 0.0), (Q + 2, 0.0), (Q + 3, 0.0)],
        "attitude_state",
    ),
    (
        &[(Q, 1e-200), (Q + 1, 1e-200), (Q + 2, 0.0), (Q + 3, 0.0)],
        "attitude_state",
    ),
    (&[(Q + 2, 1e200)], "attitude_state"),
    (&[(OMEGA + 1, 1e200)], "omega_body[2]"),
    (&[(OMEGA, 1e160), (OMEGA + 2, -1e160)], "omega_body[1]"),
    (&[(1, 1e300)], "translation_state[2]"),
    (&[(4, -1e200)], "translation_state[5]"),
    (&[(MASS, 0.0)], "mass"),
    (&[(MASS, -900.0)], "mass"),
    (&[(THRUST_LAG, 1e300)], "thrust_lag_state"),
];

/// The spherical plant's: the Moon's centre, beyond the pole, faster than light.
const SPHERICAL_CASES: &[(&[(usize, f64)], &str)] = &[
    (&[(0, 0.0)], "translation_state[1]"),
    (&[(0, 1e-300)], "translation_state[1]"),
    (&[(2, 2.0)], "translation_state[3]"),
    (&[(3, 1e200), (4, 1e200)], "translation_state[4]"),
    (&[(5, 1e160)], "translation_state[6]"),
];

#[test]
fn fmi2_hostile_state_vectors_are_refused_by_name_and_change_nothing() {
    hostile_states_are_refused_by_name(&me2(&[("omega0_body[1]", 0.2)]), FLAT_CASES);
}

#[test]
fn fmi2_hostile_spherical_state_vectors_are_refused_by_name() {
    let me = me2_with(&[], &[("translation_model", 2)]);
    hostile_states_are_refused_by_name(&me, SPHERICAL_CASES);
}

#[test]
fn fmi3_hostile_state_vectors_are_refused_by_name_and_change_nothing() {
    hostile_states_are_refused_by_name(&me3(&[("omega0_body[1]", 0.2)]), FLAT_CASES);
}

/// Explicit Euler or classical RK4 at a fixed step over the ME equations, as a foreign
/// master runs them: every stage set, every step completed.
#[derive(Clone, Copy, Debug)]
enum Method {
    Euler,
    Rk4,
}

fn integrate(me: &dyn Me, method: Method, h: f64, duration: f64) {
    let mut x = me.states();
    let mut t = 0.0;
    let derivative_at = |t: f64, x: &[f64]| -> Vec<f64> {
        me.set_time(t);
        assert!(me.set_states(x), "t = {t}: {}", me.log());
        me.derivatives()
            .unwrap_or_else(|| panic!("t = {t}: {}", me.log()))
    };
    let along = |x: &[f64], k: &[f64], s: f64| -> Vec<f64> {
        x.iter().zip(k).map(|(a, b)| a + s * b).collect()
    };
    let steps = (duration / h).round() as usize;
    for _ in 0..steps {
        x = match method {
            Method::Euler => along(&x, &derivative_at(t, &x), h),
            Method::Rk4 => {
                let k1 = derivative_at(t, &x);
                let k2 = derivative_at(t + h / 2.0, &along(&x, &k1, h / 2.0));
                let k3 = derivative_at(t + h / 2.0, &along(&x, &k2, h / 2.0));
                let k4 = derivative_at(t + h, &along(&x, &k3, h));
                (0..x.len())
                    .map(|i| x[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]))
                    .collect()
            }
        };
        t += h;
        me.set_time(t);
        assert!(me.set_states(&x), "t = {t}: {}", me.log());
        me.completed_step();
        assert!(me.indicators().iter().all(|z| *z > 0.0), "an event at {t}");
    }
}

/// A lander tumbling at about 1.4 rad/s under thrust, 5 km up: 30 s in 0.1 s steps.
const TUMBLING: &[(&str, f64)] = &[
    ("omega0_body[1]", 1.0),
    ("omega0_body[2]", 0.5),
    ("omega0_body[3]", -0.8),
    ("r0_nue[2]", 5000.0),
    ("thrust_cmd", 1400.0),
];

fn norm_error(x: &[f64]) -> f64 {
    (x[Q..Q + 4].iter().map(|v| v * v).sum::<f64>().sqrt() - 1.0).abs()
}

fn a_foreign_run_is_a_state_the_instance_restores(me: &dyn Me, method: Method) {
    // GIVEN 30 s of the ME equations under a foreign fixed-step integrator
    integrate(me, method, 0.1, 30.0);
    let x = me.states();
    let drift = norm_error(&x);
    assert!(
        drift > 1e-9,
        "{method:?}: |q| - 1 = {drift}: the run does not drift"
    );
    // WHEN the master saves and restores the instance, in memory and serialized
    // THEN every step of it is accepted and the state is the one it saved
    if let Err(log) = me.round_trip() {
        panic!("{method:?}, |q| - 1 = {drift:e}: {log}");
    }
    assert_eq!(me.states(), x);
    assert!(finite(&me.derivatives().unwrap()));
}

#[test]
fn fmi2_an_explicit_euler_run_restores() {
    a_foreign_run_is_a_state_the_instance_restores(&me2(TUMBLING), Method::Euler);
}

#[test]
fn fmi2_an_rk4_run_restores() {
    a_foreign_run_is_a_state_the_instance_restores(&me2(TUMBLING), Method::Rk4);
}

#[test]
fn fmi3_an_explicit_euler_run_restores() {
    a_foreign_run_is_a_state_the_instance_restores(&me3(TUMBLING), Method::Euler);
}

#[test]
fn fmi3_an_rk4_run_restores() {
    a_foreign_run_is_a_state_the_instance_restores(&me3(TUMBLING), Method::Rk4);
}

/// The integrator stepped past the exhaustion event before its master located it: the
/// mass is a hair below the dry mass, the engines still on.
fn a_mass_just_below_dry_mass_is_accepted(me: &dyn Me) {
    let mut x = me.states();
    x[MASS] = 600.0 * (1.0 - 1e-6);
    assert!(me.set_states(&x), "{}", me.log());
    assert!(finite(&me.derivatives().unwrap()));
    assert!(
        me.indicators()[1] < 0.0,
        "the exhaustion indicator has crossed"
    );
    if let Err(log) = me.round_trip() {
        panic!("{log}");
    }
    assert_eq!(me.states(), x);
}

#[test]
fn fmi2_a_mass_just_below_dry_mass_is_accepted_and_restored() {
    a_mass_just_below_dry_mass_is_accepted(&me2(&[("thrust_cmd", 1400.0)]));
}

#[test]
fn fmi3_a_mass_just_below_dry_mass_is_accepted_and_restored() {
    a_mass_just_below_dry_mass_is_accepted(&me3(&[("thrust_cmd", 1400.0)]));
}
