//! The generic bodies of the 34 `fmi2*` functions. [`export_fmi2!`](crate::export_fmi2)
//! generates the `#[no_mangle]` symbols in the model crate, each a one-line call into here.
//!
//! Every function that takes an instance goes through [`call`]: NULL, freed or foreign
//! component -> `fmi2Error` (no logger to tell; the address is looked up in a registry of
//! live instances before anything is read through it); a call while another call on the
//! same instance has not returned (from inside its logger) -> `fmi2Error` and a log line; call trace (`logCalls`); state-machine check against
//! the table of [`Function::legal_states`]; the body under `catch_unwind` (a panic becomes
//! `fmi2Fatal` and state Fatal); a refusal is logged as one line "fmi2Xxx: reason".
//!
//! Refused arguments (illegal call sequence, NULL array, unknown value reference, value not
//! settable/non-finite/out of range, bad communication point) leave the instance as it
//! was, like the Reference FMUs: the call had no effect, so there is nothing to recover
//! from. A failure of the model itself (`exit_initialization` or `do_step` returning an
//! error) moves it to state Error as the standard's state machine says; `fmi2Reset`,
//! `fmi2SetFMUstate` or `fmi2FreeInstance` lead on from there.
//!
//! # Safety
//! Every function here is `unsafe`: the caller (the generated symbol, i.e. the master)
//! must pass pointers that are valid as the FMI 2.0 standard requires for the function.
#![allow(unsafe_code)]

use crate::error::{CallError, Success};
use crate::ffi::*;
use crate::index::BaseType;
use crate::instance::{Core, Instance, Tag};
use crate::logging::{Category, Logger};
use crate::model::{Log, Model, StepEnd};
use crate::rules::{check_enumeration, check_integer, check_real, check_settable};
use crate::state::{Function, State};
use crate::variable::{Access, Variable};
pub(crate) use fmi_abi::args::{out, panic_text, show, slice, slice_mut};
use fmi_model::prepared::{Getter, Setter};
use fmi_model::registry::{Entered, Refusal, Registry, Reporting};
use fmi_model::snapshot;
use std::ffi::{CStr, CString};
use std::os::raw::c_char;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::ptr;

/// Relative tolerance on communication points: masters accumulate `t += h` and arrive a
/// few ulps off (fmpy reaches step 1200 of 0.01 s at 11.999999999999789). A point `t` is
/// accepted when `|t - time| <= 1e-9 * max(1, |time|)`; the same bound applies to the
/// declared stop time.
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
/// returns `fmi2Error`) when `c` is no live instance of `M` (NULL, freed, foreign: nothing
/// is read through it), or when another call on it has not returned (a call from inside one
/// of its callbacks, or from a second thread: refused with a log line, see
/// [`fmi_model::registry`]).
#[inline(always)]
unsafe fn enter<'a, M: Model>(
    c: fmi2Component,
    function: Function,
) -> Option<(Entered<'static, Logger>, &'a mut Instance<M>)> {
    let entered = match LIVE.enter(c as usize) {
        Ok(entered) => entered,
        Err(Refusal::Unknown) => return None,
        Err(Refusal::Busy(report)) => {
            refuse_nested(report, function);
            return None;
        }
    };
    // SAFETY: a registered address is a live Box<Instance<_>> from fmi2Instantiate, whose
    // first field is the Tag (repr(C)); the tag check guards against an instance of another
    // model linked into the same process.
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
            fmi2Error,
            &format!(
                "{}: refused: another call on this instance has not returned yet \
                 (a call from inside one of its callbacks, or from a second thread)",
                function.name()
            ),
        );
    }
}

/// Runs one FMI call on an instance; see the module documentation.
pub(crate) unsafe fn call<M: Model>(
    c: fmi2Component,
    function: Function,
    trace: impl FnOnce() -> String,
    body: impl FnOnce(&mut Instance<M>) -> Result<Success, CallError>,
) -> fmi2Status {
    let Some((_entered, inst)) = (unsafe { enter::<M>(c, function) }) else {
        return fmi2Error;
    };
    let outcome = catch_unwind(AssertUnwindSafe(|| {
        if inst.logger.is_on(Category::Calls) {
            inst.logger.log(fmi2OK, Category::Calls, &trace());
        }
        let state = inst.core.state;
        let result = if function.legal_states().contains(state) {
            body(inst)
        } else {
            Err(CallError::IllegalCall(state))
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
                fmi2Fatal,
                &format!(
                    "{}: internal error, instance unusable: {}",
                    function.name(),
                    panic_text(payload.as_ref())
                ),
            );
        }));
        fmi2Fatal
    })
}

/// A string argument as a user would write it: quoted, or NULL.
fn shown(s: &Option<CString>) -> String {
    match s {
        Some(s) => format!("\"{}\"", s.to_string_lossy()),
        None => "NULL".into(),
    }
}

unsafe fn show_str(s: fmi2String) -> String {
    if s.is_null() {
        "NULL".into()
    } else {
        // SAFETY: the master passes NUL-terminated strings.
        format!("{:?}", unsafe { CStr::from_ptr(s) }.to_string_lossy())
    }
}

fn row<M: Model>(
    inst: &Instance<M>,
    base: BaseType,
    vr: fmi2ValueReference,
) -> Result<Variable<M>, CallError> {
    match inst.index.row(base, vr) {
        // A copy (a few words), so that the caller may go on to borrow the model mutably.
        Some(r) => Ok(inst.table[r]),
        None => Err(unknown_value_reference(base, vr)),
    }
}

/// Out of line: the error is built only when a lookup fails, never on the success path.
#[cold]
#[inline(never)]
fn unknown_value_reference(base: BaseType, vr: fmi2ValueReference) -> CallError {
    CallError::UnknownValueReference {
        vr,
        type_name: base.name(),
    }
}

// ---------------------------------------------------------------------------------------
// Functions without an instance
// ---------------------------------------------------------------------------------------

pub fn get_types_platform() -> *const c_char {
    TYPES_PLATFORM.as_ptr()
}

pub fn get_version() -> *const c_char {
    VERSION.as_ptr()
}

/// # Safety
/// See the module documentation.
pub unsafe fn instantiate<M: Model>(
    instance_name: fmi2String,
    fmu_type: fmi2Type,
    fmu_guid: fmi2String,
    fmu_resource_location: fmi2String,
    functions: *const fmi2CallbackFunctions,
    visible: fmi2Boolean,
    logging_on: fmi2Boolean,
) -> fmi2Component {
    unsafe {
        instantiate_as::<M>(
            instance_name,
            fmu_type,
            fmu_guid,
            fmu_resource_location,
            functions,
            visible,
            logging_on,
            false,
        )
    }
}

/// [`instantiate`] for a model that also supports Model Exchange (`with_model_exchange`).
///
/// # Safety
/// See the module documentation.
#[allow(clippy::too_many_arguments)]
pub unsafe fn instantiate_as<M: Model>(
    instance_name: fmi2String,
    fmu_type: fmi2Type,
    fmu_guid: fmi2String,
    fmu_resource_location: fmi2String,
    functions: *const fmi2CallbackFunctions,
    visible: fmi2Boolean,
    logging_on: fmi2Boolean,
    with_model_exchange: bool,
) -> fmi2Component {
    // Without callbacks there is no way to say what went wrong: NULL is the whole answer.
    // SAFETY: the master passes a readable struct when non-null; we copy it.
    let Some(callbacks) = (unsafe { functions.as_ref() }).copied() else {
        return ptr::null_mut();
    };
    if callbacks.logger.is_none() {
        return ptr::null_mut();
    }
    let owned = |s: fmi2String| {
        // SAFETY: NUL-terminated when non-null, per the standard; copied at once.
        (!s.is_null()).then(|| unsafe { CStr::from_ptr(s) }.to_owned())
    };
    let name = owned(instance_name);
    let guid = owned(fmu_guid);
    let resource_location = owned(fmu_resource_location);
    let logger = Logger::new(
        callbacks.logger,
        callbacks.componentEnvironment,
        name.clone().unwrap_or_default(),
        logging_on != fmi2False,
    );
    let outcome = catch_unwind(AssertUnwindSafe(move || {
        if logger.is_on(Category::Calls) {
            let trace = format!(
                "fmi2Instantiate(instanceName={}, fmuType={fmu_type}, fmuGUID={}, \
                 fmuResourceLocation={}, visible={visible}, loggingOn={logging_on})",
                shown(&name),
                shown(&guid),
                shown(&resource_location)
            );
            logger.log(fmi2OK, Category::Calls, &trace);
        }
        let expected_guid = crate::guid::<M>();
        let refusal = if name.as_ref().is_none_or(|n| n.is_empty()) {
            Some("instanceName is NULL or empty".to_string())
        } else if fmu_type == fmi2ModelExchange && !with_model_exchange {
            Some(format!(
                "fmuType fmi2ModelExchange is not supported: {} implements Co-Simulation \
                 (fmi2CoSimulation = {fmi2CoSimulation}) only",
                M::MODEL_IDENTIFIER
            ))
        } else if fmu_type != fmi2CoSimulation && fmu_type != fmi2ModelExchange {
            Some(format!(
                "fmuType {fmu_type} is neither fmi2ModelExchange ({fmi2ModelExchange}) nor \
                 fmi2CoSimulation ({fmi2CoSimulation})"
            ))
        } else if guid.as_ref().map(|g| g.to_bytes()) != Some(expected_guid.as_bytes()) {
            Some(format!(
                "fmuGUID {} does not match this FMU's GUID {expected_guid}",
                shown(&guid)
            ))
        } else {
            None
        };
        if let Some(reason) = refusal {
            logger.status(fmi2Error, &format!("fmi2Instantiate: {reason}"));
            return ptr::null_mut();
        }
        let report = logger.clone();
        let instance = Box::new(Instance::<M>::new(
            logger,
            crate::interface_uuid::<M>(),
            resource_location,
            fmu_type == fmi2ModelExchange,
        ));
        let c = Box::into_raw(instance) as fmi2Component;
        if let Err(full) = LIVE.insert(c as usize, report) {
            // SAFETY: `c` came from Box::into_raw just above and was never handed out.
            let instance = unsafe { Box::from_raw(c as *mut Instance<M>) };
            instance
                .logger
                .status(fmi2Error, &format!("fmi2Instantiate: {full}"));
            return ptr::null_mut();
        }
        c
    }));
    outcome.unwrap_or_else(|payload| {
        let logger = Logger::new(
            callbacks.logger,
            callbacks.componentEnvironment,
            c"".to_owned(),
            false,
        );
        logger.status(
            fmi2Fatal,
            &format!(
                "fmi2Instantiate: internal error: {}",
                panic_text(payload.as_ref())
            ),
        );
        ptr::null_mut()
    })
}

/// # Safety
/// See the module documentation.
pub unsafe fn free_instance<M: Model>(c: fmi2Component) {
    let Some((entered, inst)) = (unsafe { enter::<M>(c, Function::FreeInstance) }) else {
        return;
    };
    let _ = catch_unwind(AssertUnwindSafe(|| {
        if inst.logger.is_on(Category::Calls) {
            inst.logger
                .log(fmi2OK, Category::Calls, "fmi2FreeInstance()");
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
    c: fmi2Component,
    logging_on: fmi2Boolean,
    n_categories: usize,
    categories: *const fmi2String,
) -> fmi2Status {
    let f = Function::SetDebugLogging;
    let trace = || {
        let names: Vec<String> = unsafe { slice(categories, n_categories, "categories") }
            .map(|s| s.iter().map(|&p| unsafe { show_str(p) }).collect())
            .unwrap_or_default();
        format!(
            "{}(loggingOn={logging_on}, nCategories={n_categories}, categories=[{}])",
            f.name(),
            names.join(", ")
        )
    };
    unsafe {
        call::<M>(c, f, trace, |inst| {
            let names = slice(categories, n_categories, "categories")?;
            let mut chosen = Vec::with_capacity(names.len());
            for &p in names {
                if p.is_null() {
                    return Err(CallError::NullArgument("categories[i]"));
                }
                let name = CStr::from_ptr(p).to_bytes();
                let category = crate::logging::Category::from_name(name).ok_or_else(|| {
                    CallError::InvalidArgument(format!(
                        "unknown log category {:?}",
                        String::from_utf8_lossy(name)
                    ))
                })?;
                chosen.push(category);
            }
            let on = logging_on != fmi2False;
            if chosen.is_empty() {
                inst.logger.set_all(on);
            } else {
                for category in chosen {
                    inst.logger.set(category, on);
                }
            }
            Ok(Success::Ok)
        })
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn setup_experiment<M: Model>(
    c: fmi2Component,
    tolerance_defined: fmi2Boolean,
    tolerance: fmi2Real,
    start_time: fmi2Real,
    stop_time_defined: fmi2Boolean,
    stop_time: fmi2Real,
) -> fmi2Status {
    let f = Function::SetupExperiment;
    let trace = || {
        format!(
            "{}(toleranceDefined={tolerance_defined}, tolerance={tolerance:e} (not used: \
             fixed-step model), startTime={start_time}, stopTimeDefined={stop_time_defined}, \
             stopTime={stop_time})",
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
            let stop = (stop_time_defined != fmi2False).then_some(stop_time);
            if let Some(stop) = stop {
                if !stop.is_finite() || stop < start_time {
                    return Err(CallError::InvalidArgument(format!(
                        "stopTime {stop} is not a finite time at or after startTime {start_time}"
                    )));
                }
            }
            let core = &mut inst.core;
            core.start_time = start_time;
            core.stop_time = stop;
            core.time = start_time;
            core.last_successful_time = start_time;
            Ok(Success::Ok)
        })
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn enter_initialization_mode<M: Model>(c: fmi2Component) -> fmi2Status {
    let f = Function::EnterInitializationMode;
    unsafe {
        call::<M>(
            c,
            f,
            || format!("{}()", f.name()),
            |inst| {
                inst.core.state = State::InitializationMode;
                inst.dirty = true;
                Ok(Success::Ok)
            },
        )
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn exit_initialization_mode<M: Model>(c: fmi2Component) -> fmi2Status {
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
                inst.core.state = if inst.model_exchange {
                    State::EventMode
                } else {
                    State::StepComplete
                };
                inst.core.time = start_time;
                inst.core.last_successful_time = start_time;
                inst.dirty = true;
                Ok(success)
            },
        )
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn terminate<M: Model>(c: fmi2Component) -> fmi2Status {
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

/// Back to the freshly instantiated state: start values reapplied, time and status reset.
/// Logging flags and FMU states stay: they belong to the master's session, not to the run.
///
/// # Safety
/// See the module documentation.
pub unsafe fn reset<M: Model>(c: fmi2Component) -> fmi2Status {
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

// ---------------------------------------------------------------------------------------
// Get and set
// ---------------------------------------------------------------------------------------

fn get_values<M: Model, V>(
    inst: &mut Instance<M>,
    f: Function,
    base: BaseType,
    vrs: &[fmi2ValueReference],
    values: &mut [V],
    read: impl Fn(&Variable<M>, &M) -> V,
) -> Result<Success, CallError> {
    let success = inst.refresh(f);
    for (&vr, value) in vrs.iter().zip(values) {
        *value = read(&row(inst, base, vr)?, &inst.core.model);
    }
    Ok(success)
}

/// Checks every value before writing any, so a refused call changes nothing.
fn set_values<M: Model, V: Copy>(
    inst: &mut Instance<M>,
    base: BaseType,
    vrs: &[fmi2ValueReference],
    values: &[V],
    check: impl Fn(&Variable<M>, V) -> Result<(), CallError>,
    write: impl Fn(&Variable<M>, &mut M, V),
) -> Result<Success, CallError> {
    for (&vr, &value) in vrs.iter().zip(values) {
        let var = row(inst, base, vr)?;
        check_settable(&var, inst.core.state)?;
        check(&var, value)?;
    }
    for (&vr, &value) in vrs.iter().zip(values) {
        let var = row(inst, base, vr)?;
        write(&var, &mut inst.core.model, value);
    }
    if !vrs.is_empty() {
        inst.dirty = true;
    }
    Ok(Success::Ok)
}

macro_rules! trace_array_call {
    ($f:expr, $vr:expr, $nvr:expr, $value:expr) => {
        || {
            format!(
                "{}(nvr={}, vr={}, value={})",
                $f.name(),
                $nvr,
                show($vr, $nvr),
                show($value, $nvr)
            )
        }
    };
    ($f:expr, $vr:expr, $nvr:expr) => {
        || format!("{}(nvr={}, vr={})", $f.name(), $nvr, show($vr, $nvr))
    };
}

/// # Safety
/// See the module documentation.
pub unsafe fn get_real<M: Model>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2Real,
) -> fmi2Status {
    let f = Function::GetReal;
    unsafe {
        call::<M>(c, f, trace_array_call!(f, vr, nvr), |inst| {
            let vrs = slice(vr, nvr, "vr")?;
            let values = slice_mut(value, nvr, "value")?;
            let success = inst.refresh(f);
            let index = &inst.index;
            let prepared = inst
                .prepared_get
                .read(vrs, values, &inst.core.model, |vr, out| {
                    match index.real(vr) {
                        Some(slot) => {
                            out.push(Getter {
                                get: slot.get,
                                element: slot.element,
                            });
                            true
                        }
                        None => false,
                    }
                });
            if prepared {
                return Ok(success);
            }
            for (&vr, value) in vrs.iter().zip(values) {
                let slot = inst
                    .index
                    .real(vr)
                    .ok_or_else(|| unknown_value_reference(BaseType::Real, vr))?;
                *value = slot.read(&inst.core.model);
            }
            Ok(success)
        })
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn get_integer<M: Model>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2Integer,
) -> fmi2Status {
    let f = Function::GetInteger;
    unsafe {
        call::<M>(c, f, trace_array_call!(f, vr, nvr), |inst| {
            let vrs = slice(vr, nvr, "vr")?;
            let values = slice_mut(value, nvr, "value")?;
            get_values(
                inst,
                f,
                BaseType::Integer,
                vrs,
                values,
                |var, m| match &var.access {
                    Access::Integer { get, .. } | Access::Enumeration { get, .. } => get(m),
                    _ => 0,
                },
            )
        })
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn get_boolean<M: Model>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2Boolean,
) -> fmi2Status {
    let f = Function::GetBoolean;
    unsafe {
        call::<M>(c, f, trace_array_call!(f, vr, nvr), |inst| {
            let vrs = slice(vr, nvr, "vr")?;
            let values = slice_mut(value, nvr, "value")?;
            get_values(
                inst,
                f,
                BaseType::Boolean,
                vrs,
                values,
                |var, m| match &var.access {
                    Access::Boolean { get, .. } if get(m) => fmi2True,
                    _ => fmi2False,
                },
            )
        })
    }
}

/// The returned pointers stay valid until the next `fmi2GetString` on this instance or
/// its `fmi2FreeInstance`.
///
/// # Safety
/// See the module documentation.
pub unsafe fn get_string<M: Model>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2String,
) -> fmi2Status {
    let f = Function::GetString;
    unsafe {
        call::<M>(c, f, trace_array_call!(f, vr, nvr), |inst| {
            let vrs = slice(vr, nvr, "vr")?;
            let values = slice_mut(value, nvr, "value")?;
            let mut strings = vec![CString::default(); nvr];
            let success =
                get_values(
                    inst,
                    f,
                    BaseType::String,
                    vrs,
                    &mut strings,
                    |var, m| match &var.access {
                        Access::String { get, .. } => crate::logging::sanitize(get(m)),
                        _ => CString::default(),
                    },
                )?;
            inst.returned_strings = strings;
            for (out, s) in values.iter_mut().zip(&inst.returned_strings) {
                *out = s.as_ptr();
            }
            Ok(success)
        })
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn set_real<M: Model>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2Real,
) -> fmi2Status {
    let f = Function::SetReal;
    unsafe {
        call::<M>(c, f, trace_array_call!(f, vr, nvr, value), |inst| {
            let vrs = slice(vr, nvr, "vr")?;
            let values = slice(value, nvr, "value")?;
            let state = inst.core.state;
            let index = &inst.index;
            let prepared = inst.prepared_set.write(
                vrs,
                values,
                &mut inst.core.model,
                state as u16,
                |vr, out| match index.real(vr) {
                    Some(slot) => slot.set.is_some_and(|set| {
                        out.push(Setter {
                            set,
                            element: slot.element,
                            lowest: slot.lowest,
                            highest: slot.highest,
                            settable_in: slot.settable_in.bits(),
                        });
                        true
                    }),
                    None => false,
                },
            );
            if prepared {
                inst.dirty |= !vrs.is_empty();
                return Ok(Success::Ok);
            }
            // Checks every value before writing any, so a refused call changes nothing.
            // The write pass looks each reference up again: two array reads, cheaper than
            // keeping what the first pass found.
            for (&vr, &value) in vrs.iter().zip(values) {
                let slot = inst
                    .index
                    .real(vr)
                    .ok_or_else(|| unknown_value_reference(BaseType::Real, vr))?;
                if !slot.accepts(value, state) {
                    refuse_real(&inst.table[slot.row], value, state)?;
                }
            }
            let model = &mut inst.core.model;
            for (&vr, &value) in vrs.iter().zip(values) {
                if let Some(slot) = inst.index.real(vr) {
                    if let Some(set) = slot.set {
                        set(model, slot.element, value);
                    }
                }
            }
            if !vrs.is_empty() {
                inst.dirty = true;
            }
            Ok(Success::Ok)
        })
    }
}

/// Why `value` is refused for `var`, in the words of the checks `RealSlot::accepts` stands
/// in for (which have the last word, should the two ever disagree).
#[cold]
#[inline(never)]
fn refuse_real<M: Model>(var: &Variable<M>, value: f64, state: State) -> Result<(), CallError> {
    check_settable(var, state)?;
    match &var.access {
        Access::Real { min, max, .. } => check_real(var, value, *min, *max),
        _ => Ok(()),
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn set_integer<M: Model>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2Integer,
) -> fmi2Status {
    let f = Function::SetInteger;
    unsafe {
        call::<M>(c, f, trace_array_call!(f, vr, nvr, value), |inst| {
            let vrs = slice(vr, nvr, "vr")?;
            let values = slice(value, nvr, "value")?;
            set_values(
                inst,
                BaseType::Integer,
                vrs,
                values,
                |var, v| match &var.access {
                    Access::Integer { min, max, .. } => check_integer(var, v, *min, *max),
                    Access::Enumeration { ty, .. } => check_enumeration(var, v, ty),
                    _ => Ok(()),
                },
                |var, m, v| match &var.access {
                    Access::Integer { set: Some(set), .. }
                    | Access::Enumeration { set: Some(set), .. } => set(m, v),
                    _ => {}
                },
            )
        })
    }
}

/// Any non-zero `fmi2Boolean` is true, as C reads it.
///
/// # Safety
/// See the module documentation.
pub unsafe fn set_boolean<M: Model>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2Boolean,
) -> fmi2Status {
    let f = Function::SetBoolean;
    unsafe {
        call::<M>(c, f, trace_array_call!(f, vr, nvr, value), |inst| {
            let vrs = slice(vr, nvr, "vr")?;
            let values = slice(value, nvr, "value")?;
            set_values(
                inst,
                BaseType::Boolean,
                vrs,
                values,
                |_, _| Ok(()),
                |var, m, v| {
                    if let Access::Boolean { set: Some(set), .. } = &var.access {
                        set(m, v != fmi2False)
                    }
                },
            )
        })
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn set_string<M: Model>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2String,
) -> fmi2Status {
    let f = Function::SetString;
    let trace = || {
        // Each string is shown quoted once (or NULL), as the master passed it.
        let shown: Vec<String> = unsafe { slice(value, nvr.min(16), "value") }
            .map(|s| s.iter().map(|&p| unsafe { show_str(p) }).collect())
            .unwrap_or_default();
        let more = if nvr > 16 { ", ..." } else { "" };
        format!(
            "{}(nvr={nvr}, vr={}, value=[{}{more}])",
            f.name(),
            unsafe { show(vr, nvr) },
            shown.join(", ")
        )
    };
    let text = |var: &Variable<M>, p: fmi2String| -> Result<&str, CallError> {
        let invalid = |reason: &str| CallError::InvalidValue {
            name: var.name().into_owned(),
            vr: var.value_reference,
            reason: reason.into(),
        };
        if p.is_null() {
            return Err(invalid("value is a NULL string"));
        }
        // SAFETY: non-null strings are NUL-terminated per the standard.
        unsafe { CStr::from_ptr(p) }
            .to_str()
            .map_err(|_| invalid("value is not valid UTF-8"))
    };
    unsafe {
        call::<M>(c, f, trace, |inst| {
            let vrs = slice(vr, nvr, "vr")?;
            let values = slice(value, nvr, "value")?;
            set_values(
                inst,
                BaseType::String,
                vrs,
                values,
                |var, p| text(var, p).map(|_| ()),
                |var, m, p| {
                    if let (Access::String { set: Some(set), .. }, Ok(s)) =
                        (&var.access, text(var, p))
                    {
                        set(m, s)
                    }
                },
            )
        })
    }
}

// ---------------------------------------------------------------------------------------
// FMU state
// ---------------------------------------------------------------------------------------

/// The state at `state` if this instance handed it out and has not freed it.
fn owned_state<'a, M: Model>(
    inst: &Instance<M>,
    state: fmi2FMUstate,
) -> Result<&'a mut Core<M>, CallError> {
    if state.is_null() {
        return Err(CallError::NullArgument("FMUstate"));
    }
    if !inst.fmu_states.contains(&(state as usize)) {
        return Err(CallError::InvalidArgument(format!(
            "FMUstate {state:p} was not created by this instance (or was freed)"
        )));
    }
    // SAFETY: registered addresses come from Box::into_raw of a Core<M> and are removed
    // when freed; the master does not use one state from two threads at once.
    Ok(unsafe { &mut *(state as *mut Core<M>) })
}

/// Stores `core` in `*slot`: into the state already there (which must be ours) or a new one.
fn store_state<M: Model>(
    inst: &mut Instance<M>,
    slot: &mut fmi2FMUstate,
    core: Core<M>,
) -> Result<Success, CallError> {
    if slot.is_null() {
        let address = Box::into_raw(Box::new(core));
        inst.fmu_states.insert(address as usize);
        *slot = address as fmi2FMUstate;
    } else {
        *owned_state(inst, *slot)? = core;
    }
    Ok(Success::Ok)
}

/// # Safety
/// See the module documentation.
pub unsafe fn get_fmu_state<M: Model>(c: fmi2Component, state: *mut fmi2FMUstate) -> fmi2Status {
    let f = Function::GetFMUstate;
    let trace = || format!("{}(FMUstate={state:p})", f.name());
    unsafe {
        call::<M>(c, f, trace, |inst| {
            let slot = out(state, "FMUstate")?;
            let core = inst.core.clone();
            store_state(inst, slot, core)
        })
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn set_fmu_state<M: Model>(c: fmi2Component, state: fmi2FMUstate) -> fmi2Status {
    let f = Function::SetFMUstate;
    let trace = || format!("{}(FMUstate={state:p})", f.name());
    unsafe {
        call::<M>(c, f, trace, |inst| {
            let core = owned_state(inst, state)?;
            crate::restore::validate(&inst.table, core)?;
            inst.core = core.clone();
            inst.dirty = true;
            Ok(Success::Ok)
        })
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn free_fmu_state<M: Model>(c: fmi2Component, state: *mut fmi2FMUstate) -> fmi2Status {
    let f = Function::FreeFMUstate;
    let trace = || format!("{}(FMUstate={state:p})", f.name());
    unsafe {
        call::<M>(c, f, trace, |inst| {
            let slot = out(state, "FMUstate")?;
            // The standard: a NULL *FMUstate is ignored.
            if slot.is_null() {
                return Ok(Success::Ok);
            }
            owned_state(inst, *slot)?;
            inst.fmu_states.remove(&(*slot as usize));
            // SAFETY: registered (checked above), hence a live Box<Core<M>>; now unregistered.
            drop(Box::from_raw(*slot as *mut Core<M>));
            *slot = ptr::null_mut();
            Ok(Success::Ok)
        })
    }
}

/// What identifies a serialized state of this FMU.
fn snapshot_header<M: Model>(inst: &Instance<M>) -> snapshot::Header {
    snapshot::Header {
        magic: crate::SNAPSHOT_MAGIC,
        state_version: M::STATE_VERSION,
        guid: inst.guid,
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn serialized_fmu_state_size<M: Model>(
    c: fmi2Component,
    state: fmi2FMUstate,
    size: *mut usize,
) -> fmi2Status {
    let f = Function::SerializedFMUstateSize;
    let trace = || format!("{}(FMUstate={state:p})", f.name());
    unsafe {
        call::<M>(c, f, trace, |inst| {
            let size = out(size, "size")?;
            *size = snapshot::encode(owned_state(inst, state)?, snapshot_header::<M>(inst))?.len();
            Ok(Success::Ok)
        })
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn serialize_fmu_state<M: Model>(
    c: fmi2Component,
    state: fmi2FMUstate,
    serialized: *mut fmi2Byte,
    size: usize,
) -> fmi2Status {
    let f = Function::SerializeFMUstate;
    let trace = || format!("{}(FMUstate={state:p}, size={size})", f.name());
    unsafe {
        call::<M>(c, f, trace, |inst| {
            let bytes = snapshot::encode(owned_state(inst, state)?, snapshot_header::<M>(inst))?;
            if size != bytes.len() {
                return Err(CallError::InvalidArgument(format!(
                    "size {size} differs from fmi2SerializedFMUstateSize = {}",
                    bytes.len()
                )));
            }
            let buffer = slice_mut(serialized as *mut u8, size, "serializedState")?;
            buffer.copy_from_slice(&bytes);
            Ok(Success::Ok)
        })
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn de_serialize_fmu_state<M: Model>(
    c: fmi2Component,
    serialized: *const fmi2Byte,
    size: usize,
    state: *mut fmi2FMUstate,
) -> fmi2Status {
    let f = Function::DeSerializeFMUstate;
    let trace = || format!("{}(size={size}, FMUstate={state:p})", f.name());
    unsafe {
        call::<M>(c, f, trace, |inst| {
            let bytes = slice(serialized as *const u8, size, "serializedState")?;
            let slot = out(state, "FMUstate")?;
            let core = snapshot::decode::<Core<M>>(bytes, snapshot_header::<M>(inst))?;
            crate::restore::validate(&inst.table, &core)?;
            store_state(inst, slot, core)
        })
    }
}

// ---------------------------------------------------------------------------------------
// Unsupported optional functions
// ---------------------------------------------------------------------------------------

/// # Safety
/// See the module documentation.
pub unsafe fn get_directional_derivative<M: Model>(
    c: fmi2Component,
    _unknowns: *const fmi2ValueReference,
    n_unknown: usize,
    _knowns: *const fmi2ValueReference,
    n_known: usize,
    _dv_known: *const fmi2Real,
    _dv_unknown: *mut fmi2Real,
) -> fmi2Status {
    let f = Function::GetDirectionalDerivative;
    let trace = || format!("{}(nUnknown={n_unknown}, nKnown={n_known})", f.name());
    unsafe {
        call::<M>(c, f, trace, |_| {
            Err(CallError::Unsupported(
                "not provided (providesDirectionalDerivative = false)",
            ))
        })
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn set_real_input_derivatives<M: Model>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    _order: *const fmi2Integer,
    _value: *const fmi2Real,
) -> fmi2Status {
    let f = Function::SetRealInputDerivatives;
    unsafe {
        call::<M>(c, f, trace_array_call!(f, vr, nvr), |_| {
            Err(CallError::Unsupported(
                "not supported (canInterpolateInputs = false)",
            ))
        })
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn get_real_output_derivatives<M: Model>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    _order: *const fmi2Integer,
    _value: *mut fmi2Real,
) -> fmi2Status {
    let f = Function::GetRealOutputDerivatives;
    unsafe {
        call::<M>(c, f, trace_array_call!(f, vr, nvr), |_| {
            Err(CallError::Unsupported(
                "not supported (maxOutputDerivativeOrder = 0)",
            ))
        })
    }
}

// ---------------------------------------------------------------------------------------
// Stepping and status
// ---------------------------------------------------------------------------------------

/// # Safety
/// See the module documentation.
pub unsafe fn do_step<M: Model>(
    c: fmi2Component,
    current_communication_point: fmi2Real,
    communication_step_size: fmi2Real,
    no_set_fmu_state_prior_to_current_point: fmi2Boolean,
) -> fmi2Status {
    let f = Function::DoStep;
    let (t, h) = (current_communication_point, communication_step_size);
    let trace = || {
        format!(
            "{}(currentCommunicationPoint={t}, communicationStepSize={h}, \
             noSetFMUStatePriorToCurrentPoint={no_set_fmu_state_prior_to_current_point})",
            f.name()
        )
    };
    unsafe { call::<M>(c, f, trace, |inst| step(inst, t, h)) }
}

fn step<M: Model>(inst: &mut Instance<M>, t: f64, h: f64) -> Result<Success, CallError> {
    let f = Function::DoStep;
    if !(h.is_finite() && h > 0.0) {
        return Err(CallError::InvalidArgument(format!(
            "communicationStepSize {h} is not a finite positive number"
        )));
    }
    let time = inst.core.time;
    // Written so that a NaN anywhere (the master's t, or a corrupt time of ours) refuses.
    if !(t.is_finite() && time.is_finite() && (t - time).abs() <= time_tolerance(time)) {
        return Err(CallError::InvalidArgument(format!(
            "currentCommunicationPoint {t} does not match the FMU's time {time} \
             (relative tolerance {TIME_TOLERANCE:e})"
        )));
    }
    // The master's own t + h: the next call's t must match it, so no rounding of ours.
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
                "step to {end} (currentCommunicationPoint {t} + communicationStepSize {h}) \
                 passes the stop time {stop} declared in fmi2SetupExperiment"
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
            inst.core.last_successful_time = end;
            Ok(success)
        }
        StepEnd::Stopped {
            time: stopped,
            terminated,
            reason,
        } => {
            if !(t..=end).contains(&stopped) {
                return Err(inst.fail(CallError::InvalidArgument(format!(
                    "model error: stopped at {stopped}, outside the step [{t}, {end}]"
                ))));
            }
            let core = &mut inst.core;
            core.time = stopped;
            core.last_successful_time = stopped;
            core.terminated = terminated;
            core.state = State::StepFailed;
            Err(CallError::Discard(format!(
                "step ended early at t = {stopped}{}: {reason}",
                if terminated { " (terminated)" } else { "" }
            )))
        }
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn cancel_step<M: Model>(c: fmi2Component) -> fmi2Status {
    // Never legal: fmi2DoStep is synchronous and never returns fmi2Pending, so the table
    // refuses it in every state with "illegal call".
    let f = Function::CancelStep;
    unsafe { call::<M>(c, f, || format!("{}()", f.name()), |_| Ok(Success::Ok)) }
}

#[allow(non_upper_case_globals)]
fn status_kind_name(kind: fmi2StatusKind) -> Result<&'static str, CallError> {
    match kind {
        fmi2DoStepStatus => Ok("fmi2DoStepStatus"),
        fmi2PendingStatus => Ok("fmi2PendingStatus"),
        fmi2LastSuccessfulTime => Ok("fmi2LastSuccessfulTime"),
        fmi2Terminated => Ok("fmi2Terminated"),
        other => Err(CallError::InvalidArgument(format!(
            "status kind {other} is not an fmi2StatusKind"
        ))),
    }
}

/// The standard: "If a status is required which cannot be retrieved by the slave it
/// returns fmi2Discard."
fn not_available(kind: fmi2StatusKind, what: &str) -> Result<Success, CallError> {
    Err(CallError::Discard(format!(
        "{} is not available as {what} (no asynchronous steps here)",
        status_kind_name(kind)?
    )))
}

/// # Safety
/// See the module documentation.
pub unsafe fn get_status<M: Model>(
    c: fmi2Component,
    kind: fmi2StatusKind,
    value: *mut fmi2Status,
) -> fmi2Status {
    let f = Function::GetStatus;
    unsafe {
        call::<M>(
            c,
            f,
            || format!("{}(s={kind})", f.name()),
            |_| {
                out(value, "value")?;
                not_available(kind, "an fmi2Status")
            },
        )
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn get_real_status<M: Model>(
    c: fmi2Component,
    kind: fmi2StatusKind,
    value: *mut fmi2Real,
) -> fmi2Status {
    let f = Function::GetRealStatus;
    unsafe {
        call::<M>(
            c,
            f,
            || format!("{}(s={kind})", f.name()),
            |inst| {
                let value = out(value, "value")?;
                if kind != fmi2LastSuccessfulTime {
                    return not_available(kind, "a Real");
                }
                *value = inst.core.last_successful_time;
                Ok(Success::Ok)
            },
        )
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn get_integer_status<M: Model>(
    c: fmi2Component,
    kind: fmi2StatusKind,
    value: *mut fmi2Integer,
) -> fmi2Status {
    let f = Function::GetIntegerStatus;
    unsafe {
        call::<M>(
            c,
            f,
            || format!("{}(s={kind})", f.name()),
            |_| {
                out(value, "value")?;
                not_available(kind, "an Integer")
            },
        )
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn get_boolean_status<M: Model>(
    c: fmi2Component,
    kind: fmi2StatusKind,
    value: *mut fmi2Boolean,
) -> fmi2Status {
    let f = Function::GetBooleanStatus;
    unsafe {
        call::<M>(
            c,
            f,
            || format!("{}(s={kind})", f.name()),
            |inst| {
                let value = out(value, "value")?;
                if kind != fmi2Terminated {
                    return not_available(kind, "a Boolean");
                }
                *value = if inst.core.terminated {
                    fmi2True
                } else {
                    fmi2False
                };
                Ok(Success::Ok)
            },
        )
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn get_string_status<M: Model>(
    c: fmi2Component,
    kind: fmi2StatusKind,
    value: *mut fmi2String,
) -> fmi2Status {
    let f = Function::GetStringStatus;
    unsafe {
        call::<M>(
            c,
            f,
            || format!("{}(s={kind})", f.name()),
            |_| {
                out(value, "value")?;
                not_available(kind, "a String")
            },
        )
    }
}
