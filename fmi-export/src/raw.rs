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

/// # Safety
/// See the module documentation.
pub unsafe fn exit_initialization_mode<M: Model, A: Abi>(c: *mut c_void, f: A::Function) -> Status {
    let trace = || format!("{}()", f.name());
    unsafe { call::<M, A>(c, f, trace, |inst| lifecycle::exit_initialization(inst, f)) }
}

/// # Safety
/// See the module documentation.
pub unsafe fn terminate<M: Model, A: Abi>(c: *mut c_void, f: A::Function) -> Status {
    unsafe { call::<M, A>(c, f, || format!("{}()", f.name()), lifecycle::terminate) }
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

/// The `#[no_mangle]` symbols of the functions [`crate::raw`] serves, from one version's
/// names, C types and function table. Invoked by each version's export macro.
#[macro_export]
macro_rules! export_shared {
    (@symbol $name:ident ( $($arg:ident : $ty:ty),* ) -> $ret:ty => $body:expr) => {
        #[allow(unsafe_code, non_snake_case, clippy::missing_safety_doc)]
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $name($($arg: $ty),*) -> $ret {
            #[allow(unused_unsafe)]
            unsafe {
                $body
            }
        }
    };
    (
        model = $model:ty, abi = $abi:ty, function = $f:ty,
        types = { instance: $inst:ty, state: $state:ty, byte: $byte:ty, status: $status:ty },
        fmu_state = {
            $get:ident = $get_f:ident, $set:ident = $set_f:ident, $free:ident = $free_f:ident,
            $size:ident = $size_f:ident, $ser:ident = $ser_f:ident, $de:ident = $de_f:ident
        },
        lifecycle = { $exit:ident = $exit_f:ident, $term:ident = $term_f:ident, $reset:ident = $reset_f:ident }
    ) => {
        $crate::export_shared! { @symbol $get(c: $inst, state: *mut $state) -> $status
            => <$abi as $crate::Abi>::status($crate::raw::get_fmu_state::<$model, $abi>(c, <$f>::$get_f, state)) }
        $crate::export_shared! { @symbol $set(c: $inst, state: $state) -> $status
            => <$abi as $crate::Abi>::status($crate::raw::set_fmu_state::<$model, $abi>(c, <$f>::$set_f, state)) }
        $crate::export_shared! { @symbol $free(c: $inst, state: *mut $state) -> $status
            => <$abi as $crate::Abi>::status($crate::raw::free_fmu_state::<$model, $abi>(c, <$f>::$free_f, state)) }
        $crate::export_shared! { @symbol $size(c: $inst, state: $state, size: *mut usize) -> $status
            => <$abi as $crate::Abi>::status($crate::raw::serialized_fmu_state_size::<$model, $abi>(c, <$f>::$size_f, state, size)) }
        $crate::export_shared! { @symbol $ser(c: $inst, state: $state, serialized: *mut $byte, size: usize) -> $status
            => <$abi as $crate::Abi>::status($crate::raw::serialize_fmu_state::<$model, $abi>(
                c, <$f>::$ser_f, <$f>::$size_f, state, serialized as *mut u8, size)) }
        $crate::export_shared! { @symbol $de(c: $inst, serialized: *const $byte, size: usize, state: *mut $state) -> $status
            => <$abi as $crate::Abi>::status($crate::raw::deserialize_fmu_state::<$model, $abi>(
                c, <$f>::$de_f, serialized as *const u8, size, state)) }
        $crate::export_shared! { @symbol $exit(c: $inst) -> $status
            => <$abi as $crate::Abi>::status($crate::raw::exit_initialization_mode::<$model, $abi>(c, <$f>::$exit_f)) }
        $crate::export_shared! { @symbol $term(c: $inst) -> $status
            => <$abi as $crate::Abi>::status($crate::raw::terminate::<$model, $abi>(c, <$f>::$term_f)) }
        $crate::export_shared! { @symbol $reset(c: $inst) -> $status
            => <$abi as $crate::Abi>::status($crate::raw::reset::<$model, $abi>(c, <$f>::$reset_f)) }
    };
    (
        model = $model:ty, abi = $abi:ty, function = $f:ty,
        types = { instance: $inst:ty, status: $status:ty },
        model_exchange = {
            $time:ident = $time_f:ident, $states_in:ident = $states_in_f:ident,
            $der:ident = $der_f:ident, $ind:ident = $ind_f:ident, $states:ident = $states_f:ident,
            $nom:ident = $nom_f:ident, $ctm:ident = $ctm_f:ident
        }
    ) => {
        $crate::export_shared! { @symbol $time(c: $inst, time: f64) -> $status
            => <$abi as $crate::Abi>::status($crate::raw::set_time::<$model, $abi>(c, <$f>::$time_f, time)) }
        $crate::export_shared! { @symbol $states_in(c: $inst, x: *const f64, nx: usize) -> $status
            => <$abi as $crate::Abi>::status($crate::raw::set_continuous_states::<$model, $abi>(c, <$f>::$states_in_f, x, nx)) }
        $crate::export_shared! { @symbol $der(c: $inst, values: *mut f64, n: usize) -> $status
            => <$abi as $crate::Abi>::status($crate::raw::read_vector::<$model, $abi>(
                c, <$f>::$der_f, $crate::model_exchange::Vector::Derivatives, values, n)) }
        $crate::export_shared! { @symbol $ind(c: $inst, values: *mut f64, n: usize) -> $status
            => <$abi as $crate::Abi>::status($crate::raw::read_vector::<$model, $abi>(
                c, <$f>::$ind_f, $crate::model_exchange::Vector::EventIndicators, values, n)) }
        $crate::export_shared! { @symbol $states(c: $inst, values: *mut f64, n: usize) -> $status
            => <$abi as $crate::Abi>::status($crate::raw::read_vector::<$model, $abi>(
                c, <$f>::$states_f, $crate::model_exchange::Vector::States, values, n)) }
        $crate::export_shared! { @symbol $nom(c: $inst, values: *mut f64, n: usize) -> $status
            => <$abi as $crate::Abi>::status($crate::raw::read_vector::<$model, $abi>(
                c, <$f>::$nom_f, $crate::model_exchange::Vector::Nominals, values, n)) }
        $crate::export_shared! { @symbol $ctm(c: $inst) -> $status
            => <$abi as $crate::Abi>::status($crate::raw::enter_continuous_time_mode::<$model, $abi>(c, <$f>::$ctm_f)) }
    };
}
