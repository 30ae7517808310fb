//! The generic bodies of the 34 `fmi2*` functions. [`export_fmi2!`](crate::export_fmi2)
//! generates the `#[no_mangle]` symbols in the model crate, each a one-line call into here.
//!
//! This layer unpacks the C arguments and reports results in FMI 2.0's words; everything
//! the two FMI versions share (the call guard, the state rules, the step, FMU states, the
//! setter checks) is the export core's ([`fmi_export`]). Every function that takes an
//! instance goes through [`call`], the core's guard: a handle that is no live instance ->
//! `fmi2Error` with nothing read through it, a re-entrant call refused with a log line, the
//! call trace, the state table of [`Function::legal_states`], a panic caught as `fmi2Fatal`,
//! one log line per refusal. Refused arguments leave the instance as it was; a failure of
//! the model itself moves it to state Error.
//!
//! # Safety
//! Every function here is `unsafe`: the caller (the generated symbol, i.e. the master)
//! must pass pointers that are valid as the FMI 2.0 standard requires for the function.
#![allow(unsafe_code)]

use crate::ffi::*;
use crate::index::BaseType;
use crate::state::{Function, State};
use crate::variable::{Access, Variable};
use crate::version::Fmi2;
pub(crate) use fmi_abi::args::{few, few_mut, lists, lists_mut, out, show, slice, slice_mut};
pub(crate) use fmi_export::call::c_call as call;
use fmi_export::call::quick;
use fmi_export::call::{first_non_finite, non_finite_read, shown, Request};
use fmi_export::prepared::Element;
use fmi_export::setters::{check_enumeration, check_integer, check_real, check_settable};
use fmi_export::step::Advance;
use fmi_export::Abi;
use fmi_export::Sink;
use fmi_export::{lifecycle, CallError, Interface, Logger, Options, Success};
use fmi_model::Model;
use std::ffi::{CStr, CString};
use std::os::raw::c_char;
use std::ptr;

/// An FMI 2.0 instance of `M`.
pub type Instance<M> = fmi_export::Instance<M, Fmi2>;

/// Every Real of FMI 2.0 is a scalar: the fast paths leave out the loops of arrays.
const SCALARS_ONLY: bool = true;

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
    match inst.view.index.row(base, vr) {
        // A copy (a few words), so that the caller may go on to borrow the model mutably.
        Some(r) => Ok(inst.view.table[r]),
        None => Err(unknown_value_reference(base, vr)),
    }
}

/// Every Real scalar for the instance's exchange table ([`fmi_export::prepared`]).
fn real_elements<M: Model>(
    view: &crate::version::View<M>,
) -> impl Iterator<Item = (u32, Element<M>)> + '_ {
    view.table.iter().filter_map(|var| {
        if !matches!(var.access, Access::Real { .. }) {
            return None;
        }
        let vr = var.value_reference;
        let slot = view.index.real(vr)?;
        Some((
            vr,
            Element {
                get: slot.get,
                set: slot.set,
                element: slot.element,
                len: 1,
                place: slot.place,
                lowest: slot.lowest,
                highest: slot.highest,
                settable_in: slot.settable_in.bits(),
            },
        ))
    })
}

/// The core's settable rule for an FMI 2.0 scalar.
fn settable_now<M: Model>(var: &Variable<M>, state: State) -> Result<(), CallError> {
    check_settable(
        || var.name().into_owned(),
        var.value_reference,
        var.causality,
        var.variability,
        state,
    )
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
#[allow(clippy::too_many_arguments, non_upper_case_globals)]
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
    let logger = Logger::<Fmi2>::new(
        Sink {
            callback: callbacks.logger,
            environment: callbacks.componentEnvironment,
            instance_name: name.clone().unwrap_or_default(),
        },
        logging_on != fmi2False,
    );
    let trace = format!(
        "fmi2Instantiate(instanceName={}, fmuType={fmu_type}, fmuGUID={}, \
         fmuResourceLocation={}, visible={visible}, loggingOn={logging_on})",
        shown(&name),
        shown(&guid),
        shown(&resource_location)
    );
    let (interface, refusal) = match fmu_type {
        fmi2CoSimulation => (Interface::CoSimulation, None),
        fmi2ModelExchange if with_model_exchange => (Interface::ModelExchange, None),
        fmi2ModelExchange => (
            Interface::ModelExchange,
            Some(format!(
                "fmuType fmi2ModelExchange is not supported: {} implements Co-Simulation \
                 (fmi2CoSimulation = {fmi2CoSimulation}) only",
                M::MODEL_IDENTIFIER
            )),
        ),
        other => (
            Interface::CoSimulation,
            Some(format!(
                "fmuType {other} is neither fmi2ModelExchange ({fmi2ModelExchange}) nor \
                 fmi2CoSimulation ({fmi2CoSimulation})"
            )),
        ),
    };
    let request = Request {
        function: "fmi2Instantiate",
        interface,
        options: Options::default(),
        instance_name: name,
        token: guid,
        resource_location,
        trace,
        refusal,
    };
    fmi_export::call::instantiate::<M, Fmi2>(logger, request, with_model_exchange)
}

/// # Safety
/// See the module documentation.
pub unsafe fn free_instance<M: Model>(c: fmi2Component) {
    unsafe { fmi_export::call::free_instance::<M, Fmi2>(c, Function::FreeInstance) }
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
        call::<M, Fmi2>(c, f, trace, |inst| {
            fmi_export::raw::set_debug_logging(
                inst,
                logging_on != fmi2False,
                categories,
                n_categories,
            )
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
        let (tolerance_on, stop_on) = (tolerance_defined, stop_time_defined);
        let (start, stop) = (start_time, stop_time);
        lifecycle::experiment_trace(f.name(), tolerance_on, tolerance, start, stop_on, stop)
    };
    let stop = (stop_time_defined != fmi2False).then_some(stop_time);
    unsafe {
        call::<M, Fmi2>(c, f, trace, |inst| {
            lifecycle::set_experiment(inst, start_time, stop)
        })
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn enter_initialization_mode<M: Model>(c: fmi2Component) -> fmi2Status {
    let f = Function::EnterInitializationMode;
    unsafe {
        call::<M, Fmi2>(
            c,
            f,
            || format!("{}()", f.name()),
            lifecycle::enter_initialization,
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
        settable_now(&var, inst.core.state)?;
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

/// The fast path of `fmi2GetReal` (see [`fmi_export::call::quick`]): outputs up to date,
/// every reference a Real stored in the model's bytes and every value finite; any other
/// call goes on to [`get_real_full`] (a jump: same arguments, no unwinding in between).
///
/// # Safety
/// See the module documentation.
#[inline(always)]
pub unsafe fn get_real<M: Model>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2Real,
) -> fmi2Status {
    let served = unsafe {
        quick::<M, Fmi2, _>(c, Function::GetReal, |inst| {
            let (vrs, values) = few_mut(vr, nvr, value, nvr)?;
            // The outputs computed first, if anything changed: model code, out of line
            // under the panic guard. OK, Warning (a message logged) or Fatal (a panic).
            let mut refreshed = fmi2OK;
            if inst.dirty {
                refreshed = refresh_outputs(inst);
                if refreshed == fmi2Fatal {
                    return Some(refreshed);
                }
            }
            if inst
                .reals
                .read_fast(vrs, values, &inst.core.model, SCALARS_ONLY)
            {
                return Some(refreshed);
            }
            if refreshed == fmi2OK {
                // Nothing to remember: the full path decides, as if it had refreshed.
                return None;
            }
            // The warning is this call's: the rest of the call here, at least a Warning.
            let status = get_real_admitted(inst, vr, nvr, value);
            Some(if status == fmi2OK { refreshed } else { status })
        })
    };
    match served {
        Some(status) => status,
        None => unsafe { get_real_full::<M>(c, vr, nvr, value) },
    }
}

/// The outputs of an instance a fast get has admitted computed, under the core's panic
/// guard: `fmi2OK`, `fmi2Warning` (a warning logged) or `fmi2Fatal` (a panic, logged).
/// `extern "C"`: nothing unwinds out of it into the fast path.
#[inline(never)]
extern "C" fn refresh_outputs<M: Model>(inst: &mut Instance<M>) -> fmi2Status {
    let f = Function::GetReal;
    Fmi2::status(fmi_export::call::run(inst, f, |inst| Ok(inst.refresh(f))))
}

/// The body of an `fmi2GetReal` the fast path has admitted, under the core's panic guard.
/// `extern "C"`: nothing unwinds out of it into the fast path.
///
/// # Safety
/// See the module documentation.
#[inline(never)]
unsafe extern "C" fn get_real_admitted<M: Model>(
    inst: &mut Instance<M>,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2Real,
) -> fmi2Status {
    let f = Function::GetReal;
    Fmi2::status(fmi_export::call::run(inst, f, |inst| unsafe {
        get_real_body(inst, vr, nvr, value)
    }))
}

/// `fmi2GetReal` through the full guard.
///
/// # Safety
/// See the module documentation.
#[inline(never)]
pub unsafe extern "C" fn get_real_full<M: Model>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2Real,
) -> fmi2Status {
    let f = Function::GetReal;
    unsafe {
        call::<M, Fmi2>(c, f, trace_array_call!(f, vr, nvr), |inst| {
            get_real_body(inst, vr, nvr, value)
        })
    }
}

/// What `fmi2GetReal` does once the call is admitted.
///
/// # Safety
/// See the module documentation.
unsafe fn get_real_body<M: Model>(
    inst: &mut Instance<M>,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2Real,
) -> Result<Success, CallError> {
    let f = Function::GetReal;
    unsafe {
        {
            let (vrs, values) = lists_mut(vr, nvr, "vr", value, nvr, "value")?;
            let success = inst.refresh(f);
            // The table is built at the first call it cannot serve (its first of all).
            let prepared = inst.reals.read(vrs, values, &inst.core.model) || {
                let view = &inst.view;
                inst.reals.ensure(&inst.core.model, || real_elements(view));
                inst.reals.read(vrs, values, &inst.core.model)
            };
            if !prepared {
                for (&vr, value) in vrs.iter().zip(values.iter_mut()) {
                    let slot = inst
                        .view
                        .index
                        .real(vr)
                        .ok_or_else(|| unknown_value_reference(BaseType::Real, vr))?;
                    *value = slot.read(&inst.core.model);
                }
            }
            if let Some(i) = first_non_finite(values) {
                let name = row(inst, BaseType::Real, vrs[i])?.name().into_owned();
                return Err(non_finite_read(name, vrs[i], values[i]));
            }
            Ok(success)
        }
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
        call::<M, Fmi2>(c, f, trace_array_call!(f, vr, nvr), |inst| {
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
        call::<M, Fmi2>(c, f, trace_array_call!(f, vr, nvr), |inst| {
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
        call::<M, Fmi2>(c, f, trace_array_call!(f, vr, nvr), |inst| {
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
                        Access::String { get, .. } => fmi_export::logging::sanitize(get(m)),
                        _ => CString::default(),
                    },
                )?;
            inst.hand_out_strings(strings, values);
            Ok(success)
        })
    }
}

/// The fast path of `fmi2SetReal` (see [`fmi_export::call::quick`]): every reference a
/// Real stored in the model's bytes, settable now, every value admitted; any other call
/// goes on to [`set_real_full`] with nothing written.
///
/// # Safety
/// See the module documentation.
#[inline(always)]
pub unsafe fn set_real<M: Model>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2Real,
) -> fmi2Status {
    let served = unsafe {
        quick::<M, Fmi2, _>(c, Function::SetReal, |inst| {
            let (vrs, values) = few(vr, nvr, value, nvr)?;
            let state_bit = inst.core.state as u16;
            let model = &mut inst.core.model;
            if !inst
                .reals
                .write_fast(vrs, values, model, state_bit, SCALARS_ONLY)
            {
                return None;
            }
            inst.dirty |= nvr != 0;
            Some(fmi2OK)
        })
    };
    match served {
        Some(status) => status,
        None => unsafe { set_real_full::<M>(c, vr, nvr, value) },
    }
}

/// `fmi2SetReal` through the full guard.
///
/// # Safety
/// See the module documentation.
#[inline(never)]
pub unsafe extern "C" fn set_real_full<M: Model>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2Real,
) -> fmi2Status {
    let f = Function::SetReal;
    unsafe {
        call::<M, Fmi2>(c, f, trace_array_call!(f, vr, nvr, value), |inst| {
            let (vrs, values) = lists(vr, nvr, "vr", value, nvr, "value")?;
            let state = inst.core.state;
            // The table is built at the first call it cannot serve (its first of all).
            let model = &mut inst.core.model;
            let prepared = inst.reals.write(vrs, values, model, state as u16) || {
                let view = &inst.view;
                inst.reals.ensure(model, || real_elements(view));
                inst.reals.write(vrs, values, model, state as u16)
            };
            if prepared {
                inst.dirty |= !vrs.is_empty();
                return Ok(Success::Ok);
            }
            // Checks every value before writing any, so a refused call changes nothing.
            // The write pass looks each reference up again: two array reads, cheaper than
            // keeping what the first pass found.
            for (&vr, &value) in vrs.iter().zip(values) {
                let slot = inst
                    .view
                    .index
                    .real(vr)
                    .ok_or_else(|| unknown_value_reference(BaseType::Real, vr))?;
                if !slot.accepts(value, state) {
                    refuse_real(&inst.view.table[slot.row], value, state)?;
                }
            }
            let model = &mut inst.core.model;
            for (&vr, &value) in vrs.iter().zip(values) {
                if let Some(slot) = inst.view.index.real(vr) {
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
    settable_now(var, state)?;
    match &var.access {
        Access::Real { min, max, .. } => check_real(
            || var.name().into_owned(),
            var.value_reference,
            value,
            *min,
            *max,
            var.unit,
        ),
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
        call::<M, Fmi2>(c, f, trace_array_call!(f, vr, nvr, value), |inst| {
            let vrs = slice(vr, nvr, "vr")?;
            let values = slice(value, nvr, "value")?;
            set_values(
                inst,
                BaseType::Integer,
                vrs,
                values,
                |var, v| match &var.access {
                    Access::Integer { min, max, .. } => check_integer(
                        || var.name().into_owned(),
                        var.value_reference,
                        v.into(),
                        *min,
                        *max,
                    ),
                    Access::Enumeration { ty, .. } => check_enumeration(
                        || var.name().into_owned(),
                        var.value_reference,
                        v.into(),
                        ty,
                    ),
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
        call::<M, Fmi2>(c, f, trace_array_call!(f, vr, nvr, value), |inst| {
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
        call::<M, Fmi2>(c, f, trace, |inst| {
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
// Partial derivatives
// ---------------------------------------------------------------------------------------

/// The scalars of `vrs` as the core's [`Element`](fmi_export::derivatives::Element)s;
/// `role` names the argument in messages.
fn derivative_elements<M: Model>(
    inst: &Instance<M>,
    vrs: &[fmi2ValueReference],
    role: &str,
) -> Result<Vec<fmi_export::derivatives::Element>, CallError> {
    vrs.iter()
        .map(|&vr| {
            let row = inst
                .view
                .index
                .real(vr)
                .map(|slot| slot.row)
                .ok_or_else(|| {
                    CallError::InvalidArgument(format!("{role} vr {vr}: no Real variable has it"))
                })?;
            let var = &inst.view.table[row];
            Ok(fmi_export::derivatives::Element {
                scalar: fmi_model::ScalarRef::new(var.declaration, var.element()),
                vr,
            })
        })
        .collect()
}

/// `fmi2GetDirectionalDerivative` (FMI 2.0.4 §2.1.9): `dvUnknown = J dvKnown`. `states` are
/// the model's `(state, derivative)` names (empty without Model Exchange).
///
/// # Safety
/// See the module documentation.
#[allow(clippy::too_many_arguments)]
pub unsafe fn get_directional_derivative<M: Model>(
    c: fmi2Component,
    unknowns: *const fmi2ValueReference,
    n_unknown: usize,
    knowns: *const fmi2ValueReference,
    n_known: usize,
    dv_known: *const fmi2Real,
    dv_unknown: *mut fmi2Real,
    states: &'static [(&'static str, &'static str)],
) -> fmi2Status {
    use fmi_export::derivatives::{evaluate, Direction};
    let f = Function::GetDirectionalDerivative;
    let trace = || unsafe {
        format!(
            "{}(nUnknown={n_unknown}, vUnknown_ref={}, nKnown={n_known}, vKnown_ref={}, \
             dvKnown={})",
            f.name(),
            show(unknowns, n_unknown),
            show(knowns, n_known),
            show(dv_known, n_known)
        )
    };
    unsafe {
        call::<M, Fmi2>(c, f, trace, |inst| {
            if !M::PROVIDES_DIRECTIONAL_DERIVATIVES {
                return Err(CallError::Unsupported(
                    "not provided (providesDirectionalDerivative = false)",
                ));
            }
            let unknown_vrs = slice(unknowns, n_unknown, "vUnknown_ref")?;
            let known_vrs = slice(knowns, n_known, "vKnown_ref")?;
            let seed = slice(dv_known, n_known, "dvKnown")?;
            let sensitivity = slice_mut(dv_unknown, n_unknown, "dvUnknown")?;
            let unknown_elements = derivative_elements(inst, unknown_vrs, "unknown")?;
            let known_elements = derivative_elements(inst, known_vrs, "known")?;
            evaluate(
                inst,
                f,
                Direction::Forward,
                states,
                &unknown_elements,
                &known_elements,
                seed,
                sensitivity,
            )
        })
    }
}

// ---------------------------------------------------------------------------------------
// Unsupported optional functions
// ---------------------------------------------------------------------------------------

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
        call::<M, Fmi2>(c, f, trace_array_call!(f, vr, nvr), |_| {
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
        call::<M, Fmi2>(c, f, trace_array_call!(f, vr, nvr), |_| {
            Err(CallError::Unsupported(
                "not supported (maxOutputDerivativeOrder = 0)",
            ))
        })
    }
}

// ---------------------------------------------------------------------------------------
// Stepping and status
// ---------------------------------------------------------------------------------------

/// The fast path of `fmi2DoStep` (see [`fmi_export::call::quick`]): a step the checks
/// accept goes straight to the model ([`step_accepted`]); any other call goes on to
/// [`do_step_full`].
///
/// # Safety
/// See the module documentation.
#[inline(always)]
pub unsafe fn do_step<M: Model>(
    c: fmi2Component,
    current_communication_point: fmi2Real,
    communication_step_size: fmi2Real,
    no_set_fmu_state_prior_to_current_point: fmi2Boolean,
) -> fmi2Status {
    let (t, h) = (current_communication_point, communication_step_size);
    let served = unsafe {
        quick::<M, Fmi2, _>(c, Function::DoStep, |inst| {
            let end = fmi_export::step::accepted(inst, t, h)?;
            Some(step_accepted(inst, t, h, end))
        })
    };
    match served {
        Some(status) => status,
        None => unsafe { do_step_full::<M>(c, t, h, no_set_fmu_state_prior_to_current_point) },
    }
}

/// The step of an admitted `fmi2DoStep` whose arguments the checks accepted, ending at
/// `end`. `extern "C"`: nothing unwinds out of it into the fast path.
#[inline(never)]
extern "C" fn step_accepted<M: Model>(
    inst: &mut Instance<M>,
    t: f64,
    h: f64,
    end: f64,
) -> fmi2Status {
    let f = Function::DoStep;
    let status = fmi_export::call::run(inst, f, |inst| {
        let outcome = fmi_export::step::advance_checked(inst, f, t, h, end)?;
        stepped(inst, outcome)
    });
    Fmi2::status(status)
}

/// `fmi2DoStep` through the full guard.
///
/// # Safety
/// See the module documentation.
#[inline(never)]
pub unsafe extern "C" fn do_step_full<M: Model>(
    c: fmi2Component,
    current_communication_point: fmi2Real,
    communication_step_size: fmi2Real,
    no_set_fmu_state_prior_to_current_point: fmi2Boolean,
) -> fmi2Status {
    let f = Function::DoStep;
    let (t, h) = (current_communication_point, communication_step_size);
    let no_set_prior = no_set_fmu_state_prior_to_current_point;
    let trace = || fmi_export::step::trace(f.name(), t, h, no_set_prior);
    unsafe { call::<M, Fmi2>(c, f, trace, |inst| step(inst, t, h)) }
}

/// A step that ended early is `fmi2Discard`, state StepFailed, with `fmi2LastSuccessfulTime`
/// and `fmi2Terminated` telling where and whether the model asks to end (FMI 2.0.4 §4.2.2).
fn step<M: Model>(inst: &mut Instance<M>, t: f64, h: f64) -> Result<Success, CallError> {
    let outcome = fmi_export::step::advance(inst, Function::DoStep, t, h)?;
    stepped(inst, outcome)
}

/// The answer to a step that was carried out (see [`step`]).
fn stepped<M: Model>(
    inst: &mut Instance<M>,
    outcome: (Success, Advance),
) -> Result<Success, CallError> {
    match outcome {
        (success, Advance::Complete) => Ok(success),
        (
            _,
            Advance::Stopped {
                at,
                terminated,
                reason,
            },
        ) => {
            inst.core.state = State::StepFailed;
            Err(CallError::Discard(format!(
                "step ended early at t = {at}{}: {reason}",
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
    unsafe { call::<M, Fmi2>(c, f, || format!("{}()", f.name()), |_| Ok(Success::Ok)) }
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
        call::<M, Fmi2>(
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
        call::<M, Fmi2>(
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
        call::<M, Fmi2>(
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
        call::<M, Fmi2>(
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
        call::<M, Fmi2>(
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
