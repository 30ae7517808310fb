//! One FMI 2.0 Co-Simulation instance, driven through its C entry points.
//!
//! FMU states are opaque handles the FMU hands out; passing any handle (even a foreign or
//! stale one) is what the robustness tests do on purpose, and the FMU must refuse it.
#![allow(clippy::not_unsafe_ptr_arg_deref)]
use crate::functions::Fmi2Functions;
use crate::logger::{Record, TestLogger};
use fmi_abi::fmi2::*;
use std::ffi::{CStr, CString};

/// An instance and its logger; freed on drop. Every method is one FMI call (or a fixed
/// sequence of them), returning the status where a test may want to see it.
#[derive(Debug)]
pub struct Instance {
    functions: Fmi2Functions,
    c: fmi2Component,
    logger: Box<TestLogger>,
    /// FMI 2.0 FMUs may keep the pointer rather than copy the struct.
    _callbacks: Box<fmi2CallbackFunctions>,
}

impl Instance {
    /// `fmi2Instantiate` as Co-Simulation; `Err` with what the FMU logged when it returns NULL.
    pub fn new(
        functions: &Fmi2Functions,
        instance_name: &str,
        guid: &str,
        logging_on: bool,
    ) -> Result<Instance, Vec<Record>> {
        Instance::new_as(functions, instance_name, guid, logging_on, fmi2CoSimulation)
    }

    /// As [`new`](Self::new) for the interface `fmu_type` (`fmi2ModelExchange` or
    /// `fmi2CoSimulation`).
    pub fn new_as(
        functions: &Fmi2Functions,
        instance_name: &str,
        guid: &str,
        logging_on: bool,
        fmu_type: fmi2Type,
    ) -> Result<Instance, Vec<Record>> {
        let logger = Box::<TestLogger>::default();
        let callbacks = Box::new(logger.callbacks());
        let name = CString::new(instance_name).expect("no NUL in the instance name");
        let guid = CString::new(guid).expect("no NUL in the GUID");
        // SAFETY: valid strings and callbacks that outlive the instance (kept in `Instance`).
        let c = unsafe {
            (functions.instantiate)(
                name.as_ptr(),
                fmu_type,
                guid.as_ptr(),
                c"file:///nowhere".as_ptr(),
                &*callbacks,
                fmi2False,
                if logging_on { fmi2True } else { fmi2False },
            )
        };
        if c.is_null() {
            return Err(logger.all());
        }
        Ok(Instance {
            functions: *functions,
            c,
            logger,
            _callbacks: callbacks,
        })
    }

    /// As [`new`](Self::new), panicking with the FMU's messages if instantiation fails.
    pub fn instantiate(functions: &Fmi2Functions, instance_name: &str, guid: &str) -> Instance {
        Instance::new(functions, instance_name, guid, false)
            .unwrap_or_else(|log| panic!("fmi2Instantiate returned NULL: {log:?}"))
    }

    pub fn component(&self) -> fmi2Component {
        self.c
    }

    pub fn functions(&self) -> &Fmi2Functions {
        &self.functions
    }

    pub fn logger(&self) -> &TestLogger {
        &self.logger
    }

    pub fn records(&self) -> Vec<Record> {
        self.logger.all()
    }

    pub fn messages(&self) -> Vec<String> {
        self.logger.messages()
    }

    pub fn last_message(&self) -> String {
        self.messages().pop().unwrap_or_default()
    }

    pub fn clear_log(&self) {
        self.logger.clear();
    }

    // ---- life cycle ----

    pub fn setup_experiment(&self, start: f64, stop: Option<f64>) -> fmi2Status {
        let (defined, stop) = match stop {
            Some(stop) => (fmi2True, stop),
            None => (fmi2False, 0.0),
        };
        // SAFETY: a live instance.
        unsafe { (self.functions.setup_experiment)(self.c, fmi2False, 0.0, start, defined, stop) }
    }

    pub fn enter_initialization_mode(&self) -> fmi2Status {
        // SAFETY: a live instance.
        unsafe { (self.functions.enter_initialization_mode)(self.c) }
    }

    pub fn exit_initialization_mode(&self) -> fmi2Status {
        // SAFETY: a live instance.
        unsafe { (self.functions.exit_initialization_mode)(self.c) }
    }

    /// Set up at t = 0 and enter initialization mode (where parameters may still be set);
    /// panics unless both calls succeed.
    pub fn enter_init(&self) {
        assert_eq!(
            self.setup_experiment(0.0, None),
            fmi2OK,
            "{:?}",
            self.messages()
        );
        assert_eq!(
            self.enter_initialization_mode(),
            fmi2OK,
            "{:?}",
            self.messages()
        );
    }

    /// [`enter_init`](Self::enter_init), then `fmi2ExitInitializationMode`'s status.
    pub fn initialize(&self) -> fmi2Status {
        self.enter_init();
        self.exit_initialization_mode()
    }

    pub fn do_step(&self, t: f64, h: f64) -> fmi2Status {
        // SAFETY: a live instance.
        unsafe { (self.functions.co_simulation.do_step)(self.c, t, h, fmi2True) }
    }

    pub fn terminate(&self) -> fmi2Status {
        // SAFETY: a live instance.
        unsafe { (self.functions.terminate)(self.c) }
    }

    pub fn reset(&self) -> fmi2Status {
        // SAFETY: a live instance.
        unsafe { (self.functions.reset)(self.c) }
    }

    // ---- get and set ----

    pub fn set_reals(&self, vrs: &[u32], values: &[f64]) -> fmi2Status {
        assert_eq!(vrs.len(), values.len());
        // SAFETY: arrays of the length passed.
        unsafe { (self.functions.set_real)(self.c, vrs.as_ptr(), vrs.len(), values.as_ptr()) }
    }

    pub fn get_reals(&self, vrs: &[u32]) -> (fmi2Status, Vec<f64>) {
        let mut values = vec![0.0; vrs.len()];
        // SAFETY: arrays of the length passed.
        let status = unsafe {
            (self.functions.get_real)(self.c, vrs.as_ptr(), vrs.len(), values.as_mut_ptr())
        };
        (status, values)
    }

    /// `fmi2GetReal` into `values` (one per reference), allocating nothing: for loops whose
    /// instructions are counted.
    /// `fmi2GetDirectionalDerivative`: `dvUnknown` for the seed `dv_known`.
    pub fn directional_derivative(
        &self,
        unknowns: &[u32],
        knowns: &[u32],
        dv_known: &[f64],
    ) -> (fmi2Status, Vec<f64>) {
        assert_eq!(knowns.len(), dv_known.len(), "one seed per known");
        let mut dv_unknown = vec![f64::NAN; unknowns.len()];
        // SAFETY: a live instance; every array of its stated length.
        let status = unsafe {
            (self.functions().get_directional_derivative)(
                self.component(),
                unknowns.as_ptr(),
                unknowns.len(),
                knowns.as_ptr(),
                knowns.len(),
                dv_known.as_ptr(),
                dv_unknown.as_mut_ptr(),
            )
        };
        (status, dv_unknown)
    }

    pub fn get_reals_into(&self, vrs: &[u32], values: &mut [f64]) -> fmi2Status {
        assert_eq!(vrs.len(), values.len());
        // SAFETY: arrays of the length passed.
        unsafe { (self.functions.get_real)(self.c, vrs.as_ptr(), vrs.len(), values.as_mut_ptr()) }
    }

    pub fn set_real(&self, vr: u32, value: f64) -> fmi2Status {
        self.set_reals(&[vr], &[value])
    }

    /// One Real; panics unless the get succeeds.
    pub fn get_real(&self, vr: u32) -> f64 {
        let (status, values) = self.get_reals(&[vr]);
        assert!(status.is_success(), "{:?}", self.messages());
        values[0]
    }

    pub fn set_integers(&self, vrs: &[u32], values: &[i32]) -> fmi2Status {
        assert_eq!(vrs.len(), values.len());
        // SAFETY: arrays of the length passed.
        unsafe { (self.functions.set_integer)(self.c, vrs.as_ptr(), vrs.len(), values.as_ptr()) }
    }

    pub fn get_integers(&self, vrs: &[u32]) -> (fmi2Status, Vec<i32>) {
        let mut values = vec![0; vrs.len()];
        // SAFETY: arrays of the length passed.
        let status = unsafe {
            (self.functions.get_integer)(self.c, vrs.as_ptr(), vrs.len(), values.as_mut_ptr())
        };
        (status, values)
    }

    pub fn set_integer(&self, vr: u32, value: i32) -> fmi2Status {
        self.set_integers(&[vr], &[value])
    }

    /// One Integer; panics unless the get succeeds.
    pub fn get_integer(&self, vr: u32) -> i32 {
        let (status, values) = self.get_integers(&[vr]);
        assert!(status.is_success(), "{:?}", self.messages());
        values[0]
    }

    pub fn set_boolean(&self, vr: u32, value: bool) -> fmi2Status {
        let value = if value { fmi2True } else { fmi2False };
        // SAFETY: one element each.
        unsafe { (self.functions.set_boolean)(self.c, &vr, 1, &value) }
    }

    /// One Boolean; panics unless the get succeeds.
    pub fn get_boolean(&self, vr: u32) -> bool {
        let mut value = fmi2False;
        // SAFETY: one element each.
        let status = unsafe { (self.functions.get_boolean)(self.c, &vr, 1, &mut value) };
        assert!(status.is_success(), "{:?}", self.messages());
        value != fmi2False
    }

    pub fn set_string(&self, vr: u32, value: &str) -> fmi2Status {
        let value = CString::new(value).expect("no NUL in the value");
        let pointer = value.as_ptr();
        // SAFETY: one element each; the string outlives the call.
        unsafe { (self.functions.set_string)(self.c, &vr, 1, &pointer) }
    }

    /// One String; panics unless the get succeeds.
    pub fn get_string(&self, vr: u32) -> String {
        let mut value: fmi2String = std::ptr::null();
        // SAFETY: one element each; the FMU keeps the string alive until its next call.
        let status = unsafe { (self.functions.get_string)(self.c, &vr, 1, &mut value) };
        assert!(status.is_success(), "{:?}", self.messages());
        assert!(!value.is_null());
        // SAFETY: non-null and NUL-terminated, per the standard.
        unsafe { CStr::from_ptr(value) }
            .to_string_lossy()
            .into_owned()
    }

    // ---- status ----

    pub fn last_successful_time(&self) -> f64 {
        let mut time = f64::NAN;
        // SAFETY: one element.
        let status = unsafe {
            (self.functions.co_simulation.get_real_status)(
                self.c,
                fmi2LastSuccessfulTime,
                &mut time,
            )
        };
        assert_eq!(status, fmi2OK, "{:?}", self.messages());
        time
    }

    pub fn terminated(&self) -> bool {
        let mut value = fmi2False;
        // SAFETY: one element.
        let status = unsafe {
            (self.functions.co_simulation.get_boolean_status)(self.c, fmi2Terminated, &mut value)
        };
        assert_eq!(status, fmi2OK, "{:?}", self.messages());
        value != fmi2False
    }

    // ---- FMU state ----

    /// A new FMU state; panics unless the call succeeds.
    pub fn get_state(&self) -> fmi2FMUstate {
        let mut state: fmi2FMUstate = std::ptr::null_mut();
        // SAFETY: an out-pointer to a NULL state: the FMU allocates one.
        let status = unsafe { (self.functions.get_fmu_state)(self.c, &mut state) };
        assert_eq!(status, fmi2OK, "{:?}", self.messages());
        state
    }

    pub fn set_state(&self, state: fmi2FMUstate) -> fmi2Status {
        // SAFETY: a state of this instance (or one the test wants refused).
        unsafe { (self.functions.set_fmu_state)(self.c, state) }
    }

    pub fn free_state(&self, mut state: fmi2FMUstate) -> fmi2Status {
        // SAFETY: as above; the FMU sets the pointer to NULL.
        unsafe { (self.functions.free_fmu_state)(self.c, &mut state) }
    }

    /// The serialized `state`; panics unless both calls succeed.
    pub fn serialize(&self, state: fmi2FMUstate) -> Vec<u8> {
        let mut size = 0;
        // SAFETY: one out-element.
        let status =
            unsafe { (self.functions.serialized_fmu_state_size)(self.c, state, &mut size) };
        assert_eq!(status, fmi2OK, "{:?}", self.messages());
        let mut bytes = vec![0u8; size];
        // SAFETY: a buffer of the announced size.
        let status = unsafe {
            (self.functions.serialize_fmu_state)(self.c, state, bytes.as_mut_ptr().cast(), size)
        };
        assert_eq!(status, fmi2OK, "{:?}", self.messages());
        bytes
    }

    /// `bytes` deserialized into a new FMU state (NULL when refused), with the status.
    pub fn deserialize(&self, bytes: &[u8]) -> (fmi2Status, fmi2FMUstate) {
        let mut state: fmi2FMUstate = std::ptr::null_mut();
        // SAFETY: a buffer of the length passed, an out-pointer to a NULL state.
        let status = unsafe {
            (self.functions.de_serialize_fmu_state)(
                self.c,
                bytes.as_ptr().cast(),
                bytes.len(),
                &mut state,
            )
        };
        (status, state)
    }
}

impl Drop for Instance {
    fn drop(&mut self) {
        // SAFETY: the instance is live and not used again.
        unsafe { (self.functions.free_instance)(self.c) };
    }
}
