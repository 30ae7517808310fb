//! The generic bodies of the `fmi3*` functions; [`export_fmi3!`](crate::export_fmi3)
//! generates the `#[no_mangle]` symbols, each a one-line call into here or into [`crate::me`].
//!
//! This layer unpacks the C arguments and reports results in FMI 3.0's words; what the two
//! FMI versions share (the call guard, the state rules, the step, FMU states, the setter
//! checks) is the export core's ([`fmi_export`]). Every function that takes an instance goes
//! through [`call`], the core's guard: a handle that is no live instance -> `fmi3Error` with
//! nothing read through it, a re-entrant call refused with a log line, the call trace, the
//! state table ([`Function::admit`], which also refuses the other interface's functions and
//! the features we lack), a panic caught as `fmi3Fatal`, one log line per refusal.
//!
//! # Safety
//! Every function here is `unsafe`: the master must pass pointers that are valid as the
//! FMI 3.0 standard requires for the function.
#![allow(unsafe_code)]

use crate::ffi::*;
use crate::state::{Function, Interface, Refusal, State};
use crate::variables::{settable, Float64Slot, Type};
use crate::version::Fmi3;
pub(crate) use fmi_abi::args::{few, few_mut, lists, lists_mut, out, show, slice, slice_mut};
pub(crate) use fmi_export::call::c_call as call;
use fmi_export::call::quick;
use fmi_export::call::{first_non_finite, non_finite_read, shown, Request};
use fmi_export::prepared::Element;
use fmi_export::setters::{check_enumeration, check_integer, check_real};
use fmi_export::step::Advance;
use fmi_export::Abi;
use fmi_export::Sink;
use fmi_export::{lifecycle, CallError, Category, Logger, Options, Status, Success};
use fmi_model::{Declaration, Kind, Model};
use std::ffi::{CStr, CString};
use std::os::raw::c_char;
use std::ptr;

/// An FMI 3.0 instance of `M`.
pub type Instance<M> = fmi_export::Instance<M, Fmi3>;

/// FMI 3.0 exchanges arrays: the fast paths keep the loops of arrays.
const SCALARS_ONLY: bool = false;

fn owned(s: fmi3String) -> Option<CString> {
    // SAFETY: NUL-terminated when non-null, per the standard; copied at once.
    (!s.is_null()).then(|| unsafe { CStr::from_ptr(s) }.to_owned())
}

// ---------------------------------------------------------------------------------------
// Without an instance
// ---------------------------------------------------------------------------------------

pub fn get_version() -> *const c_char {
    VERSION.as_ptr()
}

/// The shared body of the instantiate functions.
#[allow(clippy::too_many_arguments)]
pub(crate) unsafe fn instantiate<M: Model>(
    interface: Interface,
    options: Options,
    refusal: Option<String>,
    instance_name: fmi3String,
    instantiation_token: fmi3String,
    resource_path: fmi3String,
    logging_on: fmi3Boolean,
    environment: fmi3InstanceEnvironment,
    log_message: fmi3LogMessageCallback,
    extra_trace: String,
    supports_model_exchange: bool,
) -> fmi3Instance {
    let logger = Logger::<Fmi3>::new(
        Sink {
            callback: log_message,
            environment,
            instance_name: Default::default(),
        },
        logging_on,
    );
    let function = match interface {
        Interface::ModelExchange => "fmi3InstantiateModelExchange",
        Interface::CoSimulation => "fmi3InstantiateCoSimulation",
    };
    let name = owned(instance_name);
    let token = owned(instantiation_token);
    let resources = owned(resource_path);
    let trace = format!(
        "{function}(instanceName={}, instantiationToken={}, resourcePath={}, \
         loggingOn={logging_on}{extra_trace})",
        shown(&name),
        shown(&token),
        shown(&resources)
    );
    let request = Request {
        function,
        interface,
        options,
        instance_name: name,
        token,
        resource_location: resources,
        trace,
        refusal,
    };
    fmi_export::call::instantiate::<M, Fmi3>(logger, request, supports_model_exchange)
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
    let refusal = (n_required_intermediate_variables > 0)
        .then(|| "intermediate variables are not supported".to_string());
    let trace = format!(
        ", eventModeUsed={event_mode_used}, earlyReturnAllowed={early_return_allowed}, \
         nRequiredIntermediateVariables={n_required_intermediate_variables}"
    );
    let options = Options {
        early_return_allowed,
        event_mode_used,
    };
    unsafe {
        instantiate::<M>(
            Interface::CoSimulation,
            options,
            refusal,
            instance_name,
            instantiation_token,
            resource_path,
            logging_on,
            environment,
            log_message,
            trace,
            false,
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
    let _ = std::panic::catch_unwind(|| {
        let sink = Sink {
            callback: log_message,
            environment,
            instance_name: Default::default(),
        };
        Logger::<Fmi3>::new(sink, false).status(
            Status::Error,
            &format!(
                "fmi3InstantiateScheduledExecution: {} offers Co-Simulation, not Scheduled \
                 Execution",
                M::MODEL_IDENTIFIER
            ),
        );
    });
    ptr::null_mut()
}

/// # Safety
/// See the module documentation.
pub unsafe fn free_instance<M: Model>(c: fmi3Instance) {
    unsafe { fmi_export::call::free_instance::<M, Fmi3>(c, Function::FreeInstance) }
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
        call::<M, Fmi3>(c, f, trace, |inst| {
            fmi_export::raw::set_debug_logging(inst, logging_on, categories, n_categories)
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
        let (tolerance_on, stop_on) = (tolerance_defined, stop_time_defined);
        let (start, stop) = (start_time, stop_time);
        lifecycle::experiment_trace(f.name(), tolerance_on, tolerance, start, stop_on, stop)
    };
    let stop = stop_time_defined.then_some(stop_time);
    unsafe {
        call::<M, Fmi3>(c, f, trace, |inst| {
            lifecycle::set_experiment(inst, start_time, stop)?;
            lifecycle::enter_initialization(inst)
        })
    }
}

/// Any function of a feature this FMU lacks: the table refuses it with the reason.
///
/// # Safety
/// See the module documentation.
pub unsafe fn unsupported<M: Model>(c: fmi3Instance, f: Function) -> fmi3Status {
    unsafe {
        call::<M, Fmi3>(
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
    match inst.view.index.get::<M>(vr) {
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
    inst.view
        .index
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

/// The fast path of `fmi3GetFloat64` (see [`fmi_export::call::quick`]): outputs up to
/// date, every reference a Float64 stored in the model's bytes, the count right and every
/// value finite; any other call goes on to [`get_float64_full`] (a jump: same arguments, no
/// unwinding in between).
///
/// # Safety
/// See the module documentation.
#[inline(always)]
pub unsafe fn get_float64<M: Model>(
    c: fmi3Instance,
    vrs: *const fmi3ValueReference,
    n_vrs: usize,
    values: *mut fmi3Float64,
    n_values: usize,
) -> fmi3Status {
    let served = unsafe {
        quick::<M, Fmi3, _>(c, Function::GetFloat64, |inst| {
            let (vr_list, value_list) = few_mut(vrs, n_vrs, values, n_values)?;
            // The outputs computed first, if anything changed: model code, out of line
            // under the panic guard. OK, Warning (a message logged) or Fatal (a panic).
            let mut refreshed = fmi3OK;
            if inst.dirty {
                refreshed = refresh_outputs(inst);
                if refreshed == fmi3Fatal {
                    return Some(refreshed);
                }
            }
            if inst
                .reals
                .read_fast(vr_list, value_list, &inst.core.model, SCALARS_ONLY)
            {
                return Some(refreshed);
            }
            if refreshed == fmi3OK {
                // Nothing to remember: the full path decides, as if it had refreshed.
                return None;
            }
            // The warning is this call's: the rest of the call here, at least a Warning.
            let status = get_float64_admitted(inst, vrs, n_vrs, values, n_values);
            Some(if status == fmi3OK { refreshed } else { status })
        })
    };
    match served {
        Some(status) => status,
        None => unsafe { get_float64_full::<M>(c, vrs, n_vrs, values, n_values) },
    }
}

/// The outputs of an instance a fast get has admitted computed, under the core's panic
/// guard: `fmi3OK`, `fmi3Warning` (a warning logged) or `fmi3Fatal` (a panic, logged).
/// `extern "C"`: nothing unwinds out of it into the fast path.
#[inline(never)]
extern "C" fn refresh_outputs<M: Model>(inst: &mut Instance<M>) -> fmi3Status {
    let f = Function::GetFloat64;
    Fmi3::status(fmi_export::call::run(inst, f, |inst| Ok(inst.refresh(f))))
}

/// The body of an `fmi3GetFloat64` the fast path has admitted, under the core's panic
/// guard. `extern "C"`: nothing unwinds out of it into the fast path.
///
/// # Safety
/// See the module documentation.
#[inline(never)]
unsafe extern "C" fn get_float64_admitted<M: Model>(
    inst: &mut Instance<M>,
    vrs: *const fmi3ValueReference,
    n_vrs: usize,
    values: *mut fmi3Float64,
    n_values: usize,
) -> fmi3Status {
    let f = Function::GetFloat64;
    Fmi3::status(fmi_export::call::run(inst, f, |inst| unsafe {
        get_float64_body(inst, vrs, n_vrs, values, n_values)
    }))
}

/// `fmi3GetFloat64` through the full guard.
///
/// # Safety
/// See the module documentation.
#[inline(never)]
pub unsafe extern "C" fn get_float64_full<M: Model>(
    c: fmi3Instance,
    vrs: *const fmi3ValueReference,
    n_vrs: usize,
    values: *mut fmi3Float64,
    n_values: usize,
) -> fmi3Status {
    let f = Function::GetFloat64;
    let trace = || unsafe { format!("{}(vr={})", f.name(), show(vrs, n_vrs)) };
    unsafe {
        call::<M, Fmi3>(c, f, trace, |inst| {
            get_float64_body(inst, vrs, n_vrs, values, n_values)
        })
    }
}

/// What `fmi3GetFloat64` does once the call is admitted.
///
/// # Safety
/// See the module documentation.
unsafe fn get_float64_body<M: Model>(
    inst: &mut Instance<M>,
    vrs: *const fmi3ValueReference,
    n_vrs: usize,
    values: *mut fmi3Float64,
    n_values: usize,
) -> Result<Success, CallError> {
    let f = Function::GetFloat64;
    unsafe {
        {
            let (vrs, values) =
                lists_mut(vrs, n_vrs, "valueReferences", values, n_values, "values")?;
            let success = inst.refresh(f);
            // The table is built at the first call it cannot serve (its first of all).
            let prepared = inst.reals.read(vrs, values, &inst.core.model) || {
                let view = &inst.view;
                inst.reals
                    .ensure(&inst.core.model, || float64_elements::<M>(view));
                inst.reals.read(vrs, values, &inst.core.model)
            };
            if prepared {
                return finite(inst, vrs, values).map(|()| success);
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
            finite(inst, vrs, values).map(|()| success)
        }
    }
}

/// `Ok` unless a value read is not finite; then the refusal naming its variable element.
#[inline]
fn finite<M: Model>(
    inst: &Instance<M>,
    vrs: &[fmi3ValueReference],
    values: &[f64],
) -> Result<(), CallError> {
    match first_non_finite(values) {
        None => Ok(()),
        Some(at) => Err(non_finite_element(inst, vrs, values, at)),
    }
}

/// Which variable element of the list the value at `at` belongs to, as a refusal.
#[cold]
#[inline(never)]
fn non_finite_element<M: Model>(
    inst: &Instance<M>,
    vrs: &[fmi3ValueReference],
    values: &[f64],
    at: usize,
) -> CallError {
    let mut k = 0;
    for &vr in vrs {
        let (name, len) = match float64(inst, vr) {
            Ok(slot) => (slot.declaration.name, slot.len),
            Err(_) => ("time", 1),
        };
        if at < k + len {
            let name = if len > 1 {
                format!("{name}[{}]", at - k + 1)
            } else {
                name.to_string()
            };
            return non_finite_read(name, vr, values[at]);
        }
        k += len;
    }
    non_finite_read(format!("value {at}"), 0, values[at])
}

/// The Float64 variable at `vr`, in the exchange's form.
#[inline]
fn float64<M: Model>(
    inst: &Instance<M>,
    vr: fmi3ValueReference,
) -> Result<&Float64Slot<M>, CallError> {
    match inst
        .view
        .index
        .row(vr)
        .and_then(|row| inst.view.float64.get(row))
    {
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
    min: Option<fmi_model::Limit>,
    max: Option<fmi_model::Limit>,
) -> CallError {
    let name = || {
        if len > 1 {
            format!("{}[{}]", d.name, i + 1)
        } else {
            d.name.to_string()
        }
    };
    match check_real(name, d.value_reference, v, min, max, d.unit) {
        Err(error) => error,
        Ok(()) => CallError::InvalidArgument(format!("{}: value {v} refused", d.name)),
    }
}

fn refuse_set<M>(d: &Declaration<M>, reason: &'static str) -> CallError {
    CallError::NotSettable {
        name: d.name.to_string(),
        vr: d.value_reference,
        reason,
    }
}

/// The two kinds of state a Float64's settability depends on, as bits for
/// [`fmi_export::prepared`].
const INITIALIZING: u16 = 1;
const RUNNING: u16 = 2;

fn initializing(state: State) -> bool {
    state.initializing()
}

/// Every Float64 variable for the instance's exchange table
/// ([`fmi_export::prepared`]).
fn float64_elements<M: Model>(
    view: &crate::version::View<M>,
) -> impl Iterator<Item = (u32, Element<M>)> + '_ {
    view.float64.iter().flatten().map(|slot| {
        let settable_in = (u16::from(slot.settable_initializing) * INITIALIZING)
            | (u16::from(slot.settable_running) * RUNNING);
        let variable = Element {
            get: slot.get,
            set: slot.set,
            element: 0,
            len: slot.len,
            place: slot.place,
            lowest: slot.lowest,
            highest: slot.highest,
            settable_in,
        };
        (slot.declaration.value_reference, variable)
    })
}

/// The fast path of `fmi3SetFloat64` (see [`fmi_export::call::quick`]): every reference
/// a Float64 stored in the model's bytes, settable now, the count right and every value
/// admitted; any other call goes on to [`set_float64_full`] with nothing written.
///
/// # Safety
/// See the module documentation.
#[inline(always)]
pub unsafe fn set_float64<M: Model>(
    c: fmi3Instance,
    vrs: *const fmi3ValueReference,
    n_vrs: usize,
    values: *const fmi3Float64,
    n_values: usize,
) -> fmi3Status {
    let served = unsafe {
        quick::<M, Fmi3, _>(c, Function::SetFloat64, |inst| {
            let (vrs, values) = few(vrs, n_vrs, values, n_values)?;
            let state_bit = if initializing(inst.core.state) {
                INITIALIZING
            } else {
                RUNNING
            };
            let model = &mut inst.core.model;
            if !inst
                .reals
                .write_fast(vrs, values, model, state_bit, SCALARS_ONLY)
            {
                return None;
            }
            inst.dirty |= !vrs.is_empty();
            Some(fmi3OK)
        })
    };
    match served {
        Some(status) => status,
        None => unsafe { set_float64_full::<M>(c, vrs, n_vrs, values, n_values) },
    }
}

/// `fmi3SetFloat64` through the full guard.
///
/// # Safety
/// See the module documentation.
#[inline(never)]
pub unsafe extern "C" fn set_float64_full<M: Model>(
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
        call::<M, Fmi3>(c, f, trace, |inst| {
            let (vrs, values) = lists(vrs, n_vrs, "valueReferences", values, n_values, "values")?;
            let initializing = initializing(inst.core.state);
            let state_bit = if initializing { INITIALIZING } else { RUNNING };
            // The table is built at the first call it cannot serve (its first of all).
            let model = &mut inst.core.model;
            let prepared = inst.reals.write(vrs, values, model, state_bit) || {
                let view = &inst.view;
                inst.reals.ensure(model, || float64_elements::<M>(view));
                inst.reals.write(vrs, values, model, state_bit)
            };
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
        call::<M, Fmi3>(c, f, trace, |inst| {
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
    check: fn(&Declaration<M>, V) -> Result<(), CallError>,
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
        call::<M, Fmi3>(c, f, trace, |inst| {
            let vrs = slice(vrs, n_vrs, "valueReferences")?;
            let values = slice(values, n_values, "values")?;
            let decls = check_count(inst, vrs, ty, n_values)?;
            for (d, &v) in decls.iter().zip(values) {
                settable(d, initializing(inst.core.state)).map_err(|r| refuse_set(d, r))?;
                check(d, v)?;
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
    let check = |d: &Declaration<M>, v: i32| match d.kind {
        Kind::Integer { min, max, .. } => {
            check_integer(|| d.name.to_string(), d.value_reference, v.into(), min, max)
        }
        Kind::Enumeration { ty, .. } => {
            check_enumeration(|| d.name.to_string(), d.value_reference, v.into(), ty)
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
    let check = |d: &Declaration<M>, v: i64| match d.kind {
        Kind::Enumeration { ty, .. } => {
            check_enumeration(|| d.name.to_string(), d.value_reference, v, ty)
        }
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
        call::<M, Fmi3>(c, f, trace, |inst| {
            let vrs = slice(vrs, n_vrs, "valueReferences")?;
            let values = slice_mut(values, n_values, "values")?;
            let success = inst.refresh(f);
            let decls = check_count(inst, vrs, Type::String, n_values)?;
            let strings: Vec<CString> = decls
                .iter()
                .map(|d| match &d.kind {
                    Kind::String { get, .. } => {
                        fmi_export::logging::sanitize(get(&inst.core.model))
                    }
                    _ => CString::default(),
                })
                .collect();
            inst.hand_out_strings(strings, values);
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
        call::<M, Fmi3>(c, f, trace, |inst| {
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
        call::<M, Fmi3>(c, f, trace, |_| {
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

// ---------------------------------------------------------------------------------------
// Co-Simulation
// ---------------------------------------------------------------------------------------

/// What `fmi3DoStep` tells the master besides its status.
#[derive(Debug, Clone, Copy, PartialEq)]
struct StepReport {
    event_handling_needed: bool,
    terminate: bool,
    early_return: bool,
    last_successful_time: f64,
}

/// Where `fmi3DoStep` writes what it tells the master besides its status.
struct StepOut<'a> {
    event_handling_needed: &'a mut fmi3Boolean,
    terminate: &'a mut fmi3Boolean,
    early_return: &'a mut fmi3Boolean,
    last_successful_time: &'a mut fmi3Float64,
}

impl StepOut<'_> {
    /// The out-arguments, or the first that is NULL.
    ///
    /// # Safety
    /// Each non-NULL pointer points to a writable value.
    #[inline(always)]
    unsafe fn of(
        event_handling_needed: *mut fmi3Boolean,
        terminate_simulation: *mut fmi3Boolean,
        early_return: *mut fmi3Boolean,
        last_successful_time: *mut fmi3Float64,
    ) -> Result<Self, fmi_abi::args::ArgError> {
        unsafe {
            Ok(StepOut {
                event_handling_needed: out(event_handling_needed, "eventHandlingNeeded")?,
                terminate: out(terminate_simulation, "terminateSimulation")?,
                early_return: out(early_return, "earlyReturn")?,
                last_successful_time: out(last_successful_time, "lastSuccessfulTime")?,
            })
        }
    }

    /// Runs a step (`step`, given the report to fill) and writes its report.
    fn report<M: Model>(
        self,
        inst: &mut Instance<M>,
        step: impl FnOnce(&mut Instance<M>, &mut StepReport) -> Result<Success, CallError>,
    ) -> Result<Success, CallError> {
        let mut report = StepReport {
            event_handling_needed: false,
            terminate: inst.core.terminated,
            early_return: false,
            last_successful_time: inst.core.time,
        };
        let result = step(inst, &mut report);
        *self.event_handling_needed = report.event_handling_needed;
        *self.terminate = report.terminate;
        *self.early_return = report.early_return;
        *self.last_successful_time = report.last_successful_time;
        result
    }
}

/// The fast path of `fmi3DoStep` (see [`fmi_export::call::quick`]): a step the checks
/// accept, with every out-argument given, goes straight to the model ([`step_accepted`]);
/// any other call goes on to [`do_step_full`].
///
/// # Safety
/// See the module documentation.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
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
    let (t, h) = (current_communication_point, communication_step_size);
    let served = unsafe {
        quick::<M, Fmi3, _>(c, Function::DoStep, |inst| {
            let given = !event_handling_needed.is_null()
                & !terminate_simulation.is_null()
                & !early_return.is_null()
                & !last_successful_time.is_null();
            if !given || inst.core.terminated {
                return None;
            }
            let end = fmi_export::step::accepted(inst, t, h)?;
            Some(step_accepted(
                inst,
                t,
                h,
                end,
                event_handling_needed,
                terminate_simulation,
                early_return,
                last_successful_time,
            ))
        })
    };
    match served {
        Some(status) => status,
        None => unsafe {
            do_step_full::<M>(
                c,
                t,
                h,
                no_set_fmu_state_prior_to_current_point,
                event_handling_needed,
                terminate_simulation,
                early_return,
                last_successful_time,
            )
        },
    }
}

/// The step of an admitted `fmi3DoStep` whose arguments the checks accepted, ending at
/// `end`. `extern "C"`: nothing unwinds out of it into the fast path.
///
/// # Safety
/// The out-arguments are non-NULL and writable.
#[allow(clippy::too_many_arguments)]
#[inline(never)]
unsafe extern "C" fn step_accepted<M: Model>(
    inst: &mut Instance<M>,
    t: f64,
    h: f64,
    end: f64,
    event_handling_needed: *mut fmi3Boolean,
    terminate_simulation: *mut fmi3Boolean,
    early_return: *mut fmi3Boolean,
    last_successful_time: *mut fmi3Float64,
) -> fmi3Status {
    let f = Function::DoStep;
    let status = fmi_export::call::run(inst, f, |inst| {
        // What the report starts from ([`StepOut::report`]); the fast path admitted only an
        // instance that has not ended its run.
        let mut report = StepReport {
            event_handling_needed: false,
            terminate: false,
            early_return: false,
            last_successful_time: inst.core.time,
        };
        let result = match fmi_export::step::advance_checked(inst, f, t, h, end) {
            // The common step, done in one advance: what `step_from` concludes for it.
            Ok((outcome, Advance::Complete)) => {
                inst.core.time = end;
                inst.core.last_successful_time = end;
                report.last_successful_time = end;
                Ok(Success::Ok.and(outcome))
            }
            first => first.and_then(|first| step_from(inst, t, h, end, Some(first), &mut report)),
        };
        // SAFETY: the fast path checked every out-argument non-NULL; the caller owns them.
        unsafe {
            *event_handling_needed = report.event_handling_needed;
            *terminate_simulation = report.terminate;
            *early_return = report.early_return;
            *last_successful_time = report.last_successful_time;
        }
        result
    });
    Fmi3::status(status)
}

/// `fmi3DoStep` through the full guard.
///
/// # Safety
/// See the module documentation.
#[allow(clippy::too_many_arguments)]
#[inline(never)]
pub unsafe extern "C" fn do_step_full<M: Model>(
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
    let no_set_prior = no_set_fmu_state_prior_to_current_point;
    let trace = || fmi_export::step::trace(f.name(), t, h, no_set_prior);
    unsafe {
        call::<M, Fmi3>(c, f, trace, |inst| {
            let outs = StepOut::of(
                event_handling_needed,
                terminate_simulation,
                early_return,
                last_successful_time,
            )?;
            outs.report(inst, |inst, report| step(inst, t, h, report))
        })
    }
}

/// Most events one step may pass through when it must not return early: each ends a model
/// step strictly inside the communication step, so a model that reports more is broken.
const MAX_EVENTS_PER_STEP: usize = 64;

/// A step as FMI 3.0 §4.2 wants it: `fmi3OK` whenever the step was carried out. At an event
/// inside the step (touchdown, propellant exhaustion) the FMU returns early at the event
/// (`earlyReturn`, `lastSuccessfulTime` at it, the outputs the event's) if the master
/// allowed early return; otherwise a model that ends its run (touchdown) stays frozen at the
/// event and asks to terminate (`terminateSimulation`, `lastSuccessfulTime` at the event),
/// and one that goes on is stepped on from the event to the step's end. `fmi3Discard` is never the answer to an
/// event: it means the step did not succeed.
fn step<M: Model>(
    inst: &mut Instance<M>,
    t: f64,
    h: f64,
    report: &mut StepReport,
) -> Result<Success, CallError> {
    if inst.core.terminated {
        // Once terminateSimulation was returned the importer must end the run with
        // fmi3Terminate (FMI 3.0, fmi3DoStep); a step past it would integrate a model that
        // has ended.
        return Err(CallError::InvalidArgument(format!(
            "the FMU ended the simulation at t = {} (terminateSimulation); only {}, {} or \
             {} lead on",
            inst.core.last_successful_time,
            Function::Terminate.name(),
            Function::Reset.name(),
            Function::SetFMUState.name()
        )));
    }
    let end = fmi_export::step::check(inst, t, h)?;
    step_from(inst, t, h, end, None, report)
}

/// [`step`] once its arguments were accepted: from `t` to `end` (= `t + h`); `first`, when
/// given, is the outcome of the advance over the whole step already made.
fn step_from<M: Model>(
    inst: &mut Instance<M>,
    t: f64,
    h: f64,
    end: f64,
    mut first: Option<(Success, Advance)>,
    report: &mut StepReport,
) -> Result<Success, CallError> {
    let f = Function::DoStep;
    let mut success = Success::Ok;
    let mut from = t;
    let mut finished = false;
    let mut ended_at = None;
    for _ in 0..=MAX_EVENTS_PER_STEP {
        // The master's own h for the step as asked (what FMI 2.0 passes too: `(t + h) - t`
        // can differ from h in its last bit, and a model that integrates over h would then
        // fly another trajectory); after an event, the rest of the step.
        let span = if from == t { h } else { end - from };
        let (outcome, advance) = match first.take() {
            Some(first) => first,
            None => fmi_export::step::advance_checked(inst, f, from, span, end)?,
        };
        success = success.and(outcome);
        let (at, terminated, reason) = match advance {
            Advance::Complete => {
                finished = true;
                break;
            }
            Advance::Stopped {
                at,
                terminated,
                reason,
            } => (at, terminated, reason),
        };
        if inst.logger.is_on(Category::Events) {
            inst.logger.log(
                Status::Ok,
                Category::Events,
                &format!("{}: event at t = {at}: {reason}", f.name()),
            );
        }
        report.terminate |= terminated;
        if inst.options.early_return_allowed && at < end {
            // eventHandlingNeeded speaks of an event at lastSuccessfulTime: only when the
            // step returns at it (a step that went on past it has handled it).
            report.event_handling_needed = inst.options.event_mode_used && !terminated;
            report.early_return = true;
            report.last_successful_time = at;
            return Ok(success);
        }
        if terminated {
            // lastSuccessfulTime is the FMU's internal time when the step returns, whatever
            // earlyReturn says (FMI 3.0, fmi3DoStep): a model that ended its run stays at
            // the event, so that is where its time stopped, not at t + h.
            ended_at = Some(at);
            finished = true;
            break;
        }
        if at >= end {
            finished = true;
            break;
        }
        from = at;
    }
    if !finished {
        return Err(inst.fail(CallError::Model(format!(
            "model error: more than {MAX_EVENTS_PER_STEP} events in the step from t = {t} s"
        ))));
    }
    // The step is complete at the master's own t + h (the next call's t must match it),
    // or at the event that ended the model's run.
    let reached = ended_at.unwrap_or(end);
    inst.core.time = reached;
    inst.core.last_successful_time = reached;
    report.last_successful_time = reached;
    Ok(success)
}

// ---------------------------------------------------------------------------------------
// Event Mode (Model Exchange, and Co-Simulation with eventModeUsed)
// ---------------------------------------------------------------------------------------

/// Model Exchange: from Continuous-Time Mode. Co-Simulation: from Step Mode, when the
/// master chose `eventModeUsed` at instantiation. In Co-Simulation's Event Mode inputs may
/// be set and outputs read in any order, the outputs computed from the inputs at this
/// instant (FMI 3.0 §4.2: in Step Mode a get must not follow a set before the next step).
///
/// # Safety
/// See the module documentation.
pub unsafe fn enter_event_mode<M: Model>(c: fmi3Instance) -> fmi3Status {
    let f = Function::EnterEventMode;
    unsafe {
        call::<M, Fmi3>(
            c,
            f,
            || format!("{}()", f.name()),
            |inst| {
                if inst.interface() == Interface::CoSimulation && !inst.options.event_mode_used {
                    return Err(CallError::InvalidArgument(
                        "Event Mode in Co-Simulation needs eventModeUsed = true at \
                         fmi3InstantiateCoSimulation"
                            .into(),
                    ));
                }
                inst.core.state = State::EventMode;
                Ok(Success::Ok)
            },
        )
    }
}

/// The event update of a Co-Simulation instance: our models have no discrete states that
/// an event at a communication point changes, so there is nothing to update; what the
/// outputs depend on is computed on the next get.
pub(crate) fn co_simulation_event_update<M: Model>(
    inst: &mut Instance<M>,
) -> (Success, fmi_model::EventUpdate) {
    inst.dirty = true;
    (Success::Ok, fmi_model::EventUpdate::default())
}

/// Co-Simulation: back from Event Mode to Step Mode.
///
/// # Safety
/// See the module documentation.
pub unsafe fn enter_step_mode<M: Model>(c: fmi3Instance) -> fmi3Status {
    let f = Function::EnterStepMode;
    unsafe {
        call::<M, Fmi3>(
            c,
            f,
            || format!("{}()", f.name()),
            |inst| {
                inst.core.state = State::StepComplete;
                Ok(Success::Ok)
            },
        )
    }
}

/// Co-Simulation's Event Mode: the discrete equations at the current instant. Ours are
/// evaluated on every get, so this only marks the outputs for recomputation.
///
/// # Safety
/// See the module documentation.
pub unsafe fn evaluate_discrete_states<M: Model>(c: fmi3Instance) -> fmi3Status {
    let f = Function::EvaluateDiscreteStates;
    unsafe {
        call::<M, Fmi3>(
            c,
            f,
            || format!("{}()", f.name()),
            |inst| {
                inst.dirty = true;
                Ok(Success::Ok)
            },
        )
    }
}

// ---------------------------------------------------------------------------------------
// Partial derivatives
// ---------------------------------------------------------------------------------------

/// The serialized elements of `vrs` (every element of an array, in order) as the core's
/// [`Element`](fmi_export::derivatives::Element)s; `role` names the argument in messages.
fn derivative_elements<M: Model>(
    inst: &Instance<M>,
    vrs: &[fmi3ValueReference],
    role: &str,
) -> Result<Vec<fmi_export::derivatives::Element>, CallError> {
    let mut elements = Vec::with_capacity(vrs.len());
    for &vr in vrs {
        if vr == crate::variables::TIME_VR {
            return Err(CallError::InvalidArgument(format!(
                "{role} time (vr {vr}): derivatives with respect to or of the independent \
                 variable are not provided"
            )));
        }
        let declaration = inst.view.index.row(vr).ok_or_else(|| {
            CallError::InvalidArgument(format!("{role} vr {vr}: no variable has it"))
        })?;
        let len = M::declarations()[declaration].shape().len();
        elements.extend((0..len).map(|element| fmi_export::derivatives::Element {
            scalar: fmi_model::ScalarRef::new(declaration, element),
            vr,
        }));
    }
    Ok(elements)
}

/// `fmi3GetDirectionalDerivative` and `fmi3GetAdjointDerivative` (FMI 3.0 §2.2.11): seed and
/// sensitivity hold the serialized elements of the arrays named. `states` are the model's
/// `(state, derivative)` names (empty without Model Exchange).
///
/// # Safety
/// See the module documentation.
#[allow(clippy::too_many_arguments)]
pub unsafe fn derivative<M: Model>(
    c: fmi3Instance,
    f: Function,
    states: &'static [(&'static str, &'static str)],
    unknowns: *const fmi3ValueReference,
    n_unknowns: usize,
    knowns: *const fmi3ValueReference,
    n_knowns: usize,
    seed: *const fmi3Float64,
    n_seed: usize,
    sensitivity: *mut fmi3Float64,
    n_sensitivity: usize,
) -> fmi3Status {
    use fmi_export::derivatives::{check_lengths, evaluate, Direction};
    let direction = if f == Function::GetAdjointDerivative {
        Direction::Adjoint
    } else {
        Direction::Forward
    };
    let trace = || unsafe {
        format!(
            "{}(unknowns={}, knowns={}, seed={}, nSensitivity={n_sensitivity})",
            f.name(),
            show(unknowns, n_unknowns),
            show(knowns, n_knowns),
            show(seed, n_seed)
        )
    };
    unsafe {
        call::<M, Fmi3>(c, f, trace, |inst| {
            if !M::PROVIDES_DIRECTIONAL_DERIVATIVES {
                return Err(CallError::Refused(Refusal::Unsupported(match direction {
                    Direction::Forward => "directional derivatives",
                    Direction::Adjoint => "adjoint derivatives",
                })));
            }
            let unknown_vrs = slice(unknowns, n_unknowns, "unknowns")?;
            let known_vrs = slice(knowns, n_knowns, "knowns")?;
            let seed = slice(seed, n_seed, "seed")?;
            let sensitivity = slice_mut(sensitivity, n_sensitivity, "sensitivity")?;
            let unknown_elements = derivative_elements(inst, unknown_vrs, "unknown")?;
            let known_elements = derivative_elements(inst, known_vrs, "known")?;
            check_lengths(
                direction,
                known_elements.len(),
                unknown_elements.len(),
                seed.len(),
                sensitivity.len(),
            )?;
            evaluate(
                inst,
                f,
                direction,
                states,
                &unknown_elements,
                &known_elements,
                seed,
                sensitivity,
            )
        })
    }
}
