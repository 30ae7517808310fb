//! The C-level bodies of the functions whose signatures are the same in FMI 2.0 and 3.0
//! (FMU states, the argument-free lifecycle calls, the Model Exchange vectors): pointers
//! checked and unpacked here, once. [`export_shared!`](crate::export_shared) generates their
//! symbols from each version's names; a version layer writes only what differs.
//!
//! # Safety
//! The master passes pointers valid as the standard requires for the function; NULL where
//! an argument must not be NULL is refused with a log line.
#![allow(unsafe_code)]

use crate::call::call;
use crate::model_exchange::{self as me, Vector};
use crate::status::{Status, Success};
use crate::version::{Abi, Function};
use crate::{fmu_state, lifecycle};
use fmi_abi::args::{out, show, slice, slice_mut};
use fmi_model::{ContinuousModel, Model};
use std::os::raw::c_void;

/// # Safety
/// See the module documentation.
pub unsafe fn get_fmu_state<M: Model, A: Abi>(
    c: *mut c_void,
    f: A::Function,
    state: *mut *mut c_void,
) -> Status {
    let trace = || format!("{}(state={:p})", f.name(), state);
    unsafe {
        call::<M, A>(c, f, trace, |inst| {
            fmu_state::get(inst, out(state, "FMUstate")?)
        })
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn set_fmu_state<M: Model, A: Abi>(
    c: *mut c_void,
    f: A::Function,
    state: *mut c_void,
) -> Status {
    let trace = || format!("{}(state={state:p})", f.name());
    unsafe { call::<M, A>(c, f, trace, |inst| fmu_state::set(inst, state)) }
}

/// # Safety
/// See the module documentation.
pub unsafe fn free_fmu_state<M: Model, A: Abi>(
    c: *mut c_void,
    f: A::Function,
    state: *mut *mut c_void,
) -> Status {
    let trace = || format!("{}(state={:p})", f.name(), state);
    unsafe {
        call::<M, A>(c, f, trace, |inst| {
            fmu_state::free(inst, out(state, "FMUstate")?)
        })
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn serialized_fmu_state_size<M: Model, A: Abi>(
    c: *mut c_void,
    f: A::Function,
    state: *mut c_void,
    size: *mut usize,
) -> Status {
    let trace = || format!("{}(state={state:p})", f.name());
    unsafe {
        call::<M, A>(c, f, trace, |inst| {
            let size = out(size, "size")?;
            *size = fmu_state::serialize(inst, state)?.len();
            Ok(Success::Ok)
        })
    }
}

/// `size_function` is the version's size query, named when `size` is not its answer.
///
/// # Safety
/// See the module documentation.
pub unsafe fn serialize_fmu_state<M: Model, A: Abi>(
    c: *mut c_void,
    f: A::Function,
    size_function: A::Function,
    state: *mut c_void,
    serialized: *mut u8,
    size: usize,
) -> Status {
    let trace = || format!("{}(state={state:p}, size={size})", f.name());
    unsafe {
        call::<M, A>(c, f, trace, |inst| {
            let buffer = slice_mut(serialized, size, "serializedState")?;
            fmu_state::serialize_into(inst, state, buffer, size_function.name())
        })
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn deserialize_fmu_state<M: Model, A: Abi>(
    c: *mut c_void,
    f: A::Function,
    serialized: *const u8,
    size: usize,
    state: *mut *mut c_void,
) -> Status {
    let trace = || format!("{}(size={size}, state={:p})", f.name(), state);
    unsafe {
        call::<M, A>(c, f, trace, |inst| {
            let bytes = slice(serialized, size, "serializedState")?;
            fmu_state::deserialize(inst, bytes, out(state, "FMUstate")?)
        })
    }
}

/// The body of a debug-logging call: `categories` unpacked to their names (a NULL entry
/// stays `None`, refused by position in [`lifecycle::set_debug_logging`]).
///
/// # Safety
/// `categories` points to `n` pointers, each NULL or a NUL-terminated string.
pub unsafe fn set_debug_logging<M: Model, A: Abi>(
    inst: &mut crate::Instance<M, A>,
    logging_on: bool,
    categories: *const *const std::os::raw::c_char,
    n: usize,
) -> Result<Success, crate::CallError> {
    let names: Vec<Option<&[u8]>> = unsafe { slice(categories, n, "categories")? }
        .iter()
        // SAFETY: non-null names are NUL-terminated per the standard.
        .map(|&p| (!p.is_null()).then(|| unsafe { std::ffi::CStr::from_ptr(p) }.to_bytes()))
        .collect();
    lifecycle::set_debug_logging(inst, logging_on, &names)
}

/// # Safety
/// See the module documentation.
pub unsafe fn exit_initialization_mode<M: Model, A: Abi>(c: *mut c_void, f: A::Function) -> Status {
    let trace = || format!("{}()", f.name());
    unsafe { call::<M, A>(c, f, trace, |inst| lifecycle::exit_initialization(inst, f)) }
}

/// # Safety
/// See the module documentation.
pub unsafe fn terminate<M: Model, A: Abi>(c: *mut c_void, f: A::Function) -> Status {
    unsafe {
        call::<M, A>(
            c,
            f,
            || format!("{}()", f.name()),
            |inst| lifecycle::terminate(inst, f),
        )
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn reset<M: Model, A: Abi>(c: *mut c_void, f: A::Function) -> Status {
    unsafe { call::<M, A>(c, f, || format!("{}()", f.name()), lifecycle::reset) }
}

/// # Safety
/// See the module documentation.
pub unsafe fn set_time<M: ContinuousModel, A: Abi>(
    c: *mut c_void,
    f: A::Function,
    time: f64,
) -> Status {
    let trace = || format!("{}(time={time})", f.name());
    unsafe { call::<M, A>(c, f, trace, |inst| me::set_time(inst, time)) }
}

/// # Safety
/// See the module documentation.
pub unsafe fn set_continuous_states<M: ContinuousModel, A: Abi>(
    c: *mut c_void,
    f: A::Function,
    x: *const f64,
    nx: usize,
) -> Status {
    let trace = || format!("{}(nx={nx}, x={})", f.name(), unsafe { show(x, nx) });
    unsafe { call::<M, A>(c, f, trace, |inst| me::set_states(inst, slice(x, nx, "x")?)) }
}

/// One of the Model Exchange vectors into the master's `values`.
///
/// # Safety
/// See the module documentation.
pub unsafe fn read_vector<M: ContinuousModel, A: Abi>(
    c: *mut c_void,
    f: A::Function,
    vector: Vector,
    values: *mut f64,
    n: usize,
) -> Status {
    let trace = || format!("{}(n={n})", f.name());
    unsafe {
        call::<M, A>(c, f, trace, |inst| {
            me::read(inst, f, vector, slice_mut(values, n, "values")?)
        })
    }
}

/// # Safety
/// See the module documentation.
pub unsafe fn enter_continuous_time_mode<M: ContinuousModel, A: Abi>(
    c: *mut c_void,
    f: A::Function,
) -> Status {
    let trace = || format!("{}()", f.name());
    unsafe { call::<M, A>(c, f, trace, me::enter_continuous_time_mode) }
}

/// `#[no_mangle] pub unsafe extern "C"` functions, one per `name(args) -> ret => body;`
/// line: the form of every exported FMI symbol, in both versions. The items carry
/// `#[allow(unsafe_code)]`, so the model crate that invokes a version's export macro keeps
/// `#![deny(unsafe_code)]` for everything else.
#[macro_export]
macro_rules! export_symbols {
    ($(
        $name:ident ( $($arg:ident : $ty:ty),* $(,)? ) -> $ret:ty => $body:expr;
    )*) => {
        $(
            #[allow(
                unsafe_code, non_snake_case, unused_variables, clippy::missing_safety_doc,
                clippy::unused_unit, clippy::too_many_arguments
            )]
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn $name($($arg: $ty),*) -> $ret {
                #[allow(unused_unsafe)]
                unsafe {
                    $body
                }
            }
        )*
    };
}

/// The `#[no_mangle]` symbols of the functions [`crate::raw`] serves, from one version's C
/// names: each name is looked up in the version's function table at compile time. The C
/// status and byte types are named as the version's headers name them (a C header generated
/// from the expanded source must see `fmi2Status`, not a projection it cannot resolve).
/// Invoked by each version's export macro.
#[macro_export]
macro_rules! export_shared {
    (@symbol $abi:ty, $status:ty, $name:ident ( $c:ident : $c_type:ty $(, $arg:ident : $ty:ty)* ) => $raw:ident::<$model:ty>($($value:expr),*)) => {
        $crate::export_symbols! {
            $name($c: $c_type $(, $arg: $ty)*) -> $status => {
                const F: <$abi as $crate::Abi>::Function =
                    <$abi as $crate::Abi>::Function::named(stringify!($name));
                <$abi as $crate::Abi>::status($crate::raw::$raw::<$model, $abi>($c, F, $($value),*))
            };
        }
    };
    (
        $model:ty, $abi:ty, status = $status:ty, byte = $byte:ty,
        fmu_state = [$get:ident, $set:ident, $free:ident, $size:ident, $ser:ident, $de:ident],
        lifecycle = [$exit:ident, $term:ident, $reset:ident]
    ) => {
        $crate::export_shared! { @symbol $abi, $status, $get(c: *mut ::std::os::raw::c_void, state: *mut *mut ::std::os::raw::c_void)
            => get_fmu_state::<$model>(state) }
        $crate::export_shared! { @symbol $abi, $status, $set(c: *mut ::std::os::raw::c_void, state: *mut ::std::os::raw::c_void)
            => set_fmu_state::<$model>(state) }
        $crate::export_shared! { @symbol $abi, $status, $free(c: *mut ::std::os::raw::c_void, state: *mut *mut ::std::os::raw::c_void)
            => free_fmu_state::<$model>(state) }
        $crate::export_shared! { @symbol $abi, $status, $size(c: *mut ::std::os::raw::c_void, state: *mut ::std::os::raw::c_void, size: *mut usize)
            => serialized_fmu_state_size::<$model>(state, size) }
        $crate::export_shared! { @symbol $abi, $status, $ser(
                c: *mut ::std::os::raw::c_void, state: *mut ::std::os::raw::c_void,
                serialized: *mut $byte, size: usize
            ) => serialize_fmu_state::<$model>(
                <$abi as $crate::Abi>::Function::named(stringify!($size)), state, serialized as *mut u8, size
            ) }
        $crate::export_shared! { @symbol $abi, $status, $de(
                c: *mut ::std::os::raw::c_void, serialized: *const $byte,
                size: usize, state: *mut *mut ::std::os::raw::c_void
            ) => deserialize_fmu_state::<$model>(serialized as *const u8, size, state) }
        $crate::export_shared! { @symbol $abi, $status, $exit(c: *mut ::std::os::raw::c_void) => exit_initialization_mode::<$model>() }
        $crate::export_shared! { @symbol $abi, $status, $term(c: *mut ::std::os::raw::c_void) => terminate::<$model>() }
        $crate::export_shared! { @symbol $abi, $status, $reset(c: *mut ::std::os::raw::c_void) => reset::<$model>() }
    };
    (
        $model:ty, $abi:ty, status = $status:ty,
        model_exchange = [$time:ident, $states_in:ident, $der:ident, $ind:ident, $states:ident, $nom:ident, $ctm:ident]
    ) => {
        $crate::export_shared! { @symbol $abi, $status, $time(c: *mut ::std::os::raw::c_void, time: f64) => set_time::<$model>(time) }
        $crate::export_shared! { @symbol $abi, $status, $states_in(c: *mut ::std::os::raw::c_void, x: *const f64, nx: usize)
            => set_continuous_states::<$model>(x, nx) }
        $crate::export_shared! { @symbol $abi, $status, $der(c: *mut ::std::os::raw::c_void, values: *mut f64, n: usize)
            => read_vector::<$model>($crate::model_exchange::Vector::Derivatives, values, n) }
        $crate::export_shared! { @symbol $abi, $status, $ind(c: *mut ::std::os::raw::c_void, values: *mut f64, n: usize)
            => read_vector::<$model>($crate::model_exchange::Vector::EventIndicators, values, n) }
        $crate::export_shared! { @symbol $abi, $status, $states(c: *mut ::std::os::raw::c_void, values: *mut f64, n: usize)
            => read_vector::<$model>($crate::model_exchange::Vector::States, values, n) }
        $crate::export_shared! { @symbol $abi, $status, $nom(c: *mut ::std::os::raw::c_void, values: *mut f64, n: usize)
            => read_vector::<$model>($crate::model_exchange::Vector::Nominals, values, n) }
        $crate::export_shared! { @symbol $abi, $status, $ctm(c: *mut ::std::os::raw::c_void) => enter_continuous_time_mode::<$model>() }
    };
}
