//! The way into an instance, for every function that takes one.
//!
//! [`call`] runs one FMI call: a handle that is no live instance of this model and version
//! (NULL, freed, foreign) -> Error with nothing read through it (there is no logger to
//! tell); a call while another call on the same instance has not returned (from inside one
//! of its callbacks, or from a second thread) -> Error and one log line; the call trace
//! (`logCalls`); the version's state table; the body under `catch_unwind` (a panic becomes
//! Fatal and state Fatal); a refusal is logged as one line "<function>: reason".
//!
//! Refused arguments leave the instance as it was: the call had no effect, so there is
//! nothing to recover from. A failure of the model itself moves it to state Error.
#![allow(unsafe_code)]

use crate::instance::{Instance, Options, Tag};
use crate::logging::{Category, Logger};
use crate::registry::{Entered, Refusal, Reporting};
use crate::state::{Interface, State};
use crate::status::{CallError, Status, Success};
use crate::version::{Abi, Function};
use fmi_abi::args::panic_text;
use fmi_model::Model;
use std::ffi::CString;
use std::os::raw::c_void;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::ptr;

/// A call's hold on an instance: the registry's busy mark (dropped at the end of the
/// call) and the instance itself.
pub type Held<'a, M, A> = (Entered<'static, Logger<A>>, &'a mut Instance<M, A>);

/// The instance behind `handle` (the registry's, never an address), marked busy until the returned guard drops. `None` (the
/// call returns Error) when it is no live instance of `M` and `A`, or when another call on
/// it has not returned (refused with a log line, see [`crate::registry`]).
///
/// # Safety
/// `handle` is what the master passed; it is never dereferenced: the registry gives the
/// address of the live instance it stands for.
#[inline(always)]
pub unsafe fn enter<'a, M: Model, A: Abi>(
    handle: *mut c_void,
    function: A::Function,
) -> Option<Held<'a, M, A>> {
    let entered = match A::REGISTRY.enter(handle as usize) {
        Ok(entered) => entered,
        Err(Refusal::Unknown) => return None,
        Err(Refusal::Busy(report)) => {
            refuse_nested(report, function);
            return None;
        }
    };
    let address = entered.address() as *mut Instance<M, A>;
    // SAFETY: a registered address is a live Box<Instance<_, A>> from `instantiate`, whose
    // first field is the Tag (repr(C)); the tag check guards against an instance of
    // another model of this version linked into the same process.
    let tag = unsafe { &*(address as *const Tag) };
    if !tag.is_of::<M, A>() {
        return None;
    }
    // SAFETY: live, of type M, and no other call holds it (the registry says idle).
    Some((entered, unsafe { &mut *address }))
}

/// Tells the master, through the busy instance's logger, that its nested call was refused
/// (`None`: a call from inside that very report, refused silently).
#[cold]
#[inline(never)]
fn refuse_nested<A: Abi>(report: Option<Reporting<'_, Logger<A>>>, function: A::Function) {
    if let Some(logger) = report {
        logger.status(
            Status::Error,
            &format!(
                "{}: refused: another call on this instance has not returned yet \
                 (a call from inside one of its callbacks, or from a second thread)",
                function.name()
            ),
        );
    }
}

/// A call's fast path: `body` on the instance behind `handle` when it is a live, idle
/// instance of `M` and `A`, the call trace is off and the state admits `function`; `None`
/// (the instance as it was) for anything else, and whenever `body` says `None`, for the
/// caller to hand the call to the full path ([`call`]), which decides and logs. No panic
/// can start here and nothing needs unwinding: `body` must not panic either (its calls into
/// anything that could are `extern "C"`, which cannot unwind).
///
/// # Safety
/// As [`enter`].
#[inline(always)]
pub unsafe fn quick<M: Model, A: Abi, R>(
    handle: *mut c_void,
    function: A::Function,
    body: impl FnOnce(&mut Instance<M, A>) -> Option<R>,
) -> Option<R> {
    let entered = A::REGISTRY.try_enter(handle as usize)?;
    let address = entered.address() as *mut Instance<M, A>;
    // SAFETY: as in `enter`: a registered address is a live instance of `A` with its tag
    // first.
    let served = if unsafe { &*(address as *const Tag) }.is_of::<M, A>() {
        // SAFETY: live, of type M, and no other call holds it (the registry said idle).
        let inst = unsafe { &mut *address };
        if inst.logger.is_on(Category::Calls)
            || function.admit(inst.interface(), inst.core.state).is_err()
        {
            None
        } else {
            body(inst)
        }
    } else {
        None
    };
    entered.leave();
    served
}

/// The part of [`call`] after the instance was entered and the call admitted: `body` under
/// `catch_unwind`, a refusal logged, a panic Fatal. For a fast path that calls the model.
pub fn run<M: Model, A: Abi>(
    inst: &mut Instance<M, A>,
    function: A::Function,
    body: impl FnOnce(&mut Instance<M, A>) -> Result<Success, CallError>,
) -> Status {
    let outcome = catch_unwind(AssertUnwindSafe(|| match body(inst) {
        Ok(success) => success.status(),
        Err(error) => report(inst, function, error),
    }));
    outcome.unwrap_or_else(|payload| fatal(inst, function, payload.as_ref()))
}

/// Runs one FMI call on an instance; see the module documentation.
///
/// # Safety
/// As [`enter`].
#[inline(always)]
pub unsafe fn call<M: Model, A: Abi>(
    handle: *mut c_void,
    function: A::Function,
    trace: impl FnOnce() -> String,
    body: impl FnOnce(&mut Instance<M, A>) -> Result<Success, CallError>,
) -> Status {
    let Some((_entered, inst)) = (unsafe { enter::<M, A>(handle, function) }) else {
        return Status::Error;
    };
    let outcome = catch_unwind(AssertUnwindSafe(|| {
        if inst.logger.is_on(Category::Calls) {
            inst.logger.log(Status::Ok, Category::Calls, &trace());
        }
        let result = match function.admit(inst.interface(), inst.core.state) {
            Ok(()) => body(inst),
            Err(refusal) => Err(CallError::Refused(refusal)),
        };
        match result {
            Ok(success) => success.status(),
            Err(error) => report(inst, function, error),
        }
    }));
    outcome.unwrap_or_else(|payload| fatal(inst, function, payload.as_ref()))
}

/// [`call`], answering in the version's C status.
///
/// # Safety
/// As [`enter`].
#[inline(always)]
pub unsafe fn c_call<M: Model, A: Abi>(
    handle: *mut c_void,
    function: A::Function,
    trace: impl FnOnce() -> String,
    body: impl FnOnce(&mut Instance<M, A>) -> Result<Success, CallError>,
) -> A::CStatus {
    A::status(unsafe { call::<M, A>(handle, function, trace, body) })
}

#[cold]
#[inline(never)]
fn report<M: Model, A: Abi>(
    inst: &Instance<M, A>,
    function: A::Function,
    error: CallError,
) -> Status {
    let status = error.status();
    inst.logger
        .status(status, &format!("{}: {error}", function.name()));
    status
}

#[cold]
#[inline(never)]
fn fatal<M: Model, A: Abi>(
    inst: &mut Instance<M, A>,
    function: A::Function,
    payload: &(dyn std::any::Any + Send),
) -> Status {
    let _ = catch_unwind(AssertUnwindSafe(|| {
        inst.core.state = State::Fatal;
        inst.logger.status(
            Status::Fatal,
            &format!(
                "{}: internal error, instance unusable: {}",
                function.name(),
                panic_text(payload)
            ),
        );
    }));
    Status::Fatal
}

/// The position of the first value of a read that is not finite, if any: no NaN or
/// infinity is handed to a master with an OK status (the version names the variable).
#[inline]
pub fn first_non_finite(values: &[f64]) -> Option<usize> {
    // Without a branch per value (a non-finite read is the rare case), so that several
    // are tested at once: `v - v` is 0 exactly when `v` is finite (NaN for NaN and both
    // infinities).
    #[allow(clippy::eq_op)]
    if values.iter().fold(true, |all, &v| all & (v - v == 0.0)) {
        None
    } else {
        values.iter().position(|v| !v.is_finite())
    }
}

/// The refusal of a read whose value for `name` (vr `vr`) is not finite.
#[cold]
#[inline(never)]
pub fn non_finite_read(name: String, vr: u32, value: f64) -> CallError {
    CallError::Model(format!(
        "variable {name} (vr {vr}) is {value} at the current state: not finite; the model \
         cannot evaluate this state"
    ))
}

/// What a master passed to an instantiate function, copied.
#[derive(Debug)]
pub struct Request {
    /// The C function, for the trace and the refusals.
    pub function: &'static str,
    pub interface: Interface,
    pub options: Options,
    pub instance_name: Option<CString>,
    pub token: Option<CString>,
    pub resource_location: Option<CString>,
    /// The call trace, in the version's words.
    pub trace: String,
    /// The version's own reason to refuse (an fmuType it does not know, an option the FMU
    /// lacks), checked after the instance name.
    pub refusal: Option<String>,
}

/// A string argument as a user would write it: quoted, or NULL.
pub fn shown(s: &Option<CString>) -> String {
    match s {
        Some(s) => format!("\"{}\"", s.to_string_lossy()),
        None => "NULL".into(),
    }
}

/// A new instance as the master's handle, or NULL with the reason logged.
///
/// `supports_model_exchange`: the model implements Model Exchange.
pub fn instantiate<M: Model, A: Abi>(
    logger: Logger<A>,
    request: Request,
    supports_model_exchange: bool,
) -> *mut c_void {
    let function = request.function;
    let fallback = logger.clone();
    let outcome = catch_unwind(AssertUnwindSafe(move || {
        if logger.is_on(Category::Calls) {
            logger.log(Status::Ok, Category::Calls, &request.trace);
        }
        let expected = A::interface_uuid::<M>().braced().to_string();
        let token = request.token.as_ref().map(|t| t.to_bytes());
        let refusal = if request.instance_name.as_ref().is_none_or(|n| n.is_empty()) {
            Some("instanceName is NULL or empty".to_string())
        } else if let Some(reason) = request.refusal {
            Some(reason)
        } else if request.interface == Interface::ModelExchange && !supports_model_exchange {
            Some(format!(
                "{} offers Co-Simulation only, not Model Exchange",
                M::MODEL_IDENTIFIER
            ))
        } else if token != Some(expected.as_bytes()) {
            Some(format!(
                "{} {} does not match this FMU's {expected}",
                A::TOKEN_ARGUMENT,
                shown(&request.token)
            ))
        } else {
            None
        };
        if let Some(reason) = refusal {
            logger.status(Status::Error, &format!("{function}: {reason}"));
            return ptr::null_mut();
        }
        let report = logger.clone();
        let instance = Box::new(Instance::<M, A>::new(
            logger,
            request.interface,
            request.options,
            request.resource_location,
        ));
        let address = Box::into_raw(instance);
        match A::REGISTRY.insert(address as usize, report) {
            // The master gets the registry's handle, never the address: a stale handle is
            // refused even when the allocator hands the memory to a new instance.
            Ok(handle) => ptr::without_provenance_mut(handle),
            Err(full) => {
                // SAFETY: `address` came from Box::into_raw just above, never handed out.
                let instance = unsafe { Box::from_raw(address) };
                instance
                    .logger
                    .status(Status::Error, &format!("{function}: {full}"));
                ptr::null_mut()
            }
        }
    }));
    outcome.unwrap_or_else(|payload| {
        let _ = catch_unwind(AssertUnwindSafe(|| {
            fallback.status(
                Status::Fatal,
                &format!(
                    "{function}: internal error: {}",
                    panic_text(payload.as_ref())
                ),
            )
        }));
        ptr::null_mut()
    })
}

/// Frees the instance behind `handle` and every FMU state it still holds; anything that is
/// no live instance is ignored (the function returns nothing to tell).
///
/// # Safety
/// As [`enter`].
pub unsafe fn free_instance<M: Model, A: Abi>(handle: *mut c_void, function: A::Function) {
    let Some((entered, inst)) = (unsafe { enter::<M, A>(handle, function) }) else {
        return;
    };
    let _ = catch_unwind(AssertUnwindSafe(|| {
        if inst.logger.is_on(Category::Calls) {
            inst.logger.log(
                Status::Ok,
                Category::Calls,
                &format!("{}()", function.name()),
            );
        }
    }));
    // Unregistered before the memory goes: a second free, or any later call, is refused
    // without reading it.
    inst.tag = Tag::cleared();
    let address = entered.address() as *mut Instance<M, A>;
    entered.remove();
    let _ = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: the registered address came from Box::into_raw in `instantiate`; `inst`
        // is not used again.
        drop(unsafe { Box::from_raw(address) });
    }));
}
