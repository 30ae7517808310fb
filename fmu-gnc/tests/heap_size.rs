//! The heap one LanderGnc instance holds, measured with a counting global allocator while
//! this test binary drives its own exported C functions: instantiate, initialize, step,
//! read outputs. Issue 7 bounds it at 64 KiB. One test in this binary, so that no other test
//! allocates at the same time.
#![allow(unsafe_code)]

use fmi2_export::ffi::*;
use fmu_gnc as fmu;
use std::alloc::{GlobalAlloc, Layout, System};
use std::ffi::{c_void, CString};
use std::sync::atomic::{AtomicIsize, Ordering};

struct Counting;

static LIVE_BYTES: AtomicIsize = AtomicIsize::new(0);
static PEAK_BYTES: AtomicIsize = AtomicIsize::new(0);

// SAFETY: forwards to the system allocator and only counts.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            let live = LIVE_BYTES.fetch_add(layout.size() as isize, Ordering::SeqCst)
                + layout.size() as isize;
            PEAK_BYTES.fetch_max(live, Ordering::SeqCst);
        }
        p
    }
    unsafe fn dealloc(&self, p: *mut u8, layout: Layout) {
        unsafe { System.dealloc(p, layout) };
        LIVE_BYTES.fetch_sub(layout.size() as isize, Ordering::SeqCst);
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

const LIMIT_BYTES: isize = 64 * 1024;

/// The layer always calls the logger with "%s" and one string; a non-variadic callee with
/// those arguments reads them where a variadic call puts them (x86-64 and AArch64 Linux).
extern "C" fn quiet(
    _: fmi2ComponentEnvironment,
    _: fmi2String,
    _: fmi2Status,
    _: fmi2String,
    _: fmi2String,
    _: fmi2String,
) {
}

type Fixed = extern "C" fn(
    fmi2ComponentEnvironment,
    fmi2String,
    fmi2Status,
    fmi2String,
    fmi2String,
    fmi2String,
);

#[test]
fn one_instance_holds_less_than_64_kib_of_heap_and_frees_it_all() {
    let guid = CString::new(fmi2_export::guid::<fmu::LanderGnc>()).unwrap();
    let inputs: Vec<u32> = fmi2_export::variables::<fmu::LanderGnc>()
        .iter()
        .filter(|v| v.causality == fmi2_export::Causality::Input)
        .map(|v| v.value_reference)
        .collect();
    assert_eq!(inputs.len(), 14);
    let outputs: Vec<u32> = fmi2_export::variables::<fmu::LanderGnc>()
        .iter()
        .filter(|v| v.causality == fmi2_export::Causality::Output)
        .filter(|v| matches!(v.access, fmi2_export::Access::Real { .. }))
        .map(|v| v.value_reference)
        .collect();
    let mut values = vec![0.0; outputs.len()];
    let functions = fmi2CallbackFunctions {
        // SAFETY: see `quiet`.
        logger: unsafe { std::mem::transmute::<Fixed, fmi2CallbackLogger>(quiet) },
        allocateMemory: None,
        freeMemory: None,
        stepFinished: None,
        componentEnvironment: std::ptr::null_mut::<c_void>(),
    };
    // Twice: the first time also counts what the process sets up once (the test harness's
    // output capture, the standard library's thread data), which is not the instance's.
    for round in 0..2 {
        let before = LIVE_BYTES.load(Ordering::SeqCst);
        PEAK_BYTES.store(before, Ordering::SeqCst);
        // SAFETY: valid arguments throughout, as a master passes them.
        let held = unsafe {
            let c = fmu::fmi2Instantiate(
                c"heap".as_ptr(),
                fmi2CoSimulation,
                guid.as_ptr(),
                c"file:///tmp".as_ptr(),
                &functions,
                fmi2False,
                fmi2False,
            );
            assert!(!c.is_null());
            assert_eq!(
                fmu::fmi2SetupExperiment(c, fmi2False, 0.0, 0.0, fmi2False, 0.0),
                fmi2Status::fmi2OK
            );
            assert_eq!(fmu::fmi2EnterInitializationMode(c), fmi2Status::fmi2OK);
            assert_eq!(fmu::fmi2ExitInitializationMode(c), fmi2Status::fmi2OK);
            for k in 0..200 {
                let t = k as f64 * 0.01;
                // A lander at 800 m, slowly sinking, upright, at rest otherwise.
                let navigation = [
                    0.0,
                    800.0 - t,
                    0.0,
                    0.0,
                    -1.0,
                    0.0,
                    1.0,
                    0.0,
                    0.0,
                    0.0,
                    0.0,
                    0.0,
                    0.0,
                    900.0,
                ];
                assert_eq!(
                    fmu::fmi2SetReal(c, inputs.as_ptr(), inputs.len(), navigation.as_ptr()),
                    fmi2Status::fmi2OK
                );
                assert_eq!(
                    fmu::fmi2GetReal(c, outputs.as_ptr(), outputs.len(), values.as_mut_ptr()),
                    fmi2Status::fmi2OK
                );
                assert_eq!(fmu::fmi2DoStep(c, t, 0.01, fmi2True), fmi2Status::fmi2OK);
            }
            let held = LIVE_BYTES.load(Ordering::SeqCst) - before;
            fmu::fmi2FreeInstance(c);
            held
        };
        let peak = PEAK_BYTES.load(Ordering::SeqCst) - before;
        let after = LIVE_BYTES.load(Ordering::SeqCst) - before;
        println!("LanderGnc instance heap (round {round}): {held} bytes held while stepping, {peak} bytes at peak, {after} after free");
        assert!(held > 0, "the counter must see the instance");
        assert!(peak < LIMIT_BYTES, "{peak} bytes at peak");
        if round == 1 {
            assert_eq!(after, 0, "fmi2FreeInstance left {after} bytes");
        }
    }
}
