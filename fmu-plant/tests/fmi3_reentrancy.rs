//! A hostile FMI 3.0 master calls back into an instance from inside that instance's
//! logMessage callback, on every path that logs (call trace, warning, error, the trace of
//! fmi3FreeInstance), with every kind of function, fmi3FreeInstance and fmi3Reset included,
//! and from a second thread while the call runs. Each nested call must get fmi3Error and a
//! log line naming it, the outer call must finish normally, and nothing may touch freed
//! memory: run this binary under valgrind (see tests/robustness/README.md) for the last part.
//! The intermediateUpdate callback a master passes is never called (the FMU does not
//! provide intermediate update), however the step ends.
#![allow(unsafe_code)]

use crate::fmi3_common;

use fmi3_common::vr;
use fmi_testkit::fmi3_ffi::*;
use fmi_testkit::Fmi3Functions;
use std::ffi::{c_void, CStr, CString};
use std::ptr;
use std::sync::atomic::{AtomicBool, AtomicPtr, AtomicUsize, Ordering};
use std::sync::Mutex;

/// The kit's table of the plant's FMI 3.0 entry points: every call below goes through it,
/// as a C master's function pointers.
static FMU: &Fmi3Functions = &fmi3_common::FUNCTIONS;

/// A function a hostile logger calls on the instance that is logging.
type Nested = unsafe fn(fmi3Instance) -> fmi3Status;

unsafe fn nested_reset(c: fmi3Instance) -> fmi3Status {
    unsafe { (FMU.reset)(c) }
}
unsafe fn nested_free(c: fmi3Instance) -> fmi3Status {
    unsafe { (FMU.free_instance)(c) };
    // Void: whether it was refused shows afterwards, in the instance still working.
    fmi3Error
}
unsafe fn nested_step(c: fmi3Instance) -> fmi3Status {
    let (mut event, mut terminate, mut early, mut last) = (false, false, false, 0.0);
    unsafe {
        (FMU.co_simulation.do_step)(
            c,
            0.0,
            0.01,
            true,
            &mut event,
            &mut terminate,
            &mut early,
            &mut last,
        )
    }
}
unsafe fn nested_get(c: fmi3Instance) -> fmi3Status {
    let (vr, mut x) = (vr("mass"), 0.0);
    unsafe { (FMU.get_float64)(c, &vr, 1, &mut x, 1) }
}
unsafe fn nested_set(c: fmi3Instance) -> fmi3Status {
    let (vr, u) = (vr("thrust_cmd"), 1.0);
    unsafe { (FMU.set_float64)(c, &vr, 1, &u, 1) }
}
unsafe fn nested_terminate(c: fmi3Instance) -> fmi3Status {
    unsafe { (FMU.terminate)(c) }
}
unsafe fn nested_debug_logging(c: fmi3Instance) -> fmi3Status {
    unsafe { (FMU.set_debug_logging)(c, false, 0, ptr::null()) }
}
unsafe fn nested_get_state(c: fmi3Instance) -> fmi3Status {
    let mut state: fmi3FMUState = ptr::null_mut();
    unsafe { (FMU.get_fmu_state)(c, &mut state) }
}
unsafe fn nested_enter_init(c: fmi3Instance) -> fmi3Status {
    unsafe { (FMU.enter_initialization_mode)(c, false, 0.0, 0.0, false, 0.0) }
}
unsafe fn nested_set_time(c: fmi3Instance) -> fmi3Status {
    unsafe { (FMU.model_exchange.set_time)(c, 0.0) }
}
/// A second thread calls while the first one's call is still running.
unsafe fn nested_from_thread(c: fmi3Instance) -> fmi3Status {
    let address = c as usize;
    std::thread::spawn(move || unsafe { nested_get(address as fmi3Instance) })
        .join()
        .unwrap()
}

const NESTED: [(&str, Nested); 11] = [
    ("fmi3Reset", nested_reset),
    ("fmi3FreeInstance", nested_free),
    ("fmi3DoStep", nested_step),
    ("fmi3GetFloat64", nested_get),
    ("fmi3SetFloat64", nested_set),
    ("fmi3Terminate", nested_terminate),
    ("fmi3SetDebugLogging", nested_debug_logging),
    ("fmi3GetFMUState", nested_get_state),
    ("fmi3EnterInitializationMode", nested_enter_init),
    ("fmi3SetTime", nested_set_time),
    ("fmi3GetFloat64", nested_from_thread),
];

/// The master's instanceEnvironment.
struct Hostile {
    component: AtomicPtr<c_void>,
    nested: Mutex<Option<Nested>>,
    armed: AtomicBool,
    /// Depth of logger calls on the stack; its maximum shows whether re-entry recursed.
    depth: AtomicUsize,
    max_depth: AtomicUsize,
    statuses: Mutex<Vec<fmi3Status>>,
    messages: Mutex<Vec<(fmi3Status, String)>>,
    /// Calls of the intermediateUpdate callback (there must be none).
    intermediate_updates: AtomicUsize,
}

unsafe extern "C" fn log_message(
    environment: fmi3InstanceEnvironment,
    status: fmi3Status,
    _category: fmi3String,
    message: fmi3String,
) {
    // SAFETY: the environment is a live, boxed Hostile; the message NUL-terminated.
    let hostile = unsafe { &*(environment as *const Hostile) };
    let text = unsafe { CStr::from_ptr(message) }
        .to_string_lossy()
        .into_owned();
    hostile.messages.lock().unwrap().push((status, text));
    let depth = hostile.depth.fetch_add(1, Ordering::SeqCst) + 1;
    hostile.max_depth.fetch_max(depth, Ordering::SeqCst);
    // The test's own bound, should the FMU let nested calls through and recurse.
    if hostile.armed.load(Ordering::SeqCst) && depth < 8 {
        let c = hostile.component.load(Ordering::SeqCst);
        let nested = *hostile.nested.lock().unwrap();
        if let Some(nested) = nested {
            // SAFETY: the instance the test created; the FMU must cope.
            let s = unsafe { nested(c) };
            hostile.statuses.lock().unwrap().push(s);
        }
    }
    hostile.depth.fetch_sub(1, Ordering::SeqCst);
}

/// Records the call and re-enters, as a hostile master would; must never run.
#[allow(clippy::too_many_arguments)]
unsafe extern "C" fn intermediate_update(
    environment: fmi3InstanceEnvironment,
    _time: fmi3Float64,
    _intermediate_variable_set_requested: fmi3Boolean,
    _intermediate_variable_get_allowed: fmi3Boolean,
    _intermediate_step_finished: fmi3Boolean,
    _can_return_early: fmi3Boolean,
    early_return_requested: *mut fmi3Boolean,
    _early_return_time: *mut fmi3Float64,
) {
    // SAFETY: as in `log_message`; the out-pointer is the FMU's.
    let hostile = unsafe { &*(environment as *const Hostile) };
    hostile.intermediate_updates.fetch_add(1, Ordering::SeqCst);
    unsafe {
        if !early_return_requested.is_null() {
            *early_return_requested = true;
        }
        (FMU.reset)(hostile.component.load(Ordering::SeqCst));
    }
}

impl Hostile {
    fn new() -> Box<Hostile> {
        Box::new(Hostile {
            component: AtomicPtr::new(ptr::null_mut()),
            nested: Mutex::new(None),
            armed: AtomicBool::new(false),
            depth: AtomicUsize::new(0),
            max_depth: AtomicUsize::new(0),
            statuses: Mutex::new(Vec::new()),
            messages: Mutex::new(Vec::new()),
            intermediate_updates: AtomicUsize::new(0),
        })
    }

    fn instantiate(&self, logging_on: bool) -> fmi3Instance {
        let token = CString::new(fmi3_common::token()).unwrap();
        // SAFETY: valid strings and callbacks; `self` outlives the instance.
        let c = unsafe {
            (FMU.co_simulation.instantiate_co_simulation)(
                c"hostile".as_ptr(),
                token.as_ptr(),
                ptr::null(),
                false,
                logging_on,
                false,
                true,
                ptr::null(),
                0,
                self as *const Hostile as *mut c_void,
                Some(log_message),
                Some(intermediate_update),
            )
        };
        assert!(!c.is_null());
        self.component.store(c, Ordering::SeqCst);
        c
    }

    /// Runs `outer` with every logger call re-entering with `nested`.
    fn while_armed<T>(&self, nested: Nested, outer: impl FnOnce() -> T) -> T {
        *self.nested.lock().unwrap() = Some(nested);
        self.armed.store(true, Ordering::SeqCst);
        let result = outer();
        self.armed.store(false, Ordering::SeqCst);
        result
    }

    fn refusals(&self, function: &str) -> usize {
        self.messages
            .lock()
            .unwrap()
            .iter()
            .filter(|(s, m)| {
                *s == fmi3Error && m.starts_with(function) && m.contains("has not returned")
            })
            .count()
    }
}

fn step(c: fmi3Instance, t: f64, h: f64) -> fmi3Status {
    let (mut event, mut terminate, mut early, mut last) = (false, false, false, 0.0);
    // SAFETY: valid out-parameters; the instance is the test's.
    unsafe {
        (FMU.co_simulation.do_step)(
            c,
            t,
            h,
            true,
            &mut event,
            &mut terminate,
            &mut early,
            &mut last,
        )
    }
}
fn enter_init(c: fmi3Instance) -> fmi3Status {
    unsafe { (FMU.enter_initialization_mode)(c, false, 0.0, 0.0, false, 0.0) }
}
fn exit_init(c: fmi3Instance) -> fmi3Status {
    unsafe { (FMU.exit_initialization_mode)(c) }
}
fn illegal_step(c: fmi3Instance) -> fmi3Status {
    // fmi3DoStep before initialization: an error.
    step(c, 0.0, 0.01)
}
fn set_tilted_start(c: fmi3Instance) -> fmi3Status {
    // An initial attitude 5e-4 off unit norm: normalised with a warning at exit.
    let q = [1.0005, 0.0, 0.0, 0.0];
    let vr = vr("q0_body_to_nue");
    unsafe { (FMU.set_float64)(c, &vr, 1, q.as_ptr(), 4) }
}

/// How each logging path is triggered: the outer call, what runs unarmed before it, and
/// the status the outer call must still return with a hostile logger.
type Path = (
    &'static str,
    bool,
    fn(fmi3Instance) -> fmi3Status,
    fn(fmi3Instance) -> fmi3Status,
    fmi3Status,
);

const PATHS: [Path; 3] = [
    ("call trace", true, set_tilted_start, enter_init, fmi3OK),
    ("error", false, set_tilted_start, illegal_step, fmi3Error),
    ("warning", false, enter_init, exit_init, fmi3Warning),
];

#[test]
fn every_nested_call_from_every_logging_path_is_refused_and_named() {
    for (path, logging_on, before, outer, expected) in PATHS {
        for (function, nested) in NESTED {
            // GIVEN an instance whose logger calls `function` on it whenever it logs
            let hostile = Hostile::new();
            let c = hostile.instantiate(logging_on);
            assert_eq!(set_tilted_start(c), fmi3OK);
            before(c);
            // WHEN the outer call logs
            let status = hostile.while_armed(nested, || outer(c));
            // THEN the outer call finishes as it would have without the nesting
            assert_eq!(status, expected, "{path}, nested {function}");
            let statuses = hostile.statuses.lock().unwrap().clone();
            assert!(!statuses.is_empty(), "{path}: the logger was never called");
            // AND every nested call got fmi3Error, each logged once by its name
            assert!(
                statuses.iter().all(|&s| s == fmi3Error),
                "{path}, nested {function}: {statuses:?}"
            );
            assert!(hostile.refusals(function) >= 1, "{path}, nested {function}");
            // AND a call from inside the refusal's own log line stopped the recursion
            assert!(hostile.max_depth.load(Ordering::SeqCst) <= 2, "{path}");
            // AND the instance is intact: it resets, and it is freed once
            assert_eq!(
                unsafe { (FMU.reset)(c) },
                fmi3OK,
                "{path}, nested {function}"
            );
            unsafe { (FMU.free_instance)(c) };
        }
    }
}

#[test]
fn a_nested_call_during_the_trace_of_free_instance_is_refused_and_the_free_completes() {
    for (function, nested) in NESTED {
        let hostile = Hostile::new();
        let c = hostile.instantiate(true);
        hostile.while_armed(nested, || unsafe { (FMU.free_instance)(c) });
        assert!(hostile.refusals(function) >= 1, "nested {function}");
        let statuses = hostile.statuses.lock().unwrap().clone();
        assert!(statuses.iter().all(|&s| s == fmi3Error), "{statuses:?}");
        // The instance is gone: any call is refused without a log line (no logger left),
        // and a second free does nothing (valgrind: no read of the freed memory).
        let logged = hostile.messages.lock().unwrap().len();
        assert_eq!(unsafe { (FMU.reset)(c) }, fmi3Error);
        unsafe { (FMU.free_instance)(c) };
        assert_eq!(hostile.messages.lock().unwrap().len(), logged);
    }
}

#[test]
fn calls_on_a_freed_instance_are_refused_and_a_new_instance_is_unaffected() {
    let hostile = Hostile::new();
    let old = hostile.instantiate(false);
    unsafe { (FMU.free_instance)(old) };
    unsafe { (FMU.free_instance)(old) };
    assert_eq!(enter_init(old), fmi3Error);
    assert_eq!(exit_init(old), fmi3Error);
    assert_eq!(step(old, 0.0, 0.1), fmi3Error);
    // A new instance (possibly at the same address) works normally.
    let fresh = hostile.instantiate(false);
    assert_eq!(enter_init(fresh), fmi3OK);
    assert_eq!(exit_init(fresh), fmi3OK);
    unsafe { (FMU.free_instance)(fresh) };
}

#[test]
fn the_intermediate_update_callback_is_never_called() {
    // GIVEN a master that passes an intermediateUpdate callback which would re-enter
    let hostile = Hostile::new();
    let c = hostile.instantiate(true);
    let r0 = [0.0, 5.0, 0.0];
    let vr0 = vr("r0_nue");
    assert_eq!(
        unsafe { (FMU.set_float64)(c, &vr0, 1, r0.as_ptr(), 3) },
        fmi3OK
    );
    assert_eq!(enter_init(c), fmi3OK);
    assert_eq!(exit_init(c), fmi3OK);
    // WHEN steps complete, one returns early at touchdown, and later ones follow
    let mut t = 0.0;
    for _ in 0..5 {
        assert_eq!(step(c, t, 0.1), fmi3OK);
        t += 0.1;
    }
    assert_eq!(step(c, t, 10.0), fmi3OK, "{:?}", hostile.messages);
    step(c, t, 0.1);
    // THEN the callback never ran
    assert_eq!(hostile.intermediate_updates.load(Ordering::SeqCst), 0);
    unsafe { (FMU.free_instance)(c) };
}
