//! A thin driver over the raw functions for the table tests, the thread, leak and long runs:
//! each method is one C call whose status is returned unchanged, nothing is hidden.
#![allow(unsafe_code)]

use crate::api::Api;
use crate::ffi::*;
use crate::logger::{LogSink, Record};
use crate::package::{Lander, PackageError, Unpacked};
use model_description::VariableKind;
use std::ffi::{CStr, CString};
use std::ptr;

/// A loaded FMU: its unpacked files and its functions.
pub struct Fmu {
    pub api: Api,
    pub package: Unpacked,
}

#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    #[error(transparent)]
    Package(#[from] PackageError),
    #[error("cannot load the library: {0}")]
    Library(#[from] libloading::Error),
}

impl Fmu {
    pub fn load(lander: Lander) -> Result<Fmu, LoadError> {
        let package = Unpacked::open(lander)?;
        let api = Api::load(&package.library)?;
        Ok(Fmu { api, package })
    }

    pub fn lander(&self) -> Lander {
        self.package.lander
    }

    pub fn vr(&self, name: &str) -> u32 {
        self.package.vr(name)
    }

    pub fn guid(&self) -> CString {
        CString::new(self.package.guid.clone()).expect("a GUID has no NUL")
    }

    /// A Co-Simulation instance with the right GUID; panics if the FMU refuses it.
    pub fn instantiate(&self, name: &str, logging_on: bool) -> Instance<'_> {
        self.try_instantiate(name, logging_on)
            .unwrap_or_else(|sink| panic!("fmi2Instantiate refused: {:?}", sink.all()))
    }

    /// `Err` carries what the FMU logged when it returned NULL.
    pub fn try_instantiate(
        &self,
        name: &str,
        logging_on: bool,
    ) -> Result<Instance<'_>, Box<LogSink>> {
        let sink = Box::<LogSink>::default();
        let callbacks = sink.callbacks();
        let name_c = CString::new(name).expect("no NUL in a test instance name");
        // SAFETY: every pointer is valid for the duration of the call; the FMU copies them.
        let c = unsafe {
            (self.api.instantiate)(
                name_c.as_ptr(),
                fmi2CoSimulation,
                self.guid().as_ptr(),
                c"file:///nowhere".as_ptr(),
                &callbacks,
                0,
                logging_on as fmi2Boolean,
            )
        };
        if c.is_null() {
            return Err(sink);
        }
        Ok(Instance {
            fmu: self,
            c,
            sink,
            name: name.to_string(),
        })
    }
}

/// One instance, freed on drop (which also frees its FMU states).
pub struct Instance<'a> {
    pub fmu: &'a Fmu,
    pub c: fmi2Component,
    pub sink: Box<LogSink>,
    pub name: String,
}

// SAFETY: FMI 2.0 lets a master drive an instance from any thread, one thread at a time;
// the instance owns no thread-bound resource and the sink is a Mutex.
unsafe impl Send for Instance<'_> {}

impl<'a> Instance<'a> {
    /// Takes ownership of a component returned by `fmi2Instantiate` of `fmu`.
    ///
    /// # Safety
    /// `c` is a live component of `fmu` whose callbacks' environment is `sink`, owned by
    /// nothing else (it is freed on drop).
    pub unsafe fn from_raw(
        fmu: &'a Fmu,
        c: fmi2Component,
        sink: Box<LogSink>,
        name: String,
    ) -> Self {
        Instance { fmu, c, sink, name }
    }

    /// `fmi2FreeInstance`, returning the sink so that what was logged during the call can
    /// still be inspected.
    pub fn free(self) -> Box<LogSink> {
        let this = std::mem::ManuallyDrop::new(self);
        // SAFETY: `c` is live and freed exactly once: `this` is never dropped.
        unsafe { (this.fmu.api.free_instance)(this.c) };
        // SAFETY: each field is moved out exactly once and `this` is forgotten.
        let _name = unsafe { ptr::read(&this.name) };
        unsafe { ptr::read(&this.sink) }
    }
}

impl Drop for Instance<'_> {
    fn drop(&mut self) {
        // SAFETY: `c` came from fmi2Instantiate and is freed exactly once.
        unsafe { (self.fmu.api.free_instance)(self.c) }
    }
}

/// Shorthand for a call on this instance's API.
macro_rules! call {
    ($self:ident . $f:ident ( $($arg:expr),* )) => {
        // SAFETY: `c` is live; every pointer argument is valid as the standard requires.
        unsafe { ($self.fmu.api.$f)($self.c $(, $arg)*) }
    };
    (co_simulation: $self:ident . $f:ident ( $($arg:expr),* )) => {
        // SAFETY: as above.
        unsafe { ($self.fmu.api.co_simulation.$f)($self.c $(, $arg)*) }
    };
}

impl Instance<'_> {
    pub fn setup(&self, start: f64, stop: Option<f64>) -> fmi2Status {
        call!(self.setup_experiment(
            0,
            0.0,
            start,
            stop.is_some() as fmi2Boolean,
            stop.unwrap_or(0.0)
        ))
    }

    pub fn enter_init(&self) -> fmi2Status {
        call!(self.enter_initialization_mode())
    }

    pub fn exit_init(&self) -> fmi2Status {
        call!(self.exit_initialization_mode())
    }

    /// Setup at `start` (no stop time), enter and exit initialization mode; the status of
    /// the first call that is not fmi2OK, or fmi2OK.
    pub fn init_at(&self, start: f64) -> fmi2Status {
        for status in [self.setup(start, None), self.enter_init(), self.exit_init()] {
            if status != fmi2OK {
                return status;
            }
        }
        fmi2OK
    }

    pub fn terminate(&self) -> fmi2Status {
        call!(self.terminate())
    }

    pub fn reset(&self) -> fmi2Status {
        call!(self.reset())
    }

    pub fn step(&self, t: f64, h: f64) -> fmi2Status {
        call!(co_simulation: self.do_step(t, h, 1))
    }

    pub fn set_debug_logging(&self, on: bool, categories: &[&CStr]) -> fmi2Status {
        let pointers: Vec<fmi2String> = categories.iter().map(|c| c.as_ptr()).collect();
        call!(self.set_debug_logging(on as fmi2Boolean, pointers.len(), pointers.as_ptr()))
    }

    pub fn set_reals(&self, vrs: &[u32], values: &[f64]) -> fmi2Status {
        assert_eq!(vrs.len(), values.len());
        call!(self.set_real(vrs.as_ptr(), vrs.len(), values.as_ptr()))
    }

    pub fn set_real_by_name(&self, name: &str, value: f64) -> fmi2Status {
        self.set_reals(&[self.fmu.vr(name)], &[value])
    }

    /// A parameter by name through the function of its declared kind: Integer parameters
    /// (LanderNav's seed and latencies) take `value` as an integer.
    pub fn set_parameter(&self, name: &str, value: f64) -> fmi2Status {
        let info = self
            .fmu
            .package
            .variables
            .iter()
            .find(|v| v.name == name)
            .unwrap_or_else(|| panic!("{:?} declares no {name}", self.fmu.lander()));
        match info.kind {
            VariableKind::Integer => self.set_integers(&[info.value_reference], &[value as i32]),
            _ => self.set_reals(&[info.value_reference], &[value]),
        }
    }

    pub fn set_integers(&self, vrs: &[u32], values: &[i32]) -> fmi2Status {
        assert_eq!(vrs.len(), values.len());
        call!(self.set_integer(vrs.as_ptr(), vrs.len(), values.as_ptr()))
    }

    pub fn set_booleans(&self, vrs: &[u32], values: &[bool]) -> fmi2Status {
        let values: Vec<fmi2Boolean> = values.iter().map(|&b| b as fmi2Boolean).collect();
        call!(self.set_boolean(vrs.as_ptr(), vrs.len(), values.as_ptr()))
    }

    pub fn set_strings(&self, vrs: &[u32], values: &[&CStr]) -> fmi2Status {
        let values: Vec<fmi2String> = values.iter().map(|s| s.as_ptr()).collect();
        call!(self.set_string(vrs.as_ptr(), vrs.len(), values.as_ptr()))
    }

    pub fn get_reals(&self, vrs: &[u32]) -> (fmi2Status, Vec<f64>) {
        let mut values = vec![f64::NAN; vrs.len()];
        let status = call!(self.get_real(vrs.as_ptr(), vrs.len(), values.as_mut_ptr()));
        (status, values)
    }

    pub fn get_integers(&self, vrs: &[u32]) -> (fmi2Status, Vec<i32>) {
        let mut values = vec![i32::MIN; vrs.len()];
        let status = call!(self.get_integer(vrs.as_ptr(), vrs.len(), values.as_mut_ptr()));
        (status, values)
    }

    pub fn get_booleans(&self, vrs: &[u32]) -> (fmi2Status, Vec<fmi2Boolean>) {
        let mut values = vec![-1; vrs.len()];
        let status = call!(self.get_boolean(vrs.as_ptr(), vrs.len(), values.as_mut_ptr()));
        (status, values)
    }

    pub fn get_fmu_state(&self) -> (fmi2Status, fmi2FMUstate) {
        let mut state: fmi2FMUstate = ptr::null_mut();
        let status = call!(self.get_fmu_state(&mut state));
        (status, state)
    }

    // Any pointer value is a legal argument: the FMU checks that a state is one it handed out
    // before it touches it (that is part of what these tests check).
    #[allow(clippy::not_unsafe_ptr_arg_deref)]
    pub fn set_fmu_state(&self, state: fmi2FMUstate) -> fmi2Status {
        call!(self.set_fmu_state(state))
    }

    pub fn free_fmu_state(&self, state: &mut fmi2FMUstate) -> fmi2Status {
        call!(self.free_fmu_state(state))
    }

    /// The serialized bytes of `state`, or the status of the call that failed.
    #[allow(clippy::not_unsafe_ptr_arg_deref)]
    pub fn serialize(&self, state: fmi2FMUstate) -> Result<Vec<u8>, fmi2Status> {
        let mut size = 0usize;
        let status = call!(self.serialized_fmu_state_size(state, &mut size));
        if status != fmi2OK {
            return Err(status);
        }
        let mut bytes = vec![0u8; size];
        let status = call!(self.serialize_fmu_state(state, bytes.as_mut_ptr().cast(), size));
        if status != fmi2OK {
            return Err(status);
        }
        Ok(bytes)
    }

    pub fn deserialize(&self, bytes: &[u8]) -> (fmi2Status, fmi2FMUstate) {
        let mut state: fmi2FMUstate = ptr::null_mut();
        let status =
            call!(self.de_serialize_fmu_state(bytes.as_ptr().cast(), bytes.len(), &mut state));
        (status, state)
    }

    pub fn real_status(&self, kind: fmi2StatusKind) -> (fmi2Status, f64) {
        let mut value = f64::NAN;
        let status = call!(co_simulation: self.get_real_status(kind, &mut value));
        (status, value)
    }

    /// Everything logged since the last call of `take_log`.
    pub fn take_log(&self) -> Vec<Record> {
        self.sink.take()
    }
}
