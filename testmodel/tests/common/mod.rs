//! The Oscillator driven through its exported C functions, on the workspace's test kit.
//! Messages reach the test through the real variadic logger (the C shim of `fmi-abi`),
//! which formats them as a C master does: a message the layer passed as a format string
//! instead of an argument would show up garbled.
#![allow(dead_code, unsafe_code, unused_imports)]
// std's transcendental functions here are a reference independent of the libm the model uses.
#![allow(clippy::disallowed_methods)]

use fmi_testkit::fmi2::*;
use fmi_testkit::{fmi2_functions, Fmi2Functions, Instance};
use std::ffi::CString;
use std::ops::Deref;

pub use fmi_testkit::TestLogger as Sink;

pub static FUNCTIONS: Fmi2Functions = fmi2_functions!(fmu_testmodel);

pub mod vr {
    pub const X0: u32 = 0;
    pub const K: u32 = 1;
    pub const C: u32 = 2;
    pub const THRESHOLD: u32 = 3;
    pub const U: u32 = 4;
    pub const X: u32 = 5;
    pub const V: u32 = 6;
    pub const OMEGA_N: u32 = 7;
    pub const MASS: u32 = 8;
    pub const STEP_COUNT: u32 = 12;
    pub const SUBSTEPS: u32 = 13;
    pub const CROSSING: u32 = 14;
    pub const STOP_AT_THRESHOLD: u32 = 15;
    pub const LABEL: u32 = 16;
}

/// One logged message, NULL strings read as empty.
#[derive(Debug, Clone)]
pub struct Record {
    pub instance: String,
    pub status: fmi2Status,
    pub category: String,
    pub message: String,
}

impl From<fmi_testkit::Record> for Record {
    fn from(r: fmi_testkit::Record) -> Record {
        Record {
            instance: r.instance_name.unwrap_or_default(),
            status: r.status,
            category: r.category.unwrap_or_default(),
            message: r.message.unwrap_or_default(),
        }
    }
}

/// Everything `sink` recorded.
pub fn records_of(sink: &Sink) -> Vec<Record> {
    sink.all().into_iter().map(Record::from).collect()
}

pub fn callbacks(sink: &Sink) -> fmi2CallbackFunctions {
    sink.callbacks()
}

pub fn guid() -> CString {
    CString::new(fmi2_export::guid::<fmu_testmodel::Oscillator>()).unwrap()
}

/// One instance, freed on drop; `c` is its component for the tests that call the C
/// functions with arguments of their own.
pub struct Fmu {
    instance: Instance,
    pub c: fmi2Component,
    pub name: String,
}

impl Deref for Fmu {
    type Target = Instance;
    fn deref(&self) -> &Instance {
        &self.instance
    }
}

impl Fmu {
    pub fn new(logging_on: bool) -> Fmu {
        Self::named("osc", logging_on)
    }

    pub fn named(name: &str, logging_on: bool) -> Fmu {
        let guid = fmi2_export::guid::<fmu_testmodel::Oscillator>();
        let instance = Instance::new(&FUNCTIONS, name, &guid, logging_on)
            .unwrap_or_else(|log| panic!("instantiate failed: {log:?}"));
        Fmu {
            c: instance.component(),
            instance,
            name: name.into(),
        }
    }

    pub fn records(&self) -> Vec<Record> {
        records_of(self.logger())
    }

    pub fn clear(&self) {
        self.clear_log();
    }

    /// Messages of non-trace categories.
    pub fn messages(&self) -> Vec<String> {
        self.records()
            .into_iter()
            .filter(|r| r.category != "logCalls")
            .map(|r| r.message)
            .collect()
    }

    pub fn last_message(&self) -> String {
        self.messages().last().cloned().unwrap_or_default()
    }

    pub fn setup(&self, start: f64, stop: Option<f64>) -> fmi2Status {
        self.setup_experiment(start, stop)
    }

    pub fn enter_init(&self) -> fmi2Status {
        self.enter_initialization_mode()
    }

    pub fn exit_init(&self) -> fmi2Status {
        self.exit_initialization_mode()
    }

    /// Setup at t = 0 without stop time, enter and exit initialization mode.
    pub fn init(&self) {
        assert_eq!(self.setup(0.0, None), fmi2OK);
        assert_eq!(self.enter_init(), fmi2OK);
        assert_eq!(self.exit_init(), fmi2OK, "{:?}", self.messages());
    }

    pub fn step(&self, t: f64, h: f64) -> fmi2Status {
        self.do_step(t, h)
    }
}

pub fn analytic_x(t: f64, x0: f64, k: f64, c: f64, u: f64) -> f64 {
    let x_eq = u / k;
    let zeta_omega = c / 2.0;
    let omega_d = (k - zeta_omega * zeta_omega).sqrt();
    let a = x0 - x_eq;
    let b = zeta_omega * a / omega_d;
    x_eq + (-zeta_omega * t).exp() * (a * (omega_d * t).cos() + b * (omega_d * t).sin())
}

// ---- Both versions: one test body for FMI 2.0 and FMI 3.0 ----

pub use fmi_testkit::{Driver, Fmi2, Fmi3, Interface, Status, Version};

pub static FUNCTIONS3: fmi_testkit::Fmi3Functions = fmi_testkit::fmi3_functions!(fmu_testmodel);

/// A driver of the Oscillator: the version's function table and token.
pub trait Osc: Driver {
    fn functions() -> &'static Self::Functions;
    fn token() -> String;

    /// A Co-Simulation instance named "osc".
    fn open(logging_on: bool) -> Self {
        Self::open_as(Interface::CoSimulation, "osc", logging_on)
    }

    fn open_as(interface: Interface, name: &str, logging_on: bool) -> Self {
        Self::instantiate(
            Self::functions(),
            name,
            &Self::token(),
            interface,
            logging_on,
        )
        .unwrap_or_else(|log| panic!("instantiate failed: {log:?}"))
    }

    /// The instance's own time: FMI 2.0 `fmi2LastSuccessfulTime` (fmi2GetRealStatus); FMI
    /// 3.0 the independent variable `time` (fmi3GetFloat64), as FMI 3.0 defines no
    /// out-arguments after a refused step.
    fn own_time(&self) -> f64;

    /// The C name of a function of this version: `f("DoStep")` is `fmi2DoStep` or
    /// `fmi3DoStep`.
    fn f(name: &str) -> String {
        format!("{}{name}", Self::VERSION.prefix())
    }

    /// The C name of the Real setter or getter: `fmi2SetReal`, `fmi3SetFloat64`.
    fn real_fn(set: bool) -> String {
        let verb = if set { "Set" } else { "Get" };
        match Self::VERSION {
            Version::Fmi2 => format!("fmi2{verb}Real"),
            Version::Fmi3 => format!("fmi3{verb}Float64"),
        }
    }

    /// The C name of the Integer setter: `fmi2SetInteger`, `fmi3SetInt32`.
    fn integer_setter() -> &'static str {
        match Self::VERSION {
            Version::Fmi2 => "fmi2SetInteger",
            Version::Fmi3 => "fmi3SetInt32",
        }
    }
}

impl Osc for Fmi2 {
    fn functions() -> &'static fmi_testkit::Fmi2Functions {
        &FUNCTIONS
    }
    fn token() -> String {
        fmi2_export::guid::<fmu_testmodel::Oscillator>()
    }
    fn own_time(&self) -> f64 {
        self.last_successful_time()
    }
}

impl Osc for Fmi3 {
    fn functions() -> &'static fmi_testkit::Fmi3Functions {
        &FUNCTIONS3
    }
    fn token() -> String {
        fmi3_export::instantiation_token::<fmu_testmodel::Oscillator>()
    }
    fn own_time(&self) -> f64 {
        self.real(fmi3_export::variables::TIME_VR)
    }
}

/// `both!(case, ...)`: for each generic `fn case<D: Osc>()`, a module `case` with the tests
/// `fmi2` and `fmi3`.
#[macro_export]
macro_rules! both {
    ($($case:ident),* $(,)?) => {$(
        mod $case {
            #[test]
            fn fmi2() {
                super::$case::<fmi_testkit::Fmi2>()
            }
            #[test]
            fn fmi3() {
                super::$case::<fmi_testkit::Fmi3>()
            }
        }
    )*};
}
