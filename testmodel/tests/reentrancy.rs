//! A hostile master calls back into an instance from inside that instance's logger, on
//! every path that logs (call trace, informational message, warning, error, the trace of
//! fmi2FreeInstance), with every kind of function, fmi2FreeInstance and fmi2Reset
//! included. Each nested call must get fmi2Error and a log line naming it, the outer call
//! must finish normally, and nothing may touch freed memory: run this binary under valgrind
//! (see tests/robustness/README.md) to check the last part.
#![allow(unsafe_code)]

use fmi_testkit::fmi2::*;
use fmi_testkit::{fmi2_functions, Fmi2Functions};
use std::ffi::CString;
use std::ptr;
use std::sync::atomic::{AtomicBool, AtomicPtr, AtomicUsize, Ordering};
use std::sync::Mutex;

static FMU: Fmi2Functions = fmi2_functions!(fmu_testmodel);

/// A function a hostile logger calls on the instance that is logging.
type Nested = unsafe fn(fmi2Component) -> fmi2Status;

unsafe fn nested_reset(c: fmi2Component) -> fmi2Status {
    unsafe { (FMU.reset)(c) }
}
unsafe fn nested_free(c: fmi2Component) -> fmi2Status {
    unsafe { (FMU.free_instance)(c) };
    // Void: whether it was refused shows afterwards, in the instance still working.
    fmi2Error
}
unsafe fn nested_step(c: fmi2Component) -> fmi2Status {
    unsafe { (FMU.co_simulation.do_step)(c, 0.0, 0.01, fmi2True) }
}
unsafe fn nested_get(c: fmi2Component) -> fmi2Status {
    let (vr, mut x) = (5u32, 0.0);
    unsafe { (FMU.get_real)(c, &vr, 1, &mut x) }
}
unsafe fn nested_set(c: fmi2Component) -> fmi2Status {
    let (vr, u) = (4u32, 1.0);
    unsafe { (FMU.set_real)(c, &vr, 1, &u) }
}
unsafe fn nested_terminate(c: fmi2Component) -> fmi2Status {
    unsafe { (FMU.terminate)(c) }
}
unsafe fn nested_debug_logging(c: fmi2Component) -> fmi2Status {
    unsafe { (FMU.set_debug_logging)(c, fmi2False, 0, ptr::null()) }
}
unsafe fn nested_get_state(c: fmi2Component) -> fmi2Status {
    let mut state: fmi2FMUstate = ptr::null_mut();
    unsafe { (FMU.get_fmu_state)(c, &mut state) }
}
unsafe fn nested_enter_init(c: fmi2Component) -> fmi2Status {
    unsafe { (FMU.enter_initialization_mode)(c) }
}
unsafe fn nested_status(c: fmi2Component) -> fmi2Status {
    let mut status = fmi2OK;
    unsafe { (FMU.co_simulation.get_status)(c, fmi2DoStepStatus, &mut status) }
}

const NESTED: [(&str, Nested); 10] = [
    ("fmi2Reset", nested_reset),
    ("fmi2FreeInstance", nested_free),
    ("fmi2DoStep", nested_step),
    ("fmi2GetReal", nested_get),
    ("fmi2SetReal", nested_set),
    ("fmi2Terminate", nested_terminate),
    ("fmi2SetDebugLogging", nested_debug_logging),
    ("fmi2GetFMUstate", nested_get_state),
    ("fmi2EnterInitializationMode", nested_enter_init),
    ("fmi2GetStatus", nested_status),
];

/// The master's environment: the shim's sink first (repr(C)), then what the hostile
/// logger needs.
#[repr(C)]
struct Hostile {
    sink: fmi_abi::callbacks::LogSink,
    component: AtomicPtr<std::ffi::c_void>,
    nested: Mutex<Option<Nested>>,
    armed: AtomicBool,
    /// Depth of logger calls on the stack; its maximum shows whether re-entry recursed.
    depth: AtomicUsize,
    max_depth: AtomicUsize,
    statuses: Mutex<Vec<fmi2Status>>,
    messages: Mutex<Vec<(fmi2Status, String, String)>>,
}

extern "C" fn forward(
    sink: *const fmi_abi::callbacks::LogSink,
    _instance: fmi2String,
    status: fmi2Status,
    category: fmi2String,
    message: fmi2String,
) {
    // SAFETY: the environment is a live, boxed Hostile whose first field is the sink.
    let hostile = unsafe { &*(sink as *const Hostile) };
    // SAFETY: NUL-terminated or NULL, per the shim.
    let text = |s| unsafe { fmi_abi::callbacks::text(s) }.unwrap_or_default();
    hostile
        .messages
        .lock()
        .unwrap()
        .push((status, text(category), text(message)));
    let depth = hostile.depth.fetch_add(1, Ordering::SeqCst) + 1;
    hostile.max_depth.fetch_max(depth, Ordering::SeqCst);
    // The test's own bound, should the FMU let nested calls through and recurse.
    if hostile.armed.load(Ordering::SeqCst) && depth < 8 {
        let c = hostile.component.load(Ordering::SeqCst);
        let nested = *hostile.nested.lock().unwrap();
        if let Some(nested) = nested {
            // SAFETY: the component the test instantiated; the FMU must cope.
            let s = unsafe { nested(c) };
            hostile.statuses.lock().unwrap().push(s);
        }
    }
    hostile.depth.fetch_sub(1, Ordering::SeqCst);
}

impl Hostile {
    fn new() -> Box<Hostile> {
        Box::new(Hostile {
            sink: fmi_abi::callbacks::LogSink { forward },
            component: AtomicPtr::new(ptr::null_mut()),
            nested: Mutex::new(None),
            armed: AtomicBool::new(false),
            depth: AtomicUsize::new(0),
            max_depth: AtomicUsize::new(0),
            statuses: Mutex::new(Vec::new()),
            messages: Mutex::new(Vec::new()),
        })
    }

    fn instantiate(&self, logging_on: bool) -> fmi2Component {
        let callbacks = fmi_abi::callbacks::LogSink::callbacks(self);
        let name = CString::new("hostile").unwrap();
        let guid = CString::new(fmi2_export::guid::<fmu_testmodel::Oscillator>()).unwrap();
        // SAFETY: valid strings and callbacks; `self` outlives the instance.
        let c = unsafe {
            (FMU.instantiate)(
                name.as_ptr(),
                fmi2CoSimulation,
                guid.as_ptr(),
                ptr::null(),
                &callbacks,
                fmi2False,
                fmi2Boolean::from(logging_on),
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
            .filter(|(s, _, m)| {
                *s == fmi2Error && m.starts_with(function) && m.contains("has not returned")
            })
            .count()
    }
}

/// How each logging path is triggered on a fresh instance: the outer call and the status
/// it must still return with a hostile logger.
type Path = (
    &'static str,
    bool,
    fn(fmi2Component) -> fmi2Status,
    fmi2Status,
);

fn setup(c: fmi2Component) -> fmi2Status {
    unsafe { (FMU.setup_experiment)(c, fmi2False, 0.0, 0.0, fmi2False, 0.0) }
}
fn initialize(c: fmi2Component) -> fmi2Status {
    setup(c);
    unsafe { (FMU.enter_initialization_mode)(c) };
    unsafe { (FMU.exit_initialization_mode)(c) }
}
fn coarse_step(c: fmi2Component) -> fmi2Status {
    // Not armed during initialization: only the warning of the step re-enters.
    unsafe { (FMU.co_simulation.do_step)(c, 0.0, 100.0, fmi2True) }
}
fn illegal_step(c: fmi2Component) -> fmi2Status {
    // fmi2DoStep before initialization: an error.
    unsafe { (FMU.co_simulation.do_step)(c, 0.0, 0.01, fmi2True) }
}

const PATHS: [Path; 4] = [
    ("call trace", true, setup, fmi2OK),
    ("informational message", true, initialize, fmi2OK),
    ("error", false, illegal_step, fmi2Error),
    ("warning", false, coarse_step, fmi2Warning),
];

#[test]
fn every_nested_call_from_every_logging_path_is_refused_and_named() {
    for (path, logging_on, outer, expected) in PATHS {
        for (function, nested) in NESTED {
            // GIVEN an instance whose logger calls `function` on it whenever it logs
            let hostile = Hostile::new();
            let c = hostile.instantiate(logging_on);
            if path == "warning" {
                assert_eq!(initialize(c), fmi2OK);
            }
            // WHEN the outer call logs
            let status = hostile.while_armed(nested, || outer(c));
            // THEN the outer call finishes as it would have without the nesting
            assert_eq!(status, expected, "{path}, nested {function}");
            let statuses = hostile.statuses.lock().unwrap().clone();
            assert!(!statuses.is_empty(), "{path}: the logger was never called");
            // AND every nested call got fmi2Error, each logged once by its name
            assert!(
                statuses.iter().all(|&s| s == fmi2Error),
                "{path}, nested {function}: {statuses:?}"
            );
            assert!(hostile.refusals(function) >= 1, "{path}, nested {function}");
            // AND a call from inside the refusal's own log line stopped the recursion
            assert!(hostile.max_depth.load(Ordering::SeqCst) <= 2, "{path}");
            // AND the instance is intact: it resets, and it is freed once
            assert_eq!(
                unsafe { (FMU.reset)(c) },
                fmi2OK,
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
        assert!(statuses.iter().all(|&s| s == fmi2Error), "{statuses:?}");
        // The instance is gone: any call is refused without a log line (no logger left),
        // and a second free does nothing (valgrind: no read of the freed memory).
        let logged = hostile.messages.lock().unwrap().len();
        assert_eq!(unsafe { (FMU.reset)(c) }, fmi2Error);
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
    assert_eq!(setup(old), fmi2Error);
    assert_eq!(initialize(old), fmi2Error);
    // A new instance (possibly at the same address) works normally.
    let fresh = hostile.instantiate(false);
    assert_eq!(initialize(fresh), fmi2OK);
    unsafe { (FMU.free_instance)(fresh) };
}

/// Calls of the stepFinished callback (there must be none).
static STEP_FINISHED_CALLS: AtomicUsize = AtomicUsize::new(0);

/// Records the call and re-enters, as a hostile master would; must never run.
extern "C" fn step_finished(environment: fmi2ComponentEnvironment, _status: fmi2Status) {
    STEP_FINISHED_CALLS.fetch_add(1, Ordering::SeqCst);
    // SAFETY: the environment is the test's Hostile.
    let hostile = unsafe { &*(environment as *const Hostile) };
    unsafe { (FMU.reset)(hostile.component.load(Ordering::SeqCst)) };
}

#[test]
fn the_step_finished_callback_is_never_called() {
    // GIVEN a master that passes a stepFinished callback which would re-enter (the FMU
    // declares canRunAsynchronuously = false: fmi2DoStep always completes before returning)
    let hostile = Hostile::new();
    let mut callbacks = fmi_abi::callbacks::LogSink::callbacks(&*hostile);
    callbacks.stepFinished = Some(step_finished);
    let name = CString::new("hostile").unwrap();
    let guid = CString::new(fmi2_export::guid::<fmu_testmodel::Oscillator>()).unwrap();
    // SAFETY: valid strings and callbacks that outlive the instance.
    let c = unsafe {
        (FMU.instantiate)(
            name.as_ptr(),
            fmi2CoSimulation,
            guid.as_ptr(),
            ptr::null(),
            &callbacks,
            fmi2False,
            fmi2True,
        )
    };
    assert!(!c.is_null());
    hostile.component.store(c, Ordering::SeqCst);
    // WHEN steps complete, one is refused, one warns, and one asks for no synchronisation
    assert_eq!(initialize(c), fmi2OK);
    for k in 0..5 {
        let t = f64::from(k) * 0.01;
        assert_eq!(
            unsafe { (FMU.co_simulation.do_step)(c, t, 0.01, fmi2True) },
            fmi2OK
        );
    }
    assert_eq!(
        unsafe { (FMU.co_simulation.do_step)(c, 1.0, 0.01, fmi2True) },
        fmi2Error
    );
    assert_eq!(coarse_step_from(c, 0.05), fmi2Warning);
    let mut status = fmi2OK;
    unsafe { (FMU.co_simulation.get_status)(c, fmi2DoStepStatus, &mut status) };
    // THEN the callback never ran
    assert_eq!(STEP_FINISHED_CALLS.load(Ordering::SeqCst), 0);
    unsafe { (FMU.free_instance)(c) };
}

fn coarse_step_from(c: fmi2Component, t: f64) -> fmi2Status {
    unsafe { (FMU.co_simulation.do_step)(c, t, 100.0, fmi2False) }
}
