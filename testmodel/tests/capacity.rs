//! The registry of live instances has a fixed capacity: the instantiation beyond it returns
//! NULL with a log line saying why, and works again once an instance is freed. Its own test
//! binary, so that no other test's instances count.
#![allow(unsafe_code)]

use fmi_model::registry::CAPACITY;
use fmi_testkit::fmi2::*;
use fmi_testkit::{fmi2_functions, Fmi2Functions, TestLogger};
use std::ffi::CString;
use std::ptr;

static FMU: Fmi2Functions = fmi2_functions!(fmu_testmodel);

#[test]
fn one_instance_beyond_the_capacity_is_refused_with_a_reason() {
    let logger = Box::<TestLogger>::default();
    let callbacks = logger.callbacks();
    let name = CString::new("many").unwrap();
    let guid = CString::new(fmi2_export::guid::<fmu_testmodel::Oscillator>()).unwrap();
    // SAFETY: valid strings and callbacks that outlive every instance.
    let instantiate = || unsafe {
        (FMU.instantiate)(
            name.as_ptr(),
            fmi2CoSimulation,
            guid.as_ptr(),
            ptr::null(),
            &callbacks,
            fmi2False,
            fmi2False,
        )
    };
    let mut live: Vec<fmi2Component> = (0..CAPACITY).map(|_| instantiate()).collect();
    assert!(live.iter().all(|c| !c.is_null()));
    assert!(logger.is_empty(), "{:?}", logger.messages());

    assert!(instantiate().is_null());
    assert_eq!(
        logger.messages(),
        [format!(
            "fmi2Instantiate: {CAPACITY} instances of this FMU are already live in this \
             process; free one first"
        )]
    );

    // Every instance answers, as its own: each enters initialization and reads a variable.
    let vr = 0u32;
    for &c in &live {
        let mut x = f64::NAN;
        // SAFETY: a live instance, valid pointers.
        unsafe {
            assert_eq!(
                (FMU.setup_experiment)(c, fmi2False, 0.0, 0.0, fmi2False, 0.0),
                fmi2OK
            );
            assert_eq!((FMU.enter_initialization_mode)(c), fmi2OK);
            assert_eq!((FMU.get_real)(c, &vr, 1, &mut x), fmi2OK);
        }
        assert!(x.is_finite());
    }

    // SAFETY: a live instance, freed once.
    unsafe { (FMU.free_instance)(live.swap_remove(CAPACITY / 2)) };
    let again = instantiate();
    assert!(!again.is_null());
    live.push(again);
    for c in live {
        // SAFETY: each live instance, freed once.
        unsafe { (FMU.free_instance)(c) };
    }
    assert_eq!(logger.len(), 1);
}
