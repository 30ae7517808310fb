//! LanderGnc through its FMI 3.0 C functions: Co-Simulation works with array inputs and
//! outputs; Model Exchange, which it does not offer, is refused with the reason.
#![allow(unsafe_code)]

use fmi3_export::ffi::*;
use fmu_gnc as fmu;
use std::ffi::{c_void, CStr, CString};
use std::sync::Mutex;

#[derive(Default)]
struct Sink(Mutex<Vec<String>>);

unsafe extern "C" fn record(
    environment: fmi3InstanceEnvironment,
    _status: fmi3Status,
    _category: fmi3String,
    message: fmi3String,
) {
    // SAFETY: the environment is our Sink, the message a NUL-terminated string.
    let sink = unsafe { &*(environment as *const Sink) };
    let text = unsafe { CStr::from_ptr(message) }
        .to_string_lossy()
        .into_owned();
    sink.0.lock().unwrap().push(text);
}

fn token() -> CString {
    CString::new(fmi3_export::instantiation_token::<fmu::LanderGnc>()).unwrap()
}

#[test]
fn model_exchange_is_refused_with_the_reason() {
    let sink = Box::<Sink>::default();
    let token = token();
    // SAFETY: valid strings; the sink outlives the call.
    let c = unsafe {
        fmu::fmi3InstantiateModelExchange(
            c"gnc".as_ptr(),
            token.as_ptr(),
            std::ptr::null(),
            false,
            false,
            &*sink as *const Sink as *mut c_void,
            Some(record),
        )
    };
    assert!(c.is_null());
    assert_eq!(
        sink.0.lock().unwrap().as_slice(),
        ["fmi3InstantiateModelExchange: LanderGnc offers Co-Simulation only, not Model Exchange"]
    );
}

#[test]
fn co_simulation_steps_and_reads_the_thrust_command() {
    let sink = Box::<Sink>::default();
    let token = token();
    // SAFETY: valid strings and out-parameters; the instance is freed at the end.
    unsafe {
        let c = fmu::fmi3InstantiateCoSimulation(
            c"gnc".as_ptr(),
            token.as_ptr(),
            std::ptr::null(),
            false,
            false,
            false,
            false,
            std::ptr::null(),
            0,
            &*sink as *const Sink as *mut c_void,
            Some(record),
            None,
        );
        assert!(!c.is_null(), "{:?}", sink.0.lock().unwrap());
        assert_eq!(
            fmu::fmi3EnterInitializationMode(c, false, 0.0, 0.0, false, 0.0),
            fmi3OK
        );
        assert_eq!(fmu::fmi3ExitInitializationMode(c), fmi3OK);
        let (mut event, mut terminate, mut early, mut last) = (false, false, false, 0.0);
        assert_eq!(
            fmu::fmi3DoStep(
                c,
                0.0,
                0.01,
                true,
                &mut event,
                &mut terminate,
                &mut early,
                &mut last
            ),
            fmi3OK
        );
        assert_eq!(last, 0.01);
        let mut n = usize::MAX;
        assert_eq!(fmu::fmi3GetNumberOfContinuousStates(c, &mut n), fmi3OK);
        assert_eq!(
            n, 0,
            "a Co-Simulation-only model has no continuous states to offer"
        );
        fmu::fmi3FreeInstance(c);
    }
}
