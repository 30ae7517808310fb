//! The generic bodies of the `fmi3*` functions; [`export_fmi3!`](crate::export_fmi3)
//! generates the `#[no_mangle]` symbols, each a one-line call into here or into [`crate::me`].
//!
//! Every function that takes an instance goes through [`call`]: NULL, freed or foreign
//! instance -> `fmi3Error` (no logger to tell; the address is looked up in a registry of live
//! instances before anything is read through it); a call while another call on the same
//! instance has not returned (from inside its logMessage callback, or from a second thread)
//! -> `fmi3Error` and one log line; call trace (`logCalls`); the state table
//! ([`Function::admit`], which also refuses the other interface's functions and the
//! features we lack); the body under `catch_unwind` (a panic becomes `fmi3Fatal` and state
//! Fatal); a refusal is logged as one line "fmi3Xxx: reason". Refused arguments leave the
//! instance as it was; a failure of the model itself moves it to state Error.
//!
//! # Safety
//! Every function here is `unsafe`: the master must pass pointers that are valid as the
//! FMI 3.0 standard requires for the function.
#![allow(unsafe_code)]

use crate::error::{CallError, Success};
use crate::ffi::*;
use crate::instance::{Core, Instance, Tag};
use crate::logging::{Category, Logger};
use crate::state::{Function, Interface, Refusal, State};
use crate::variables::{settable, Float64Slot, Type};
pub(crate) use fmi_abi::args::{out, panic_text, show, slice, slice_mut};
use fmi_model::prepared::{Getter, Setter};
use fmi_model::registry::{self, Entered, Registry, Reporting};
use fmi_model::{snapshot, Declaration, Kind, Limit, Log, Model, StepEnd};
use std::ffi::{CStr, CString};
use std::os::raw::c_char;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::ptr;

/// Relative tolerance on communication points, as in the FMI 2.0 layer.
pub const TIME_TOLERANCE: f64 = 1e-9;

fn time_tolerance(reference: f64) -> f64 {
    TIME_TOLERANCE * reference.abs().max(1.0)
}

// ---------------------------------------------------------------------------------------
// Plumbing
// ---------------------------------------------------------------------------------------

/// Every live instance of this FMU, with a copy of its logger to report a refused nested
/// call without reading the busy instance.
static LIVE: Registry<Logger> = Registry::new();

/// The instance behind `c`, marked busy until the returned guard drops. `None` (the call
/// returns `fmi3Error`) when `c` is no live instance of `M` (NULL, freed, foreign: nothing
/// is read through it), or when another call on it has not returned (a call from inside its
/// logMessage callback, or from a second thread: refused with a log line, see
/// [`fmi_model::registry`]).
#[inline(always)]
unsafe fn enter<'a, M: Model>(
    c: fmi3Instance,
    function: Function,
) -> Option<(Entered<'static, Logger>, &'a mut Instance<M>)> {
    let entered = match LIVE.enter(c as usize) {
        Ok(entered) => entered,
        Err(registry::Refusal::Unknown) => return None,
        Err(registry::Refusal::Busy(report)) => {
            refuse_nested(report, function);
            return None;
        }
    };
    // SAFETY: a registered address is a live Box<Instance<_>> from an instantiate function,
    // whose first field is the Tag (repr(C)); the tag check guards against an instance of
    // another model linked into the same process.
    let tag = unsafe { ptr::read(c as *const Tag) };
    if tag != Tag::of::<M>() {
        return None;
    }
    // SAFETY: live, of type M, and no other call holds it (the registry says idle).
    Some((entered, unsafe { &mut *(c as *mut Instance<M>) }))
}

/// Tells the master, through the busy instance's logger, that its nested call was refused
/// (`None`: a call from inside that very report, refused silently).
#[cold]
#[inline(never)]
fn refuse_nested(report: Option<Reporting<'_, Logger>>, function: Function) {
    if let Some(logger) = report {
        logger.status(
            fmi3Error,
            &format!(
                "{}: refused: another call on this instance has not returned yet \
                 (a call from inside its logMessage callback, or from a second thread)",
                function.name()
            ),
        );
    }
}

/// Runs one FMI call on an instance; see the module documentation.
pub(crate) unsafe fn call<M: Model>(
    c: fmi3Instance,
    function: Function,
    trace: impl FnOnce() -> String,
    body: impl FnOnce(&mut Instance<M>) -> Result<Success, CallError>,
) -> fmi3Status {
    let Some((_entered, inst)) = (unsafe { enter::<M>(c, function) }) else {
        return fmi3Error;
    };
    let outcome = catch_unwind(AssertUnwindSafe(|| {
        if inst.logger.is_on(Category::Calls) {
            inst.logger.log(fmi3OK, Category::Calls, &trace());
        }
        let result = match function.admit(inst.interface, inst.core.state) {
            Ok(()) => body(inst),
            Err(refusal) => Err(CallError::Refused(refusal)),
        };
        match result {
            Ok(success) => success.status(),
            Err(error) => {
                let status = error.status();
                inst.logger
                    .status(status, &format!("{}: {error}", function.name()));
                status
            }
        }
    }));
    outcome.unwrap_or_else(|payload| {
        let _ = catch_unwind(AssertUnwindSafe(|| {
            inst.core.state = State::Fatal;
            inst.logger.status(
                fmi3Fatal,
                &format!(
                    "{}: internal error, instance unusable: {}",
                    function.name(),
                    panic_text(payload.as_ref())
                ),
            );
        }));
        fmi3Fatal
    })
}

fn owned(s: fmi3String) -> Option<CString> {
    // SAFETY: NUL-terminated when non-null, per the standard; copied at once.
    (!s.is_null()).then(|| unsafe { CStr::from_ptr(s) }.to_owned())
}

fn shown(s: &Option<CString>) -> String {
    s.as_ref()
        .map_or("NULL".into(), |s| format!("\"{}\"", s.to_string_lossy()))
}

fn flag(b: bool) -> fmi3Boolean {
    b
}

// ---------------------------------------------------------------------------------------
// Without an instance
// ---------------------------------------------------------------------------------------

pub fn get_version() -> *const c_char {
    VERSION.as_ptr()
}

/// The shared body of the instantiate functions; `None` refusal means the interface is ours.
#[allow(clippy::too_many_arguments)]
pub(crate) unsafe fn instantiate<M: Model>(
    interface: Interface,
    supported: Result<(), String>,
    instance_name: fmi3String,
    instantiation_token: fmi3String,
    resource_path: fmi3String,
    logging_on: fmi3Boolean,
    environment: fmi3InstanceEnvironment,
    log_message: fmi3LogMessageCallback,
    extra_trace: String,
) -> fmi3Instance {
    let logger = Logger::new(log_message, environment, logging_on);
    let function = match interface {
        Interface::ModelExchange => "fmi3InstantiateModelExchange",
        Interface::CoSimulation => "fmi3InstantiateCoSimulation",
    };
    let outcome = catch_unwind(AssertUnwindSafe(move || {
        let name = owned(instance_name);
        let token = owned(instantiation_token);
        let resources = owned(resource_path);
        if logger.is_on(Category::Calls) {
            logger.log(
                fmi3OK,
                Category::Calls,
                &format!(
                    "{function}(instanceName={}, instantiationToken={}, resourcePath={}, \
                     loggingOn={logging_on}{extra_trace})",
                    shown(&name),
                    shown(&token),
                    shown(&resources)
                ),
            );
        }
        let expected = crate::instantiation_token::<M>();
        let refusal = if name.as_ref().is_none_or(|n| n.is_empty()) {
            Some("instanceName is NULL or empty".to_string())
        } else if let Err(reason) = supported {
            Some(reason)
        } else if token.as_ref().map(|t| t.to_bytes()) != Some(expected.as_bytes()) {
            Some(format!(
                "instantiationToken {} does not match this FMU's {expected}",
                shown(&token)
            ))
        } else {
            None
        };
        if let Some(reason) = refusal {
            logger.status(fmi3Error, &format!("{function}: {reason}"));
            return ptr::null_mut();
        }
        let report = logger.clone();
        let c = Box::into_raw(Box::new(Instance::<M>::new(logger, interface))) as fmi3Instance;
        if let Err(full) = LIVE.insert(c as usize, report) {
            // SAFETY: `c` came from Box::into_raw just above and was never handed out.
            let instance = unsafe { Box::from_raw(c as *mut Instance<M>) };
            instance
                .logger
                .status(fmi3Error, &format!("{function}: {full}"));
            return ptr::null_mut();
        }
        c
    }));
    outcome.unwrap_or_else(|payload| {
        let logger = Logger::new(log_message, environment, false);
        logger.status(
            fmi3Fatal,
            &format!(
                "{function}: internal error: {}",
                panic_text(payload.as_ref())
            ),
        );
        ptr::null_mut()
    })
}

/// # Safety
/// See the module documentation.
#[allow(clippy::too_many_arguments)]
pub unsafe fn instantiate_co_simulation<M: Model>(
    instance_name: fmi3String,
    instantiation_token: fmi3String,
    resource_path: fmi3String,
    _visible: fmi3Boolean,
    logging_on: fmi3Boolean,
    event_mode_used: fmi3Boolean,
    early_return_allowed: fmi3Boolean,
    _required_intermediate_variables: *const fmi3ValueReference,
    n_required_intermediate_variables: usize,
    environment: fmi3InstanceEnvironment,
    log_message: fmi3LogMessageCallback,
    _intermediate_update: fmi3IntermediateUpdateCallback,
) -> fmi3Instance {
    // An early return is only ever offered, never required: allowing it changes nothing.
    let supported = if event_mode_used {
        Err(
            "eventModeUsed = true: this FMU has no event mode in Co-Simulation \
             (hasEventMode = false)"
                .to_string(),
        )
    } else if n_required_intermediate_variables > 0 {
        Err("intermediate variables are not supported".to_string())
    } else {
        Ok(())
    };
    let trace = format!(
        ", eventModeUsed={event_mode_used}, earlyReturnAllowed={early_return_allowed}, \
         nRequiredIntermediateVariables={n_required_intermediate_variables}"
    );
    unsafe {
        instantiate::<M>(
            Interface::CoSimulation,
            supported,
            instance_name,
            instantiation_token,
            resource_path,
            logging_on,
            environment,
            log_message,
            trace,
        )
    }
}

/// Scheduled Execution is not offered: NULL, with a log line.
///
/// # Safety
/// See the module documentation.
#[allow(clippy::too_many_arguments)]
pub unsafe fn instantiate_scheduled_execution<M: Model>(
    _instance_name: fmi3String,
    _instantiation_token: fmi3String,
    _resource_path: fmi3String,
    _visible: fmi3Boolean,
    _logging_on: fmi3Boolean,
    environment: fmi3InstanceEnvironment,
    log_message: fmi3LogMessageCallback,
    _clock_update: fmi3ClockUpdateCallback,
    _lock_preemption: fmi3LockPreemptionCallback,
    _unlock_preemption: fmi3UnlockPreemptionCallback,
) -> fmi3Instance {
    let _ = catch_unwind(|| {
        Logger::new(log_message, environment, false).status(
            fmi3Error,
            &format!(
                "fmi3InstantiateScheduledExecution: {} offers Co-Simulation{}, not Scheduled \
                 Execution",
                M::MODEL_IDENTIFIER,
                ""
            ),
        );
    });
    ptr::null_mut()
}

/// # Safety
/// See the module documentation.
pub unsafe fn free_instance<M: Model>(c: fmi3Instance) {
    let Some((entered, inst)) = (unsafe { enter::<M>(c, Function::FreeInstance) }) else {
        return;
    };
    let _ = catch_unwind(AssertUnwindSafe(|| {
        if inst.logger.is_on(Category::Calls) {
            inst.logger
                .log(fmi3OK, Category::Calls, "fmi3FreeInstance()");
        }
    }));
    // Unregistered before the memory goes: a second free, or any later call, is refused
    // by address without reading it.
    inst.tag = Tag::cleared();
    entered.remove();
    let _ = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: `c` came from Box::into_raw in instantiate; `inst` is not used again.
        let mut boxed = unsafe { Box::from_raw(c as *mut Instance<M>) };
        for address in boxed.fmu_states.drain() {
            // SAFETY: only addresses from Box::into_raw of a Core<M> are registered.
            drop(unsafe { Box::from_raw(address as *mut Core<M>) });
        }
    }));
}

// ---------------------------------------------------------------------------------------
// Lifecycle
// ---------------------------------------------------------------------------------------

/// # Safety
/// See the module documentation.
pub unsafe fn set_debug_logging<M: Model>(
    c: fmi3Instance,
    logging_on: fmi3Boolean,
    n_categories: usize,
    categories: *const fmi3String,
) -> fmi3Status {
    let f = Function::SetDebugLogging;
    let trace = || {
        format!(
            "{}(loggingOn={logging_on}, nCategories={n_categories})",
            f.name()
        )
    };
    unsafe {
        call::<M>(c, f, trace, |inst| {
            let names = slice(categories, n_categories, "categories")?;
            if names.is_empty() {
                inst.logger.set_all(logging_on);
                return Ok(Success::Ok);
            }
            let mut chosen = Vec::new();
            for &name in names {
                let text = owned(name).ok_or(CallError::NullArgument("categories[i]"))?;
                let category =
                    crate::logging::Category::from_name(text.to_bytes()).ok_or_else(|| {
                        CallError::InvalidArgument(format!(
                            "unknown log category \"{}\"",
                            text.to_string_lossy()
                        ))
                    })?;
                chosen.push(category);
            }
            for category in chosen {
                inst.logger.set(category, logging_on);
            }
            Ok(Success::Ok)
        })
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn enter_initialization_mode<M: Model>(
    c: fmi3Instance,
    tolerance_defined: fmi3Boolean,
    tolerance: fmi3Float64,
    start_time: fmi3Float64,
    stop_time_defined: fmi3Boolean,
    stop_time: fmi3Float64,
) -> fmi3Status {
    let f = Function::EnterInitializationMode;
    let trace = || {
        format!(
            "{}(toleranceDefined={tolerance_defined}, tolerance={tolerance}, \
             startTime={start_time}, stopTimeDefined={stop_time_defined}, stopTime={stop_time})",
            f.name()
        )
    };
    unsafe {
        call::<M>(c, f, trace, |inst| {
            if !start_time.is_finite() {
                return Err(CallError::InvalidArgument(format!(
                    "startTime {start_time} is not finite"
                )));
            }
            if stop_time_defined && !(stop_time.is_finite() && stop_time >= start_time) {
                return Err(CallError::InvalidArgument(format!(
                    "stopTime {stop_time} is not a finite time at or after startTime {start_time}"
                )));
            }
            let core = &mut inst.core;
            core.start_time = start_time;
            core.time = start_time;
            core.stop_time = stop_time_defined.then_some(stop_time);
            core.state = State::InitializationMode;
            inst.dirty = true;
            Ok(Success::Ok)
        })
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn exit_initialization_mode<M: Model>(c: fmi3Instance) -> fmi3Status {
    let f = Function::ExitInitializationMode;
    unsafe {
        call::<M>(
            c,
            f,
            || format!("{}()", f.name()),
            |inst| {
                let mut log = Log::default();
                let start_time = inst.core.start_time;
                let result = inst.core.model.exit_initialization(start_time, &mut log);
                let success = inst.forward(f, &log);
                result.map_err(|e| inst.model_failure(e))?;
                inst.core.state = match inst.interface {
                    Interface::ModelExchange => State::EventMode,
                    Interface::CoSimulation => State::StepMode,
                };
                inst.dirty = true;
                Ok(success)
            },
        )
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn terminate<M: Model>(c: fmi3Instance) -> fmi3Status {
    let f = Function::Terminate;
    unsafe {
        call::<M>(
            c,
            f,
            || format!("{}()", f.name()),
            |inst| {
                inst.core.state = State::Terminated;
                Ok(Success::Ok)
            },
        )
    }
}

/// Back to the freshly instantiated state (logging flags and FMU states stay).
///
/// # Safety
/// See the module documentation.
pub unsafe fn reset<M: Model>(c: fmi3Instance) -> fmi3Status {
    let f = Function::Reset;
    unsafe {
        call::<M>(
            c,
            f,
            || format!("{}()", f.name()),
            |inst| {
                inst.core = Core::fresh();
                inst.dirty = true;
                Ok(Success::Ok)
            },
        )
    }
}

/// Any function of a feature this FMU lacks: the table refuses it with the reason.
///
/// # Safety
/// See the module documentation.
pub unsafe fn unsupported<M: Model>(c: fmi3Instance, f: Function) -> fmi3Status {
    unsafe {
        call::<M>(
            c,
            f,
            || format!("{}(...)", f.name()),
            |_| {
                Err(CallError::Refused(match f.scope() {
                    crate::state::Scope::Unsupported(feature) => Refusal::Unsupported(feature),
                    _ => Refusal::Unsupported("implementation of this function"),
                }))
            },
        )
    }
}

// ---------------------------------------------------------------------------------------
// Get and set
// ---------------------------------------------------------------------------------------

fn lookup<M: Model>(
    inst: &Instance<M>,
    vr: fmi3ValueReference,
    ty: Type,
) -> Result<&'static Declaration<M>, CallError> {
    match inst.index.get::<M>(vr) {
        Some(d) if Type::of(d) == ty => Ok(d),
        _ => Err(CallError::UnknownValueReference {
            vr,
            type_name: ty.api_name(),
        }),
    }
}

/// Checks that every reference is a variable of type `ty` and that `nValues` is the total
/// element count of them (looked up again by the caller's next pass: an array read is
/// cheaper than keeping a list).
fn count_elements<M: Model>(
    inst: &Instance<M>,
    vrs: &[fmi3ValueReference],
    ty: Type,
    n_values: usize,
) -> Result<(), CallError> {
    let mut total = 0;
    for &vr in vrs {
        total += lookup(inst, vr, ty)?.shape().len();
    }
    if total != n_values {
        return Err(wrong_count(n_values, vrs.len(), total));
    }
    Ok(())
}

#[cold]
fn wrong_count(n_values: usize, n_vrs: usize, total: usize) -> CallError {
    CallError::InvalidArgument(format!(
        "nValues = {n_values}, the {n_vrs} variables asked for have {total} elements"
    ))
}

/// The declaration at a reference `count_elements` has accepted.
fn checked<M: Model>(inst: &Instance<M>, vr: fmi3ValueReference) -> &'static Declaration<M> {
    inst.index
        .get::<M>(vr)
        .expect("looked up by count_elements in this call")
}

/// [`count_elements`], returning the declarations (for the types exchanged rarely).
fn check_count<M: Model>(
    inst: &Instance<M>,
    vrs: &[fmi3ValueReference],
    ty: Type,
    n_values: usize,
) -> Result<Vec<&'static Declaration<M>>, CallError> {
    count_elements(inst, vrs, ty, n_values)?;
    Ok(vrs.iter().map(|&vr| checked(inst, vr)).collect())
}

/// # Safety
/// See the module documentation.
pub unsafe fn get_float64<M: Model>(
    c: fmi3Instance,
    vrs: *const fmi3ValueReference,
    n_vrs: usize,
    values: *mut fmi3Float64,
    n_values: usize,
) -> fmi3Status {
    let f = Function::GetFloat64;
    let trace = || unsafe { format!("{}(vr={})", f.name(), show(vrs, n_vrs)) };
    unsafe {
        call::<M>(c, f, trace, |inst| {
            let vrs = slice(vrs, n_vrs, "valueReferences")?;
            let values = slice_mut(values, n_values, "values")?;
            let success = inst.refresh(f);
            let (index, table) = (&inst.index, &inst.float64);
            let prepared = inst
                .prepared_get
                .read(vrs, values, &inst.core.model, |vr, out| {
                    match index.row(vr).and_then(|row| table.get(row)) {
                        Some(Some(slot)) => {
                            out.extend((0..slot.len).map(|element| Getter {
                                get: slot.get,
                                element,
                            }));
                            true
                        }
                        _ => false,
                    }
                });
            if prepared {
                return Ok(success);
            }
            // `time` may stand anywhere in the list, as one element. One pass: each
            // variable's elements are written as it is found; a wrong count or an unknown
            // reference refuses the call (what was written then is not a result).
            let mut k = 0;
            for &vr in vrs {
                if vr == crate::variables::TIME_VR {
                    *values
                        .get_mut(k)
                        .ok_or_else(|| count_error(inst, vrs, n_values))? = inst.core.time;
                    k += 1;
                    continue;
                }
                let slot = float64(inst, vr)?;
                let out = values
                    .get_mut(k..k + slot.len)
                    .ok_or_else(|| count_error(inst, vrs, n_values))?;
                for (i, value) in out.iter_mut().enumerate() {
                    *value = (slot.get)(&inst.core.model, i);
                }
                k += slot.len;
            }
            if k != n_values {
                return Err(count_error(inst, vrs, n_values));
            }
            Ok(success)
        })
    }
}

/// The Float64 variable at `vr`, in the exchange's form.
#[inline]
fn float64<M: Model>(
    inst: &Instance<M>,
    vr: fmi3ValueReference,
) -> Result<&Float64Slot<M>, CallError> {
    match inst.index.row(vr).and_then(|row| inst.float64.get(row)) {
        Some(Some(slot)) => Ok(slot),
        _ => Err(unknown_float64(vr)),
    }
}

#[cold]
fn unknown_float64(vr: fmi3ValueReference) -> CallError {
    CallError::UnknownValueReference {
        vr,
        type_name: Type::Float64.api_name(),
    }
}

/// The error of a Float64 call whose `nValues` is not the element count of its references
/// (all known: an unknown one is reported first, as it is met).
#[cold]
fn count_error<M: Model>(
    inst: &Instance<M>,
    vrs: &[fmi3ValueReference],
    n_values: usize,
) -> CallError {
    let mut total = 0;
    for &vr in vrs {
        total += if vr == crate::variables::TIME_VR {
            1
        } else {
            match float64(inst, vr) {
                Ok(slot) => slot.len,
                Err(unknown) => return unknown,
            }
        };
    }
    wrong_count(n_values, vrs.len(), total)
}

/// Why element `i` of `d` (of `len` elements) refuses `v`; built only for a refusal.
#[cold]
fn refused_float64<M>(
    d: &Declaration<M>,
    len: usize,
    i: usize,
    v: f64,
    min: Option<Limit>,
    max: Option<Limit>,
) -> CallError {
    let element = if len > 1 {
        format!("[{}]", i + 1)
    } else {
        String::new()
    };
    let reason = if v.is_finite() {
        format!("value{element} {v} is outside {}", bounds(min, max))
    } else {
        format!("value{element} {v} is not finite")
    };
    CallError::InvalidValue {
        name: d.name,
        vr: d.value_reference,
        reason,
    }
}

fn refuse_set<M>(d: &Declaration<M>, reason: &'static str) -> CallError {
    CallError::NotSettable {
        name: d.name,
        vr: d.value_reference,
        reason,
    }
}

/// The two kinds of state a Float64's settability depends on, as bits for
/// [`fmi_model::prepared`].
const INITIALIZING: u16 = 1;
const RUNNING: u16 = 2;

fn initializing(state: State) -> bool {
    matches!(state, State::Instantiated | State::InitializationMode)
}

/// # Safety
/// See the module documentation.
pub unsafe fn set_float64<M: Model>(
    c: fmi3Instance,
    vrs: *const fmi3ValueReference,
    n_vrs: usize,
    values: *const fmi3Float64,
    n_values: usize,
) -> fmi3Status {
    let f = Function::SetFloat64;
    let trace = || unsafe {
        format!(
            "{}(vr={}, values={})",
            f.name(),
            show(vrs, n_vrs),
            show(values, n_values)
        )
    };
    unsafe {
        call::<M>(c, f, trace, |inst| {
            let vrs = slice(vrs, n_vrs, "valueReferences")?;
            let values = slice(values, n_values, "values")?;
            let initializing = initializing(inst.core.state);
            let (index, table) = (&inst.index, &inst.float64);
            let prepared = inst.prepared_set.write(
                vrs,
                values,
                &mut inst.core.model,
                if initializing { INITIALIZING } else { RUNNING },
                |vr, out| match index.row(vr).and_then(|row| table.get(row)) {
                    Some(Some(slot)) => slot.set.is_some_and(|set| {
                        let settable_in = (u16::from(slot.settable_initializing) * INITIALIZING)
                            | (u16::from(slot.settable_running) * RUNNING);
                        out.extend((0..slot.len).map(|element| Setter {
                            set,
                            element,
                            lowest: slot.lowest,
                            highest: slot.highest,
                            settable_in,
                        }));
                        true
                    }),
                    _ => false,
                },
            );
            if prepared {
                inst.dirty |= !vrs.is_empty();
                return Ok(Success::Ok);
            }
            // Check every value before writing any: a refused call changes nothing.
            let mut k = 0;
            for &vr in vrs {
                let slot = float64(inst, vr)?;
                let allowed = if initializing {
                    slot.settable_initializing
                } else {
                    slot.settable_running
                };
                if !allowed {
                    let d = slot.declaration;
                    settable(d, initializing).map_err(|r| refuse_set(d, r))?;
                }
                let given = values
                    .get(k..k + slot.len)
                    .ok_or_else(|| count_error(inst, vrs, n_values))?;
                for (i, &v) in given.iter().enumerate() {
                    if !slot.admits(v) {
                        let (min, max) = match slot.declaration.kind {
                            Kind::Real { min, max, .. } => (min, max),
                            _ => (None, None),
                        };
                        return Err(refused_float64(slot.declaration, slot.len, i, v, min, max));
                    }
                }
                k += slot.len;
            }
            if k != n_values {
                return Err(count_error(inst, vrs, n_values));
            }
            let mut k = 0;
            for &vr in vrs {
                let (set, len) = float64(inst, vr).map(|slot| (slot.set, slot.len))?;
                if let Some(set) = set {
                    for (i, &v) in values[k..k + len].iter().enumerate() {
                        set(&mut inst.core.model, i, v);
                    }
                }
                k += len;
            }
            if !vrs.is_empty() {
                inst.dirty = true;
            }
            Ok(Success::Ok)
        })
    }
}

fn bounds(min: Option<fmi_model::Limit>, max: Option<fmi_model::Limit>) -> String {
    use fmi_model::Limit;
    let low = match min {
        Some(Limit::Inclusive(v)) => format!("[{v}"),
        Some(Limit::Exclusive(v)) => format!("({v}"),
        None => "(-inf".into(),
    };
    let high = match max {
        Some(Limit::Inclusive(v)) => format!("{v}]"),
        Some(Limit::Exclusive(v)) => format!("{v})"),
        None => "inf)".into(),
    };
    format!("{low}, {high}")
}

/// The shared body of the gets of one-element types: look every value reference up as
/// `ty`, check `nValues`, and let `read` give each declaration's value.
#[allow(clippy::too_many_arguments)]
unsafe fn get_scalars<M: Model, V>(
    c: fmi3Instance,
    f: Function,
    ty: Type,
    vrs: *const fmi3ValueReference,
    n_vrs: usize,
    values: *mut V,
    n_values: usize,
    read: fn(&Kind<M>, &M) -> Option<V>,
) -> fmi3Status {
    let trace = || unsafe { format!("{}(vr={})", f.name(), show(vrs, n_vrs)) };
    unsafe {
        call::<M>(c, f, trace, |inst| {
            let vrs = slice(vrs, n_vrs, "valueReferences")?;
            let values = slice_mut(values, n_values, "values")?;
            let success = inst.refresh(f);
            let decls = check_count(inst, vrs, ty, n_values)?;
            for (d, value) in decls.into_iter().zip(values) {
                if let Some(v) = read(&d.kind, &inst.core.model) {
                    *value = v;
                }
            }
            Ok(success)
        })
    }
}

/// The shared body of the sets of one-element types: every value checked by `check` (after
/// the settable rule) before `write` writes any, so a refused call changes nothing.
#[allow(clippy::too_many_arguments)]
unsafe fn set_scalars<M: Model, V: Copy + std::fmt::Debug>(
    c: fmi3Instance,
    f: Function,
    ty: Type,
    vrs: *const fmi3ValueReference,
    n_vrs: usize,
    values: *const V,
    n_values: usize,
    check: fn(&Kind<M>, V) -> Result<(), String>,
    write: fn(&Kind<M>, &mut M, V),
) -> fmi3Status {
    let trace = || unsafe {
        format!(
            "{}(vr={}, values={})",
            f.name(),
            show(vrs, n_vrs),
            show(values, n_values)
        )
    };
    unsafe {
        call::<M>(c, f, trace, |inst| {
            let vrs = slice(vrs, n_vrs, "valueReferences")?;
            let values = slice(values, n_values, "values")?;
            let decls = check_count(inst, vrs, ty, n_values)?;
            for (d, &v) in decls.iter().zip(values) {
                settable(d, initializing(inst.core.state)).map_err(|r| refuse_set(d, r))?;
                check(&d.kind, v).map_err(|reason| CallError::InvalidValue {
                    name: d.name,
                    vr: d.value_reference,
                    reason,
                })?;
            }
            for (d, &v) in decls.iter().zip(values) {
                write(&d.kind, &mut inst.core.model, v);
            }
            inst.dirty |= !vrs.is_empty();
            Ok(Success::Ok)
        })
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn get_int32<M: Model>(
    c: fmi3Instance,
    vrs: *const fmi3ValueReference,
    n_vrs: usize,
    values: *mut fmi3Int32,
    n_values: usize,
) -> fmi3Status {
    let read = |kind: &Kind<M>, m: &M| match kind {
        Kind::Integer { get, .. } | Kind::Enumeration { get, .. } => Some(get(m)),
        _ => None,
    };
    unsafe {
        get_scalars(
            c,
            Function::GetInt32,
            Type::Int32,
            vrs,
            n_vrs,
            values,
            n_values,
            read,
        )
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn set_int32<M: Model>(
    c: fmi3Instance,
    vrs: *const fmi3ValueReference,
    n_vrs: usize,
    values: *const fmi3Int32,
    n_values: usize,
) -> fmi3Status {
    let check = |kind: &Kind<M>, v: i32| match kind {
        Kind::Integer { min, max, .. }
            if min.is_some_and(|m| v < m) || max.is_some_and(|m| v > m) =>
        {
            let low = min.map_or("(-inf".to_string(), |m| format!("[{m}"));
            let high = max.map_or("inf)".to_string(), |m| format!("{m}]"));
            Err(format!("value {v} is outside {low}, {high}"))
        }
        Kind::Enumeration { ty, .. } if ty.item(v).is_none() => {
            Err(format!("{v} is not one of {}", ty.listing()))
        }
        _ => Ok(()),
    };
    let write = |kind: &Kind<M>, m: &mut M, v: i32| match kind {
        Kind::Integer { set: Some(set), .. } | Kind::Enumeration { set: Some(set), .. } => {
            set(m, v)
        }
        _ => {}
    };
    unsafe {
        set_scalars(
            c,
            Function::SetInt32,
            Type::Int32,
            vrs,
            n_vrs,
            values,
            n_values,
            check,
            write,
        )
    }
}

/// Enumerations, which FMI 3.0 exchanges as Int64.
///
/// # Safety
/// See the module documentation.
pub unsafe fn get_int64<M: Model>(
    c: fmi3Instance,
    vrs: *const fmi3ValueReference,
    n_vrs: usize,
    values: *mut fmi3Int64,
    n_values: usize,
) -> fmi3Status {
    let read = |kind: &Kind<M>, m: &M| match kind {
        Kind::Enumeration { get, .. } => Some(i64::from(get(m))),
        _ => None,
    };
    unsafe {
        get_scalars(
            c,
            Function::GetInt64,
            Type::Enumeration,
            vrs,
            n_vrs,
            values,
            n_values,
            read,
        )
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn set_int64<M: Model>(
    c: fmi3Instance,
    vrs: *const fmi3ValueReference,
    n_vrs: usize,
    values: *const fmi3Int64,
    n_values: usize,
) -> fmi3Status {
    let check = |kind: &Kind<M>, v: i64| match kind {
        Kind::Enumeration { ty, .. } => i32::try_from(v)
            .ok()
            .filter(|&v| ty.item(v).is_some())
            .map(|_| ())
            .ok_or_else(|| format!("{v} is not an item of {}", ty.listing())),
        _ => Ok(()),
    };
    let write = |kind: &Kind<M>, m: &mut M, v: i64| {
        if let (Kind::Enumeration { set: Some(set), .. }, Ok(v)) = (kind, i32::try_from(v)) {
            set(m, v);
        }
    };
    unsafe {
        set_scalars(
            c,
            Function::SetInt64,
            Type::Enumeration,
            vrs,
            n_vrs,
            values,
            n_values,
            check,
            write,
        )
    }
}

/// Booleans cross as bytes (C's `bool`): written 0/1, and a value other than 0/1 from a
/// careless master is read as true, never as an invalid Rust `bool`.
///
/// # Safety
/// See the module documentation.
pub unsafe fn get_boolean<M: Model>(
    c: fmi3Instance,
    vrs: *const fmi3ValueReference,
    n_vrs: usize,
    values: *mut fmi3Boolean,
    n_values: usize,
) -> fmi3Status {
    let read = |kind: &Kind<M>, m: &M| match kind {
        Kind::Boolean { get, .. } => Some(u8::from(get(m))),
        _ => None,
    };
    let values = values as *mut u8;
    unsafe {
        get_scalars(
            c,
            Function::GetBoolean,
            Type::Boolean,
            vrs,
            n_vrs,
            values,
            n_values,
            read,
        )
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn set_boolean<M: Model>(
    c: fmi3Instance,
    vrs: *const fmi3ValueReference,
    n_vrs: usize,
    values: *const fmi3Boolean,
    n_values: usize,
) -> fmi3Status {
    let write = |kind: &Kind<M>, m: &mut M, v: u8| {
        if let Kind::Boolean { set: Some(set), .. } = kind {
            set(m, v != 0);
        }
    };
    let values = values as *const u8;
    unsafe {
        set_scalars(
            c,
            Function::SetBoolean,
            Type::Boolean,
            vrs,
            n_vrs,
            values,
            n_values,
            |_, _| Ok(()),
            write,
        )
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn get_string<M: Model>(
    c: fmi3Instance,
    vrs: *const fmi3ValueReference,
    n_vrs: usize,
    values: *mut fmi3String,
    n_values: usize,
) -> fmi3Status {
    let f = Function::GetString;
    let trace = || unsafe { format!("{}(vr={})", f.name(), show(vrs, n_vrs)) };
    unsafe {
        call::<M>(c, f, trace, |inst| {
            let vrs = slice(vrs, n_vrs, "valueReferences")?;
            let values = slice_mut(values, n_values, "values")?;
            let success = inst.refresh(f);
            let decls = check_count(inst, vrs, Type::String, n_values)?;
            let strings: Vec<CString> = decls
                .iter()
                .map(|d| match &d.kind {
                    Kind::String { get, .. } => crate::logging::sanitize(get(&inst.core.model)),
                    _ => CString::default(),
                })
                .collect();
            inst.returned_strings = strings;
            for (value, s) in values.iter_mut().zip(&inst.returned_strings) {
                *value = s.as_ptr();
            }
            Ok(success)
        })
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn set_string<M: Model>(
    c: fmi3Instance,
    vrs: *const fmi3ValueReference,
    n_vrs: usize,
    values: *const fmi3String,
    n_values: usize,
) -> fmi3Status {
    let f = Function::SetString;
    let trace = || unsafe { format!("{}(vr={})", f.name(), show(vrs, n_vrs)) };
    unsafe {
        call::<M>(c, f, trace, |inst| {
            let vrs = slice(vrs, n_vrs, "valueReferences")?;
            let values = slice(values, n_values, "values")?;
            let decls = check_count(inst, vrs, Type::String, n_values)?;
            let mut texts = Vec::with_capacity(decls.len());
            for (d, &v) in decls.iter().zip(values) {
                settable(d, initializing(inst.core.state)).map_err(|r| refuse_set(d, r))?;
                let text = owned(v).ok_or(CallError::NullArgument("values[i]"))?;
                texts.push(text.to_string_lossy().into_owned());
            }
            for (d, text) in decls.iter().zip(&texts) {
                if let Kind::String { set: Some(set), .. } = &d.kind {
                    set(&mut inst.core.model, text);
                }
            }
            inst.dirty |= !vrs.is_empty();
            Ok(Success::Ok)
        })
    }
}

/// Get and set of a type no variable has: only the empty request is valid.
///
/// # Safety
/// See the module documentation.
pub unsafe fn no_variables<M: Model>(
    c: fmi3Instance,
    f: Function,
    vrs: *const fmi3ValueReference,
    n_vrs: usize,
) -> fmi3Status {
    let type_name = &f.name()[7..];
    let trace = || unsafe { format!("{}(vr={})", f.name(), show(vrs, n_vrs)) };
    unsafe {
        call::<M>(c, f, trace, |_| {
            let vrs = slice(vrs, n_vrs, "valueReferences")?;
            match vrs.first() {
                None => Ok(Success::Ok),
                Some(&vr) => Err(CallError::UnknownValueReference {
                    vr,
                    type_name: if type_name.is_empty() {
                        "this type"
                    } else {
                        type_name
                    },
                }),
            }
        })
    }
}

// ---------------------------------------------------------------------------------------
// FMU state
// ---------------------------------------------------------------------------------------

fn owned_state<M: Model>(
    inst: &Instance<M>,
    state: fmi3FMUState,
) -> Result<&'static mut Core<M>, CallError> {
    if state.is_null() {
        return Err(CallError::NullArgument("FMUState"));
    }
    if !inst.fmu_states.contains(&(state as usize)) {
        return Err(CallError::InvalidArgument(format!(
            "FMUState {state:p} was not created by this instance (or was freed)"
        )));
    }
    // SAFETY: registered addresses come from Box::into_raw of a Core<M> and are removed
    // when freed.
    Ok(unsafe { &mut *(state as *mut Core<M>) })
}

fn store_state<M: Model>(
    inst: &mut Instance<M>,
    slot: &mut fmi3FMUState,
    core: Core<M>,
) -> Result<Success, CallError> {
    if slot.is_null() {
        let address = Box::into_raw(Box::new(core));
        inst.fmu_states.insert(address as usize);
        *slot = address as fmi3FMUState;
    } else {
        *owned_state(inst, *slot)? = core;
    }
    Ok(Success::Ok)
}

fn snapshot_header<M: Model>(inst: &Instance<M>) -> snapshot::Header {
    snapshot::Header {
        magic: crate::SNAPSHOT_MAGIC,
        state_version: M::STATE_VERSION,
        guid: inst.token,
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn get_fmu_state<M: Model>(c: fmi3Instance, state: *mut fmi3FMUState) -> fmi3Status {
    let f = Function::GetFMUState;
    unsafe {
        call::<M>(
            c,
            f,
            || format!("{}()", f.name()),
            |inst| {
                let slot = out(state, "FMUState")?;
                let core = inst.core.clone();
                store_state(inst, slot, core)
            },
        )
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn set_fmu_state<M: Model>(c: fmi3Instance, state: fmi3FMUState) -> fmi3Status {
    let f = Function::SetFMUState;
    unsafe {
        call::<M>(
            c,
            f,
            || format!("{}(FMUState={state:p})", f.name()),
            |inst| {
                let core = owned_state(inst, state)?;
                crate::restore::validate(core)?;
                inst.core = core.clone();
                inst.dirty = true;
                Ok(Success::Ok)
            },
        )
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn free_fmu_state<M: Model>(c: fmi3Instance, state: *mut fmi3FMUState) -> fmi3Status {
    let f = Function::FreeFMUState;
    unsafe {
        call::<M>(
            c,
            f,
            || format!("{}()", f.name()),
            |inst| {
                let slot = out(state, "FMUState")?;
                if slot.is_null() {
                    return Ok(Success::Ok);
                }
                owned_state(inst, *slot)?;
                inst.fmu_states.remove(&(*slot as usize));
                // SAFETY: registered (checked above), hence a live Box<Core<M>>.
                drop(Box::from_raw(*slot as *mut Core<M>));
                *slot = ptr::null_mut();
                Ok(Success::Ok)
            },
        )
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn serialized_fmu_state_size<M: Model>(
    c: fmi3Instance,
    state: fmi3FMUState,
    size: *mut usize,
) -> fmi3Status {
    let f = Function::SerializedFMUStateSize;
    unsafe {
        call::<M>(
            c,
            f,
            || format!("{}(FMUState={state:p})", f.name()),
            |inst| {
                let size = out(size, "size")?;
                *size =
                    snapshot::encode(owned_state(inst, state)?, snapshot_header::<M>(inst))?.len();
                Ok(Success::Ok)
            },
        )
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn serialize_fmu_state<M: Model>(
    c: fmi3Instance,
    state: fmi3FMUState,
    serialized: *mut fmi3Byte,
    size: usize,
) -> fmi3Status {
    let f = Function::SerializeFMUState;
    unsafe {
        call::<M>(
            c,
            f,
            || format!("{}(FMUState={state:p}, size={size})", f.name()),
            |inst| {
                let bytes =
                    snapshot::encode(owned_state(inst, state)?, snapshot_header::<M>(inst))?;
                if size != bytes.len() {
                    return Err(CallError::InvalidArgument(format!(
                        "size {size} differs from fmi3SerializedFMUStateSize = {}",
                        bytes.len()
                    )));
                }
                slice_mut(serialized, size, "serializedState")?.copy_from_slice(&bytes);
                Ok(Success::Ok)
            },
        )
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn deserialize_fmu_state<M: Model>(
    c: fmi3Instance,
    serialized: *const fmi3Byte,
    size: usize,
    state: *mut fmi3FMUState,
) -> fmi3Status {
    let f = Function::DeserializeFMUState;
    unsafe {
        call::<M>(
            c,
            f,
            || format!("{}(size={size})", f.name()),
            |inst| {
                let bytes = slice(serialized, size, "serializedState")?;
                let slot = out(state, "FMUState")?;
                let core = snapshot::decode::<Core<M>>(bytes, snapshot_header::<M>(inst))?;
                crate::restore::validate(&core)?;
                store_state(inst, slot, core)
            },
        )
    }
}

// ---------------------------------------------------------------------------------------
// Co-Simulation
// ---------------------------------------------------------------------------------------

/// # Safety
/// See the module documentation.
#[allow(clippy::too_many_arguments)]
pub unsafe fn do_step<M: Model>(
    c: fmi3Instance,
    current_communication_point: fmi3Float64,
    communication_step_size: fmi3Float64,
    no_set_fmu_state_prior_to_current_point: fmi3Boolean,
    event_handling_needed: *mut fmi3Boolean,
    terminate_simulation: *mut fmi3Boolean,
    early_return: *mut fmi3Boolean,
    last_successful_time: *mut fmi3Float64,
) -> fmi3Status {
    let f = Function::DoStep;
    let (t, h) = (current_communication_point, communication_step_size);
    let trace = || {
        format!(
            "{}(currentCommunicationPoint={t}, communicationStepSize={h}, \
             noSetFMUStatePriorToCurrentPoint={no_set_fmu_state_prior_to_current_point})",
            f.name()
        )
    };
    unsafe {
        call::<M>(c, f, trace, |inst| {
            let event = out(event_handling_needed, "eventHandlingNeeded")?;
            let terminate = out(terminate_simulation, "terminateSimulation")?;
            let early = out(early_return, "earlyReturn")?;
            let last = out(last_successful_time, "lastSuccessfulTime")?;
            *event = flag(false);
            *early = flag(false);
            *terminate = flag(inst.core.terminated);
            *last = inst.core.time;
            let result = step(inst, t, h);
            *terminate = flag(inst.core.terminated);
            *last = inst.core.time;
            result
        })
    }
}

fn step<M: Model>(inst: &mut Instance<M>, t: f64, h: f64) -> Result<Success, CallError> {
    let f = Function::DoStep;
    if !(h.is_finite() && h > 0.0) {
        return Err(CallError::InvalidArgument(format!(
            "communicationStepSize {h} is not a finite positive number"
        )));
    }
    let time = inst.core.time;
    // Written so that a NaN anywhere refuses: a corrupt own time must not let any point in.
    if !(t.is_finite() && time.is_finite() && (t - time).abs() <= time_tolerance(time)) {
        return Err(CallError::InvalidArgument(format!(
            "currentCommunicationPoint {t} does not match the FMU's time {time} \
             (relative tolerance {TIME_TOLERANCE:e})"
        )));
    }
    let end = t + h;
    if !(end.is_finite() && end > t) {
        return Err(CallError::InvalidArgument(format!(
            "currentCommunicationPoint {t} + communicationStepSize {h} = {end}: the step \
             does not advance a finite time"
        )));
    }
    if let Some(stop) = inst.core.stop_time {
        if end > stop + time_tolerance(stop) {
            return Err(CallError::InvalidArgument(format!(
                "step to {end} passes the stop time {stop} given to fmi3EnterInitializationMode"
            )));
        }
    }
    let mut log = Log::default();
    let result = inst.core.model.do_step(t, h, &mut log);
    inst.dirty = true;
    let success = inst.forward(f, &log);
    match result.map_err(|e| inst.model_failure(e))? {
        StepEnd::Complete => {
            inst.core.time = end;
            Ok(success)
        }
        StepEnd::Stopped {
            time: stopped,
            terminated,
            reason,
        } => {
            if !(t..=end).contains(&stopped) {
                inst.core.state = State::Error;
                return Err(CallError::Model(format!(
                    "model error: stopped at {stopped}, outside the step [{t}, {end}]"
                )));
            }
            inst.core.time = stopped;
            inst.core.terminated = terminated;
            Err(CallError::Discard(format!(
                "step ended early at t = {stopped}{}: {reason}",
                if terminated { " (terminated)" } else { "" }
            )))
        }
    }
}
