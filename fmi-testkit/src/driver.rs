//! One driver for both FMI versions: what a test of a model's behaviour through the C ABI
//! needs, in words neither version owns ([`Status`], [`StepOutcome`]), so that one test
//! body runs as FMI 2.0 ([`Fmi2`]) and as FMI 3.0 ([`Fmi3`]). Where the versions differ by
//! standard (state names, a step that ends early), the test asks [`Driver::VERSION`] and
//! asserts each version's own behaviour.
// FMU states are opaque handles passed on to the FMU, which must refuse a bad one.
#![allow(clippy::not_unsafe_ptr_arg_deref)]
use crate::fmi3::{CoSimulationOptions, Fmi3Functions, Fmi3Instance};
use crate::functions::Fmi2Functions;
use crate::instance::Instance;
use crate::logger::{Record, TestLogger};
use fmi_abi::fmi2::*;
use fmi_abi::fmi3::{fmi3FMUState, fmi3Status};
pub use fmi_model::Interface;

/// The FMI version a driver speaks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Version {
    Fmi2,
    Fmi3,
}

impl Version {
    /// The prefix of the C function names: `"fmi2"` or `"fmi3"`.
    pub const fn prefix(self) -> &'static str {
        match self {
            Version::Fmi2 => "fmi2",
            Version::Fmi3 => "fmi3",
        }
    }
}

/// A status of either version (FMI 2.0 and 3.0 number them alike; `fmi2Pending` is FMI
/// 2.0's own).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Status {
    Ok,
    Warning,
    Discard,
    Error,
    Fatal,
    Pending,
    /// A value outside both enumerations.
    Invalid(i32),
}

impl Status {
    fn of(value: i32) -> Status {
        match value {
            0 => Status::Ok,
            1 => Status::Warning,
            2 => Status::Discard,
            3 => Status::Error,
            4 => Status::Fatal,
            5 => Status::Pending,
            other => Status::Invalid(other),
        }
    }

    /// OK or Warning: the call's results are valid.
    pub fn is_success(self) -> bool {
        matches!(self, Status::Ok | Status::Warning)
    }
}

impl From<fmi2Status> for Status {
    fn from(s: fmi2Status) -> Status {
        Status::of(s.0)
    }
}

impl From<fmi3Status> for Status {
    fn from(s: fmi3Status) -> Status {
        match s.0 {
            // fmi3Status has no Pending.
            5 => Status::Invalid(5),
            other => Status::of(other),
        }
    }
}

/// What a communication step reported, in either version's terms.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepOutcome {
    pub status: Status,
    /// The step ended before t + h: FMI 2.0 `fmi2Discard`; FMI 3.0 `earlyReturn`.
    pub ended_early: bool,
    /// The FMU asks to end the simulation: FMI 2.0 `fmi2Terminated` (asked after a
    /// discarded step); FMI 3.0 `terminateSimulation`.
    pub terminated: bool,
    /// FMI 2.0 `fmi2LastSuccessfulTime` (asked after a discarded step; t + h after a
    /// complete one); FMI 3.0 `lastSuccessfulTime`. NaN after a refused step.
    pub last_successful_time: f64,
    /// FMI 3.0 `eventHandlingNeeded` (always false in FMI 2.0).
    pub event_handling_needed: bool,
}

/// One instance of an FMU, driven through the C functions of one FMI version.
pub trait Driver: Sized {
    /// The function table the instance is created from.
    type Functions: 'static;
    /// An FMU state handle (`fmi2FMUstate`, `fmi3FMUState`).
    type FmuState: Copy + std::fmt::Debug;
    const VERSION: Version;

    /// Instantiates with a recording logger (FMI 3.0 Co-Simulation: no event mode, early
    /// return allowed); `Err` with what the FMU logged when it returns NULL.
    fn instantiate(
        functions: &Self::Functions,
        name: &str,
        token: &str,
        interface: Interface,
        logging_on: bool,
    ) -> Result<Self, Vec<Record>>;

    fn logger(&self) -> &TestLogger;

    /// Every logged message, in order.
    fn messages(&self) -> Vec<String> {
        self.logger().messages()
    }

    /// The last logged message ("" when none).
    fn last_message(&self) -> String {
        self.messages().pop().unwrap_or_default()
    }

    fn clear_log(&self) {
        self.logger().clear();
    }

    fn set_debug_logging(&self, on: bool) -> Status;

    /// SetDebugLogging for the named categories only (all of them when empty).
    fn set_debug_logging_categories(&self, on: bool, categories: &[&str]) -> Status;

    /// Into initialization mode at `start` (FMI 2.0: `fmi2SetupExperiment`, then
    /// `fmi2EnterInitializationMode`; the first status that is not OK).
    fn enter_initialization_mode(&self, start: f64, stop: Option<f64>) -> Status;
    fn exit_initialization_mode(&self) -> Status;

    /// Enter and exit initialization at t = 0, no stop time; panics unless both succeed.
    fn initialize(&self) {
        assert_eq!(
            self.enter_initialization_mode(0.0, None),
            Status::Ok,
            "{:?}",
            self.messages()
        );
        assert_eq!(
            self.exit_initialization_mode(),
            Status::Ok,
            "{:?}",
            self.messages()
        );
    }

    /// One communication step from `t` of `h`.
    fn step(&self, t: f64, h: f64) -> StepOutcome;
    fn terminate(&self) -> Status;
    fn reset(&self) -> Status;

    /// Scalar Reals (FMI 3.0: Float64, one value per reference).
    fn set_reals(&self, vrs: &[u32], values: &[f64]) -> Status;
    fn get_reals(&self, vrs: &[u32]) -> (Status, Vec<f64>);
    fn set_integers(&self, vrs: &[u32], values: &[i32]) -> Status;
    fn get_integers(&self, vrs: &[u32]) -> (Status, Vec<i32>);
    /// An enumeration (FMI 2.0: Integer; FMI 3.0: Int64).
    fn set_enumeration(&self, vr: u32, value: i64) -> Status;
    fn get_enumeration(&self, vr: u32) -> (Status, i64);
    fn set_booleans(&self, vrs: &[u32], values: &[bool]) -> Status;
    fn get_booleans(&self, vrs: &[u32]) -> (Status, Vec<bool>);
    fn set_string(&self, vr: u32, value: &str) -> Status;
    fn get_string(&self, vr: u32) -> (Status, Option<String>);

    /// The `n` elements of one Real declaration (FMI 2.0: the scalars numbered upwards from
    /// `vr`; FMI 3.0: one Float64 array).
    fn get_real_elements(&self, vr: u32, n: usize) -> (Status, Vec<f64>);
    /// Sets every element of one Real declaration (see [`get_real_elements`](Self::get_real_elements)).
    fn set_real_elements(&self, vr: u32, values: &[f64]) -> Status;

    fn set_real(&self, vr: u32, value: f64) -> Status {
        self.set_reals(&[vr], &[value])
    }

    /// One Real; panics unless the get succeeds.
    fn real(&self, vr: u32) -> f64 {
        let (status, values) = self.get_reals(&[vr]);
        assert!(status.is_success(), "{:?}", self.messages());
        values[0]
    }

    fn set_integer(&self, vr: u32, value: i32) -> Status {
        self.set_integers(&[vr], &[value])
    }

    /// One Integer; panics unless the get succeeds.
    fn integer(&self, vr: u32) -> i32 {
        let (status, values) = self.get_integers(&[vr]);
        assert!(status.is_success(), "{:?}", self.messages());
        values[0]
    }

    fn set_boolean(&self, vr: u32, value: bool) -> Status {
        self.set_booleans(&[vr], &[value])
    }

    /// One Boolean; panics unless the get succeeds.
    fn boolean(&self, vr: u32) -> bool {
        let (status, values) = self.get_booleans(&[vr]);
        assert!(status.is_success(), "{:?}", self.messages());
        values[0]
    }

    /// `J seed` through the version's directional derivative (FMI 2.0: one scalar per
    /// reference; FMI 3.0: every element of each array, serialized); `n_sensitivity`
    /// elements out.
    fn directional_derivative(
        &self,
        unknowns: &[u32],
        knowns: &[u32],
        seed: &[f64],
        n_sensitivity: usize,
    ) -> (Status, Vec<f64>);

    /// A new FMU state (null when refused) with the status.
    fn get_state(&self) -> (Status, Self::FmuState);
    fn set_state(&self, state: Self::FmuState) -> Status;
    fn free_state(&self, state: Self::FmuState) -> Status;
    /// The serialized state with the status of the failing call (or OK).
    fn serialize(&self, state: Self::FmuState) -> (Status, Vec<u8>);
    /// `bytes` deserialized into a new FMU state (null when refused), with the status.
    fn deserialize(&self, bytes: &[u8]) -> (Status, Self::FmuState);
    /// The null handle (to pass where a test wants it refused).
    fn null_state() -> Self::FmuState;
    fn is_null(state: Self::FmuState) -> bool;
}

/// `strings` as C strings and the pointers to them (valid while the first lives).
fn c_strings(strings: &[&str]) -> (Vec<std::ffi::CString>, Vec<*const std::os::raw::c_char>) {
    let owned: Vec<std::ffi::CString> = strings
        .iter()
        .map(|s| std::ffi::CString::new(*s).expect("no NUL in a category"))
        .collect();
    let pointers = owned.iter().map(|s| s.as_ptr()).collect();
    (owned, pointers)
}

/// FMI 2.0: the kit's [`Instance`].
pub type Fmi2 = Instance;
/// FMI 3.0: the kit's [`Fmi3Instance`].
pub type Fmi3 = Fmi3Instance;

impl Driver for Instance {
    type Functions = Fmi2Functions;
    type FmuState = fmi2FMUstate;
    const VERSION: Version = Version::Fmi2;

    fn instantiate(
        functions: &Fmi2Functions,
        name: &str,
        token: &str,
        interface: Interface,
        logging_on: bool,
    ) -> Result<Instance, Vec<Record>> {
        let fmu_type = match interface {
            Interface::CoSimulation => fmi2CoSimulation,
            Interface::ModelExchange => fmi2ModelExchange,
        };
        Instance::new_as(functions, name, token, logging_on, fmu_type)
    }

    fn logger(&self) -> &TestLogger {
        Instance::logger(self)
    }

    fn set_debug_logging(&self, on: bool) -> Status {
        let on = if on { fmi2True } else { fmi2False };
        // SAFETY: a live instance, no categories.
        unsafe { (self.functions().set_debug_logging)(self.component(), on, 0, std::ptr::null()) }
            .into()
    }

    fn set_debug_logging_categories(&self, on: bool, categories: &[&str]) -> Status {
        let on = if on { fmi2True } else { fmi2False };
        let (_owned, pointers) = c_strings(categories);
        // SAFETY: a live instance, `pointers.len()` NUL-terminated strings.
        unsafe {
            (self.functions().set_debug_logging)(
                self.component(),
                on,
                pointers.len(),
                pointers.as_ptr(),
            )
        }
        .into()
    }

    fn enter_initialization_mode(&self, start: f64, stop: Option<f64>) -> Status {
        let setup = self.setup_experiment(start, stop);
        if setup != fmi2OK {
            return setup.into();
        }
        Instance::enter_initialization_mode(self).into()
    }

    fn exit_initialization_mode(&self) -> Status {
        Instance::exit_initialization_mode(self).into()
    }

    fn step(&self, t: f64, h: f64) -> StepOutcome {
        let status = self.do_step(t, h);
        let (ended_early, terminated, last) = match status {
            s if s == fmi2Discard => (true, self.terminated(), self.last_successful_time()),
            s if s.is_success() => (false, false, t + h),
            _ => (false, false, f64::NAN),
        };
        StepOutcome {
            status: status.into(),
            ended_early,
            terminated,
            last_successful_time: last,
            event_handling_needed: false,
        }
    }

    fn terminate(&self) -> Status {
        Instance::terminate(self).into()
    }

    fn reset(&self) -> Status {
        Instance::reset(self).into()
    }

    fn set_reals(&self, vrs: &[u32], values: &[f64]) -> Status {
        Instance::set_reals(self, vrs, values).into()
    }

    fn get_reals(&self, vrs: &[u32]) -> (Status, Vec<f64>) {
        let (s, v) = Instance::get_reals(self, vrs);
        (s.into(), v)
    }

    fn get_real_elements(&self, vr: u32, n: usize) -> (Status, Vec<f64>) {
        let vrs: Vec<u32> = (vr..).take(n).collect();
        Driver::get_reals(self, &vrs)
    }

    fn set_real_elements(&self, vr: u32, values: &[f64]) -> Status {
        let vrs: Vec<u32> = (vr..).take(values.len()).collect();
        Driver::set_reals(self, &vrs, values)
    }

    fn set_integers(&self, vrs: &[u32], values: &[i32]) -> Status {
        Instance::set_integers(self, vrs, values).into()
    }

    fn get_integers(&self, vrs: &[u32]) -> (Status, Vec<i32>) {
        let (s, v) = Instance::get_integers(self, vrs);
        (s.into(), v)
    }

    fn set_enumeration(&self, vr: u32, value: i64) -> Status {
        match i32::try_from(value) {
            Ok(value) => Instance::set_integer(self, vr, value).into(),
            Err(_) => panic!("FMI 2.0 enumerations are Integers: {value} does not fit"),
        }
    }

    fn get_enumeration(&self, vr: u32) -> (Status, i64) {
        let (s, v) = Instance::get_integers(self, &[vr]);
        (s.into(), i64::from(v[0]))
    }

    fn set_booleans(&self, vrs: &[u32], values: &[bool]) -> Status {
        assert_eq!(vrs.len(), values.len());
        let values: Vec<fmi2Boolean> = values
            .iter()
            .map(|&b| if b { fmi2True } else { fmi2False })
            .collect();
        // SAFETY: arrays of the length passed.
        unsafe {
            (self.functions().set_boolean)(
                self.component(),
                vrs.as_ptr(),
                vrs.len(),
                values.as_ptr(),
            )
        }
        .into()
    }

    fn get_booleans(&self, vrs: &[u32]) -> (Status, Vec<bool>) {
        let mut values = vec![fmi2False; vrs.len()];
        // SAFETY: arrays of the length passed.
        let status = unsafe {
            (self.functions().get_boolean)(
                self.component(),
                vrs.as_ptr(),
                vrs.len(),
                values.as_mut_ptr(),
            )
        };
        (
            status.into(),
            values.iter().map(|&b| b != fmi2False).collect(),
        )
    }

    fn set_string(&self, vr: u32, value: &str) -> Status {
        Instance::set_string(self, vr, value).into()
    }

    fn get_string(&self, vr: u32) -> (Status, Option<String>) {
        let mut value: fmi2String = std::ptr::null();
        // SAFETY: one element each; the FMU keeps the string alive until its next call.
        let status = unsafe { (self.functions().get_string)(self.component(), &vr, 1, &mut value) };
        let text = (status.is_success() && !value.is_null()).then(|| {
            // SAFETY: non-null and NUL-terminated, per the standard.
            unsafe { std::ffi::CStr::from_ptr(value) }
                .to_string_lossy()
                .into_owned()
        });
        (status.into(), text)
    }

    fn directional_derivative(
        &self,
        unknowns: &[u32],
        knowns: &[u32],
        seed: &[f64],
        n_sensitivity: usize,
    ) -> (Status, Vec<f64>) {
        assert_eq!(
            n_sensitivity,
            unknowns.len(),
            "FMI 2.0: one value per unknown"
        );
        let (status, values) = Instance::directional_derivative(self, unknowns, knowns, seed);
        (status.into(), values)
    }

    fn get_state(&self) -> (Status, fmi2FMUstate) {
        let mut state: fmi2FMUstate = std::ptr::null_mut();
        // SAFETY: an out-pointer to a NULL state: the FMU allocates one.
        let status = unsafe { (self.functions().get_fmu_state)(self.component(), &mut state) };
        (status.into(), state)
    }

    fn set_state(&self, state: fmi2FMUstate) -> Status {
        Instance::set_state(self, state).into()
    }

    fn free_state(&self, state: fmi2FMUstate) -> Status {
        Instance::free_state(self, state).into()
    }

    fn serialize(&self, state: fmi2FMUstate) -> (Status, Vec<u8>) {
        let f = self.functions();
        let mut size = 0;
        // SAFETY: one out-element.
        let status = unsafe { (f.serialized_fmu_state_size)(self.component(), state, &mut size) };
        if status != fmi2OK {
            return (status.into(), Vec::new());
        }
        let mut bytes = vec![0u8; size];
        // SAFETY: a buffer of the announced size.
        let status = unsafe {
            (f.serialize_fmu_state)(self.component(), state, bytes.as_mut_ptr().cast(), size)
        };
        (status.into(), bytes)
    }

    fn deserialize(&self, bytes: &[u8]) -> (Status, fmi2FMUstate) {
        let (s, state) = Instance::deserialize(self, bytes);
        (s.into(), state)
    }

    fn null_state() -> fmi2FMUstate {
        std::ptr::null_mut()
    }

    fn is_null(state: fmi2FMUstate) -> bool {
        state.is_null()
    }
}

impl Driver for Fmi3Instance {
    type Functions = Fmi3Functions;
    type FmuState = fmi3FMUState;
    const VERSION: Version = Version::Fmi3;

    fn instantiate(
        functions: &Fmi3Functions,
        name: &str,
        token: &str,
        interface: Interface,
        logging_on: bool,
    ) -> Result<Fmi3Instance, Vec<Record>> {
        match interface {
            Interface::CoSimulation => Fmi3Instance::co_simulation(
                functions,
                name,
                token,
                CoSimulationOptions {
                    logging_on,
                    event_mode_used: false,
                    early_return_allowed: true,
                },
            ),
            Interface::ModelExchange => {
                Fmi3Instance::model_exchange(functions, name, token, logging_on)
            }
        }
    }

    fn logger(&self) -> &TestLogger {
        Fmi3Instance::logger(self)
    }

    fn set_debug_logging(&self, on: bool) -> Status {
        Fmi3Instance::set_debug_logging(self, on).into()
    }

    fn set_debug_logging_categories(&self, on: bool, categories: &[&str]) -> Status {
        let (_owned, pointers) = c_strings(categories);
        // SAFETY: a live instance, `pointers.len()` NUL-terminated strings.
        unsafe {
            (self.functions().set_debug_logging)(
                self.instance(),
                on,
                pointers.len(),
                pointers.as_ptr(),
            )
        }
        .into()
    }

    fn enter_initialization_mode(&self, start: f64, stop: Option<f64>) -> Status {
        Fmi3Instance::enter_initialization_mode(self, start, stop).into()
    }

    fn exit_initialization_mode(&self) -> Status {
        Fmi3Instance::exit_initialization_mode(self).into()
    }

    fn step(&self, t: f64, h: f64) -> StepOutcome {
        let s = self.do_step(t, h);
        let status = Status::from(s.status);
        // Out-arguments are defined only when the step returned OK or Warning (or Discard).
        let reported = matches!(status, Status::Ok | Status::Warning | Status::Discard);
        StepOutcome {
            status,
            ended_early: reported && s.early_return,
            terminated: reported && s.terminate_simulation,
            last_successful_time: if reported {
                s.last_successful_time
            } else {
                f64::NAN
            },
            event_handling_needed: reported && s.event_handling_needed,
        }
    }

    fn terminate(&self) -> Status {
        Fmi3Instance::terminate(self).into()
    }

    fn reset(&self) -> Status {
        Fmi3Instance::reset(self).into()
    }

    fn set_reals(&self, vrs: &[u32], values: &[f64]) -> Status {
        self.set_float64(vrs, values).into()
    }

    fn get_reals(&self, vrs: &[u32]) -> (Status, Vec<f64>) {
        let (s, v) = self.get_float64(vrs, vrs.len());
        (s.into(), v)
    }

    fn get_real_elements(&self, vr: u32, n: usize) -> (Status, Vec<f64>) {
        let (s, v) = self.get_float64(&[vr], n);
        (s.into(), v)
    }

    fn set_real_elements(&self, vr: u32, values: &[f64]) -> Status {
        self.set_float64(&[vr], values).into()
    }

    fn set_integers(&self, vrs: &[u32], values: &[i32]) -> Status {
        self.set_int32(vrs, values).into()
    }

    fn get_integers(&self, vrs: &[u32]) -> (Status, Vec<i32>) {
        let (s, v) = self.get_int32(vrs);
        (s.into(), v)
    }

    fn set_enumeration(&self, vr: u32, value: i64) -> Status {
        self.set_int64(&[vr], &[value]).into()
    }

    fn get_enumeration(&self, vr: u32) -> (Status, i64) {
        let (s, v) = self.get_int64(&[vr]);
        (s.into(), v[0])
    }

    fn set_booleans(&self, vrs: &[u32], values: &[bool]) -> Status {
        Fmi3Instance::set_booleans(self, vrs, values).into()
    }

    fn get_booleans(&self, vrs: &[u32]) -> (Status, Vec<bool>) {
        let (s, v) = Fmi3Instance::get_booleans(self, vrs);
        (s.into(), v)
    }

    fn set_string(&self, vr: u32, value: &str) -> Status {
        Fmi3Instance::set_string(self, vr, value).into()
    }

    fn get_string(&self, vr: u32) -> (Status, Option<String>) {
        let (s, v) = Fmi3Instance::get_string(self, vr);
        (s.into(), v)
    }

    fn directional_derivative(
        &self,
        unknowns: &[u32],
        knowns: &[u32],
        seed: &[f64],
        n_sensitivity: usize,
    ) -> (Status, Vec<f64>) {
        let (status, values) =
            Fmi3Instance::derivative(self, false, unknowns, knowns, seed, n_sensitivity);
        (status.into(), values)
    }

    fn get_state(&self) -> (Status, fmi3FMUState) {
        let (s, state) = Fmi3Instance::get_state(self);
        (s.into(), state)
    }

    fn set_state(&self, state: fmi3FMUState) -> Status {
        Fmi3Instance::set_state(self, state).into()
    }

    fn free_state(&self, state: fmi3FMUState) -> Status {
        Fmi3Instance::free_state(self, state).into()
    }

    fn serialize(&self, state: fmi3FMUState) -> (Status, Vec<u8>) {
        let (s, bytes) = Fmi3Instance::serialize(self, state);
        (s.into(), bytes)
    }

    fn deserialize(&self, bytes: &[u8]) -> (Status, fmi3FMUState) {
        let (s, state) = Fmi3Instance::deserialize(self, bytes);
        (s.into(), state)
    }

    fn null_state() -> fmi3FMUState {
        std::ptr::null_mut()
    }

    fn is_null(state: fmi3FMUState) -> bool {
        state.is_null()
    }
}
