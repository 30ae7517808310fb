//! FMI 3.0: the entry points of one FMU as a table of function pointers ([`Fmi3Functions`],
//! from a crate linked into the test with [`fmi3_functions!`](crate::fmi3_functions)), and
//! one instance driven through them ([`Fmi3Instance`]), freed on drop.
//!
//! FMU states are opaque handles the FMU hands out; passing any handle (even a foreign or
//! stale one) is what the robustness tests do on purpose, and the FMU must refuse it.
#![allow(clippy::not_unsafe_ptr_arg_deref)]
use crate::logger::{Record, TestLogger};
use fmi_abi::fmi3::*;
use fmi_import::tables::fmi3::{Fmi3CoSimulation, Fmi3Common, Fmi3ModelExchange, Vector};
use std::ffi::{c_void, CStr, CString};

type Inst = fmi3Instance;

/// The FMI 3.0 functions the kit drives (Co-Simulation, Model Exchange, FMU state): the
/// importer's tables (`fmi-import`, listed once there), the common ones reached directly.
#[derive(Debug, Clone, Copy)]
pub struct Fmi3Functions {
    pub common: Fmi3Common,
    pub co_simulation: Fmi3CoSimulation,
    pub model_exchange: Fmi3ModelExchange,
    pub derivatives: Fmi3Derivatives,
}

/// `fmi3GetDirectionalDerivative` and `fmi3GetAdjointDerivative` (same signature).
pub type DerivativeFunction = unsafe extern "C" fn(
    Inst,
    *const fmi3ValueReference,
    usize,
    *const fmi3ValueReference,
    usize,
    *const f64,
    usize,
    *mut f64,
    usize,
) -> fmi3Status;

/// The two partial-derivative functions of FMI 3.0.
#[derive(Debug, Clone, Copy)]
pub struct Fmi3Derivatives {
    pub directional: DerivativeFunction,
    pub adjoint: DerivativeFunction,
}

impl std::ops::Deref for Fmi3Functions {
    type Target = Fmi3Common;
    fn deref(&self) -> &Fmi3Common {
        &self.common
    }
}

/// The [`Fmi3Functions`] of an FMU crate linked into the test (its `export_fmi3!` symbols),
/// e.g. `static FMU: Fmi3Functions = fmi3_functions!(fmu_plant);`.
#[macro_export]
macro_rules! fmi3_functions {
    ($fmu:path) => {
        $crate::Fmi3Functions {
            common: $crate::fmi_import::fmi3_common!($fmu),
            co_simulation: $crate::fmi_import::fmi3_co_simulation!($fmu),
            model_exchange: $crate::fmi_import::fmi3_model_exchange!($fmu),
            derivatives: {
                use $fmu as fmu;
                $crate::Fmi3Derivatives {
                    directional: fmu::fmi3GetDirectionalDerivative,
                    adjoint: fmu::fmi3GetAdjointDerivative,
                }
            },
        }
    };
}

impl Fmi3Functions {
    /// The entry points of a loaded shared library (an FMU's binary). The library must stay
    /// loaded while the table is used.
    ///
    /// # Safety
    /// The library's `fmi3*` symbols must have the standard's signatures.
    pub unsafe fn load(library: &libloading::Library) -> Result<Fmi3Functions, libloading::Error> {
        // SAFETY: forwarded from the caller.
        unsafe {
            Ok(Fmi3Functions {
                common: Fmi3Common::load(library).map_err(|e| e.source)?,
                co_simulation: Fmi3CoSimulation::load(library).map_err(|e| e.source)?,
                model_exchange: Fmi3ModelExchange::load(library).map_err(|e| e.source)?,
                derivatives: Fmi3Derivatives {
                    directional: fmi_import::tables::symbol(
                        library,
                        "fmi3GetDirectionalDerivative",
                    )
                    .map_err(|e| e.source)?,
                    adjoint: fmi_import::tables::symbol(library, "fmi3GetAdjointDerivative")
                        .map_err(|e| e.source)?,
                },
            })
        }
    }
}

/// The out-arguments of `fmi3DoStep`, with its status.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fmi3Step {
    pub status: fmi3Status,
    pub event_handling_needed: bool,
    pub terminate_simulation: bool,
    pub early_return: bool,
    pub last_successful_time: f64,
}

/// The out-arguments of `fmi3UpdateDiscreteStates`, with its status.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fmi3EventUpdate {
    pub status: fmi3Status,
    pub discrete_states_need_update: bool,
    pub terminate_simulation: bool,
    pub nominals_changed: bool,
    pub values_changed: bool,
    pub next_event_time: Option<f64>,
}

/// How a Co-Simulation instance is created: the master's choices at instantiation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct CoSimulationOptions {
    pub logging_on: bool,
    pub event_mode_used: bool,
    pub early_return_allowed: bool,
}

/// One FMI 3.0 instance and its logger; freed on drop. Every method is one FMI call.
#[derive(Debug)]
pub struct Fmi3Instance {
    functions: Fmi3Functions,
    c: Inst,
    logger: Box<TestLogger>,
}

impl Fmi3Instance {
    /// `fmi3InstantiateCoSimulation`; `Err` with what the FMU logged when it returns NULL.
    pub fn co_simulation(
        functions: &Fmi3Functions,
        instance_name: &str,
        token: &str,
        options: CoSimulationOptions,
    ) -> Result<Fmi3Instance, Vec<Record>> {
        Fmi3Instance::co_simulation_in(functions, instance_name, token, None, options)
    }

    /// As [`co_simulation`](Self::co_simulation) with a `resourcePath` (NULL when `None`).
    pub fn co_simulation_in(
        functions: &Fmi3Functions,
        instance_name: &str,
        token: &str,
        resource_path: Option<&str>,
        options: CoSimulationOptions,
    ) -> Result<Fmi3Instance, Vec<Record>> {
        let logger = Box::<TestLogger>::default();
        let name = CString::new(instance_name).expect("no NUL in the instance name");
        let token = CString::new(token).expect("no NUL in the token");
        let resources =
            resource_path.map(|r| CString::new(r).expect("no NUL in the resource path"));
        // SAFETY: valid strings; the logger outlives the instance (kept in it).
        let c = unsafe {
            (functions.co_simulation.instantiate_co_simulation)(
                name.as_ptr(),
                token.as_ptr(),
                resources.as_ref().map_or(std::ptr::null(), |r| r.as_ptr()),
                false,
                options.logging_on,
                options.event_mode_used,
                options.early_return_allowed,
                std::ptr::null(),
                0,
                logger.environment(),
                Some(TestLogger::log_message),
                None,
            )
        };
        Fmi3Instance::made(functions, c, logger)
    }

    /// `fmi3InstantiateModelExchange`; `Err` with what the FMU logged when it returns NULL.
    pub fn model_exchange(
        functions: &Fmi3Functions,
        instance_name: &str,
        token: &str,
        logging_on: bool,
    ) -> Result<Fmi3Instance, Vec<Record>> {
        let logger = Box::<TestLogger>::default();
        let name = CString::new(instance_name).expect("no NUL in the instance name");
        let token = CString::new(token).expect("no NUL in the token");
        // SAFETY: as in `co_simulation`.
        let c = unsafe {
            (functions.model_exchange.instantiate_model_exchange)(
                name.as_ptr(),
                token.as_ptr(),
                std::ptr::null(),
                false,
                logging_on,
                logger.environment(),
                Some(TestLogger::log_message),
            )
        };
        Fmi3Instance::made(functions, c, logger)
    }

    fn made(
        functions: &Fmi3Functions,
        c: Inst,
        logger: Box<TestLogger>,
    ) -> Result<Fmi3Instance, Vec<Record>> {
        if c.is_null() {
            return Err(logger.all());
        }
        Ok(Fmi3Instance {
            functions: *functions,
            c,
            logger,
        })
    }

    pub fn instance(&self) -> fmi3Instance {
        self.c
    }

    pub fn functions(&self) -> &Fmi3Functions {
        &self.functions
    }

    pub fn logger(&self) -> &TestLogger {
        &self.logger
    }

    /// Every record the FMU logged (status, category, message), in order.
    pub fn records(&self) -> Vec<Record> {
        self.logger.all()
    }

    pub fn messages(&self) -> Vec<String> {
        self.logger.messages()
    }

    pub fn last_message(&self) -> String {
        self.messages().pop().unwrap_or_default()
    }

    // ---- life cycle ----

    pub fn set_debug_logging(&self, on: bool) -> fmi3Status {
        // SAFETY: a live instance, no categories.
        unsafe { (self.functions.set_debug_logging)(self.c, on, 0, std::ptr::null()) }
    }

    pub fn enter_initialization_mode(&self, start: f64, stop: Option<f64>) -> fmi3Status {
        // SAFETY: a live instance.
        unsafe {
            (self.functions.enter_initialization_mode)(
                self.c,
                false,
                0.0,
                start,
                stop.is_some(),
                stop.unwrap_or(0.0),
            )
        }
    }

    pub fn exit_initialization_mode(&self) -> fmi3Status {
        // SAFETY: a live instance.
        unsafe { (self.functions.exit_initialization_mode)(self.c) }
    }

    pub fn enter_event_mode(&self) -> fmi3Status {
        // SAFETY: a live instance.
        unsafe { (self.functions.enter_event_mode)(self.c) }
    }

    pub fn enter_step_mode(&self) -> fmi3Status {
        // SAFETY: a live instance.
        unsafe { (self.functions.co_simulation.enter_step_mode)(self.c) }
    }

    pub fn enter_continuous_time_mode(&self) -> fmi3Status {
        // SAFETY: a live instance.
        unsafe { (self.functions.model_exchange.enter_continuous_time_mode)(self.c) }
    }

    pub fn terminate(&self) -> fmi3Status {
        // SAFETY: a live instance.
        unsafe { (self.functions.terminate)(self.c) }
    }

    pub fn reset(&self) -> fmi3Status {
        // SAFETY: a live instance.
        unsafe { (self.functions.reset)(self.c) }
    }

    /// `fmi3DoStep` with `noSetFMUStatePriorToCurrentPoint = true`.
    #[inline]
    pub fn do_step(&self, t: f64, h: f64) -> Fmi3Step {
        // Out-arguments start at the opposite of what a quiet step reports, so a step that
        // leaves one unwritten shows.
        let (mut event, mut terminate, mut early, mut last) = (true, true, true, f64::NAN);
        // SAFETY: a live instance and valid out-pointers.
        let status = unsafe {
            (self.functions.co_simulation.do_step)(
                self.c,
                t,
                h,
                true,
                &mut event,
                &mut terminate,
                &mut early,
                &mut last,
            )
        };
        Fmi3Step {
            status,
            event_handling_needed: event,
            terminate_simulation: terminate,
            early_return: early,
            last_successful_time: last,
        }
    }

    pub fn update_discrete_states(&self) -> Fmi3EventUpdate {
        let (mut again, mut terminate, mut nominals, mut values, mut defined, mut next) =
            (true, true, true, true, true, f64::NAN);
        // SAFETY: a live instance and valid out-pointers.
        let status = unsafe {
            (self.functions.update_discrete_states)(
                self.c,
                &mut again,
                &mut terminate,
                &mut nominals,
                &mut values,
                &mut defined,
                &mut next,
            )
        };
        Fmi3EventUpdate {
            status,
            discrete_states_need_update: again,
            terminate_simulation: terminate,
            nominals_changed: nominals,
            values_changed: values,
            next_event_time: defined.then_some(next),
        }
    }

    /// `fmi3CompletedIntegratorStep`: status, enterEventMode, terminateSimulation.
    pub fn completed_integrator_step(&self) -> (fmi3Status, bool, bool) {
        let (mut enter, mut terminate) = (true, true);
        // SAFETY: a live instance and valid out-pointers.
        let status = unsafe {
            (self.functions.model_exchange.completed_integrator_step)(
                self.c,
                true,
                &mut enter,
                &mut terminate,
            )
        };
        (status, enter, terminate)
    }

    pub fn set_time(&self, t: f64) -> fmi3Status {
        // SAFETY: a live instance.
        unsafe { (self.functions.model_exchange.set_time)(self.c, t) }
    }

    pub fn set_continuous_states(&self, x: &[f64]) -> fmi3Status {
        // SAFETY: an array of the length passed.
        unsafe {
            (self.functions.model_exchange.set_continuous_states)(self.c, x.as_ptr(), x.len())
        }
    }

    /// `fmi3GetNumberOfContinuousStates`.
    pub fn number_of_continuous_states(&self) -> (fmi3Status, usize) {
        let mut n = usize::MAX;
        // SAFETY: one out-element.
        let status = unsafe {
            (self
                .functions
                .model_exchange
                .get_number_of_continuous_states)(self.c, &mut n)
        };
        (status, n)
    }

    /// `fmi3GetNumberOfEventIndicators`.
    pub fn number_of_event_indicators(&self) -> (fmi3Status, usize) {
        let mut n = usize::MAX;
        // SAFETY: one out-element.
        let status = unsafe {
            (self.functions.model_exchange.get_number_of_event_indicators)(self.c, &mut n)
        };
        (status, n)
    }

    fn vector(&self, read: Vector, n: usize) -> (fmi3Status, Vec<f64>) {
        let mut values = vec![f64::NAN; n];
        // SAFETY: an array of the length passed.
        let status = unsafe { read(self.c, values.as_mut_ptr(), n) };
        (status, values)
    }

    pub fn continuous_states(&self, n: usize) -> (fmi3Status, Vec<f64>) {
        self.vector(self.functions.model_exchange.get_continuous_states, n)
    }

    pub fn derivatives(&self, n: usize) -> (fmi3Status, Vec<f64>) {
        self.vector(
            self.functions
                .model_exchange
                .get_continuous_state_derivatives,
            n,
        )
    }

    pub fn event_indicators(&self, n: usize) -> (fmi3Status, Vec<f64>) {
        self.vector(self.functions.model_exchange.get_event_indicators, n)
    }

    pub fn nominals(&self, n: usize) -> (fmi3Status, Vec<f64>) {
        self.vector(
            self.functions
                .model_exchange
                .get_nominals_of_continuous_states,
            n,
        )
    }

    // ---- get and set ----

    /// `fmi3GetFloat64` of `vrs`, `n` values in all (arrays take one per element).
    /// `fmi3GetDirectionalDerivative` (`adjoint` false) or `fmi3GetAdjointDerivative`, with
    /// `n_sensitivity` elements out (the serialized count the call should ask for).
    pub fn derivative(
        &self,
        adjoint: bool,
        unknowns: &[u32],
        knowns: &[u32],
        seed: &[f64],
        n_sensitivity: usize,
    ) -> (fmi3Status, Vec<f64>) {
        let mut sensitivity = vec![f64::NAN; n_sensitivity];
        let function = if adjoint {
            self.functions.derivatives.adjoint
        } else {
            self.functions.derivatives.directional
        };
        // SAFETY: a live instance; every array of its stated length.
        let status = unsafe {
            function(
                self.c,
                unknowns.as_ptr(),
                unknowns.len(),
                knowns.as_ptr(),
                knowns.len(),
                seed.as_ptr(),
                seed.len(),
                sensitivity.as_mut_ptr(),
                sensitivity.len(),
            )
        };
        (status, sensitivity)
    }

    pub fn get_float64(&self, vrs: &[u32], n: usize) -> (fmi3Status, Vec<f64>) {
        let mut values = vec![f64::NAN; n];
        // SAFETY: arrays of the lengths passed.
        let status = unsafe {
            (self.functions.get_float64)(self.c, vrs.as_ptr(), vrs.len(), values.as_mut_ptr(), n)
        };
        (status, values)
    }

    /// `fmi3GetFloat64` of `vrs` into `values` (`nValues` its length), allocating nothing.
    #[inline]
    pub fn get_float64_into(&self, vrs: &[u32], values: &mut [f64]) -> fmi3Status {
        // SAFETY: arrays of the lengths passed.
        unsafe {
            (self.functions.get_float64)(
                self.c,
                vrs.as_ptr(),
                vrs.len(),
                values.as_mut_ptr(),
                values.len(),
            )
        }
    }

    #[inline]
    pub fn set_float64(&self, vrs: &[u32], values: &[f64]) -> fmi3Status {
        // SAFETY: arrays of the lengths passed.
        unsafe {
            (self.functions.set_float64)(
                self.c,
                vrs.as_ptr(),
                vrs.len(),
                values.as_ptr(),
                values.len(),
            )
        }
    }

    pub fn get_int32(&self, vrs: &[u32]) -> (fmi3Status, Vec<i32>) {
        let mut values = vec![0; vrs.len()];
        // SAFETY: arrays of the lengths passed.
        let status = unsafe {
            (self.functions.get_int32)(
                self.c,
                vrs.as_ptr(),
                vrs.len(),
                values.as_mut_ptr(),
                vrs.len(),
            )
        };
        (status, values)
    }

    pub fn set_int32(&self, vrs: &[u32], values: &[i32]) -> fmi3Status {
        // SAFETY: arrays of the lengths passed.
        unsafe {
            (self.functions.set_int32)(
                self.c,
                vrs.as_ptr(),
                vrs.len(),
                values.as_ptr(),
                values.len(),
            )
        }
    }

    /// Int64: how FMI 3.0 exchanges an enumeration.
    pub fn get_int64(&self, vrs: &[u32]) -> (fmi3Status, Vec<i64>) {
        let mut values = vec![0; vrs.len()];
        // SAFETY: arrays of the lengths passed.
        let status = unsafe {
            (self.functions.get_int64)(
                self.c,
                vrs.as_ptr(),
                vrs.len(),
                values.as_mut_ptr(),
                vrs.len(),
            )
        };
        (status, values)
    }

    pub fn set_int64(&self, vrs: &[u32], values: &[i64]) -> fmi3Status {
        // SAFETY: arrays of the lengths passed.
        unsafe {
            (self.functions.set_int64)(
                self.c,
                vrs.as_ptr(),
                vrs.len(),
                values.as_ptr(),
                values.len(),
            )
        }
    }

    pub fn get_booleans(&self, vrs: &[u32]) -> (fmi3Status, Vec<bool>) {
        let mut values = vec![false; vrs.len()];
        // SAFETY: arrays of the lengths passed.
        let status = unsafe {
            (self.functions.get_boolean)(
                self.c,
                vrs.as_ptr(),
                vrs.len(),
                values.as_mut_ptr(),
                vrs.len(),
            )
        };
        (status, values)
    }

    pub fn set_booleans(&self, vrs: &[u32], values: &[bool]) -> fmi3Status {
        // SAFETY: arrays of the lengths passed.
        unsafe {
            (self.functions.set_boolean)(
                self.c,
                vrs.as_ptr(),
                vrs.len(),
                values.as_ptr(),
                values.len(),
            )
        }
    }

    /// One String, `None` unless the get succeeds with a non-NULL string.
    pub fn get_string(&self, vr: u32) -> (fmi3Status, Option<String>) {
        let mut value: fmi3String = std::ptr::null();
        // SAFETY: one element each; the FMU keeps the string alive until its next call.
        let status = unsafe { (self.functions.get_string)(self.c, &vr, 1, &mut value, 1) };
        let text = (status.is_success() && !value.is_null()).then(|| {
            // SAFETY: non-null and NUL-terminated, per the standard.
            unsafe { CStr::from_ptr(value) }
                .to_string_lossy()
                .into_owned()
        });
        (status, text)
    }

    pub fn set_string(&self, vr: u32, value: &str) -> fmi3Status {
        let value = CString::new(value).expect("no NUL in the value");
        let pointer = value.as_ptr();
        // SAFETY: one element each; the string outlives the call.
        unsafe { (self.functions.set_string)(self.c, &vr, 1, &pointer, 1) }
    }

    // ---- FMU state ----

    /// A new FMU state (NULL when refused), with the status.
    pub fn get_state(&self) -> (fmi3Status, fmi3FMUState) {
        let mut state: fmi3FMUState = std::ptr::null_mut();
        // SAFETY: an out-pointer to a NULL state: the FMU allocates one.
        let status = unsafe { (self.functions.get_fmu_state)(self.c, &mut state) };
        (status, state)
    }

    /// Overwrites `state` in place with the instance's current state.
    pub fn get_state_into(&self, state: &mut fmi3FMUState) -> fmi3Status {
        // SAFETY: a state of this instance (or one the test wants refused).
        unsafe { (self.functions.get_fmu_state)(self.c, state) }
    }

    pub fn set_state(&self, state: fmi3FMUState) -> fmi3Status {
        // SAFETY: a state of this instance (or one the test wants refused).
        unsafe { (self.functions.set_fmu_state)(self.c, state) }
    }

    pub fn free_state(&self, mut state: fmi3FMUState) -> fmi3Status {
        // SAFETY: as above; the FMU sets the pointer to NULL.
        unsafe { (self.functions.free_fmu_state)(self.c, &mut state) }
    }

    /// The serialized `state` with the status of the failing call (or fmi3OK).
    pub fn serialize(&self, state: fmi3FMUState) -> (fmi3Status, Vec<u8>) {
        let mut size = 0;
        // SAFETY: one out-element.
        let status =
            unsafe { (self.functions.serialized_fmu_state_size)(self.c, state, &mut size) };
        if status != fmi3OK {
            return (status, Vec::new());
        }
        let mut bytes = vec![0u8; size];
        // SAFETY: a buffer of the announced size.
        let status = unsafe {
            (self.functions.serialize_fmu_state)(self.c, state, bytes.as_mut_ptr(), size)
        };
        (status, bytes)
    }

    /// `bytes` deserialized into a new FMU state (NULL when refused), with the status.
    pub fn deserialize(&self, bytes: &[u8]) -> (fmi3Status, fmi3FMUState) {
        let mut state: fmi3FMUState = std::ptr::null_mut();
        // SAFETY: a buffer of the length passed, an out-pointer to a NULL state.
        let status = unsafe {
            (self.functions.deserialize_fmu_state)(self.c, bytes.as_ptr(), bytes.len(), &mut state)
        };
        (status, state)
    }
}

impl Drop for Fmi3Instance {
    fn drop(&mut self) {
        // SAFETY: the instance is live and not used again.
        unsafe { (self.functions.free_instance)(self.c) };
    }
}

impl TestLogger {
    /// `instanceEnvironment` for FMI 3.0: this logger.
    pub fn environment(&self) -> fmi3InstanceEnvironment {
        self as *const TestLogger as *mut c_void
    }

    /// The FMI 3.0 `logMessage` callback (not variadic: the FMU formats the message) whose
    /// environment is [`TestLogger::environment`]. Records carry no instance name (FMI 3.0
    /// passes none) and the FMI 3.0 status in [`Record::status`] (the same numbers).
    ///
    /// # Safety
    /// `environment` must be a live `TestLogger`, the strings NULL or NUL-terminated.
    pub unsafe extern "C" fn log_message(
        environment: fmi3InstanceEnvironment,
        status: fmi3Status,
        category: fmi3String,
        message: fmi3String,
    ) {
        // Nothing may unwind into the FMU.
        let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            // SAFETY: the caller's promise.
            let Some(logger) = (unsafe { (environment as *const TestLogger).as_ref() }) else {
                return;
            };
            // SAFETY: as above.
            let record = unsafe {
                Record {
                    instance_name: None,
                    status: fmi_abi::fmi2::fmi2Status(status.0),
                    category: fmi_abi::callbacks::text(category),
                    message: fmi_abi::callbacks::text(message),
                }
            };
            logger.push(record);
        }));
    }
}
