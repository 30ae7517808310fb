//! One co-simulation step through the C ABI, as a master does it: fmi2SetReal of the 14
//! navigation inputs, fmi2GetReal of thrust and torque (direct feedthrough: this evaluates
//! the controller), fmi2DoStep (commits the sample). Measured in the descent phase, so every
//! tenth step re-solves the polynomial guidance; the FMU state is rewound (untimed) every
//! 100 steps to stay there.
#![allow(unsafe_code)]
// std's transcendental functions here are outside the model.
#![allow(clippy::disallowed_methods)]

use criterion::{criterion_group, criterion_main, Criterion};
use fmi_testkit::fmi2::*;
use fmu_gnc as fmu;
use std::ffi::CString;
use std::time::{Duration, Instant};

const INPUTS: [u32; 14] = [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14];
const COMMANDS: [u32; 4] = [100, 101, 102, 103];
const H: f64 = 0.01;

fn navigation(k: usize) -> [f64; 14] {
    let s = k as f64 * H;
    let half = 0.05 * (0.7 * s).sin();
    [
        0.3,
        800.0 - 2.0 * s,
        -0.2,
        0.01,
        -2.0,
        0.02,
        half.cos(),
        0.2 * half.sin(),
        0.5 * half.sin(),
        0.84 * half.sin(),
        0.01,
        -0.02,
        0.005,
        880.0,
    ]
}

fn bench_do_step(c: &mut Criterion) {
    // Logging is off: only warnings and errors would reach it, and a bench has none.
    let logger = Box::<fmi_testkit::TestLogger>::default();
    let functions = logger.callbacks();
    let guid = CString::new(fmi2_export::guid::<fmu::LanderGnc>()).unwrap();
    let inst = unsafe {
        fmu::fmi2Instantiate(
            c"bench".as_ptr(),
            fmi2CoSimulation,
            guid.as_ptr(),
            c"file:///nowhere".as_ptr(),
            &functions,
            fmi2False,
            fmi2False,
        )
    };
    assert!(!inst.is_null());
    let mut commands = [0.0; 4];
    let start_k = 1300; // t = 13 s: in the descent
    let mut state: fmi2FMUstate = std::ptr::null_mut();
    unsafe {
        fmu::fmi2SetupExperiment(inst, fmi2False, 0.0, 0.0, fmi2False, 0.0);
        fmu::fmi2EnterInitializationMode(inst);
        assert_eq!(fmu::fmi2ExitInitializationMode(inst), fmi2OK);
        for k in 0..start_k {
            fmu::fmi2SetReal(inst, INPUTS.as_ptr(), 14, navigation(k).as_ptr());
            fmu::fmi2DoStep(inst, k as f64 * H, H, fmi2True);
        }
        assert_eq!(fmu::fmi2GetFMUstate(inst, &mut state), fmi2OK);
    }
    let step = |k: usize, commands: &mut [f64; 4]| unsafe {
        fmu::fmi2SetReal(inst, INPUTS.as_ptr(), 14, navigation(k).as_ptr());
        fmu::fmi2GetReal(inst, COMMANDS.as_ptr(), 4, commands.as_mut_ptr());
        let status = fmu::fmi2DoStep(inst, k as f64 * H, H, fmi2True);
        debug_assert_eq!(status, fmi2OK);
    };

    c.bench_function(
        "fmi2 set 14 + get 4 + DoStep (descent, re-solve every 10th)",
        |b| {
            b.iter_custom(|iters| {
                let mut timed = Duration::ZERO;
                let mut done = 0;
                while done < iters {
                    unsafe { fmu::fmi2SetFMUstate(inst, state) };
                    let chunk = (iters - done).min(100) as usize;
                    let t0 = Instant::now();
                    for k in start_k..start_k + chunk {
                        step(k, &mut commands);
                    }
                    timed += t0.elapsed();
                    done += chunk as u64;
                }
                std::hint::black_box(&commands);
                timed
            })
        },
    );
    unsafe {
        fmu::fmi2FreeFMUstate(inst, &mut state);
        fmu::fmi2FreeInstance(inst);
    }
}

/// The model's own share: one controller evaluation, no FMI layer (a master's step evaluates
/// it once: for the get; do_step commits that same sample).
fn bench_gnc_sample(c: &mut Criterion) {
    use fmu::controller::{gnc_sample, NavigationInputs};
    use fmu::guidance::sequencer::{GuidanceState, Phase};
    let design = fmu::params::GncParameters::default().design().unwrap();
    let profile = fmu::attitude::profile::PhiProfile::default();
    let n = navigation(1300);
    let nav = NavigationInputs {
        r_nue_m: [n[0], n[1], n[2]],
        v_nue_mps: [n[3], n[4], n[5]],
        q_body_to_nue: [n[6], n[7], n[8], n[9]],
        omega_body_radps: [n[10], n[11], n[12]],
        mass_kg: n[13],
    };
    let state = GuidanceState {
        phase: Phase::Descent,
        ..GuidanceState::initial(1.62)
    };
    c.bench_function("gnc_sample with a descent re-solve (pure)", |b| {
        b.iter(|| {
            gnc_sample(
                &design,
                0.0,
                std::hint::black_box(&state),
                &profile,
                &nav,
                13.0,
            )
        })
    });
}

criterion_group!(benches, bench_do_step, bench_gnc_sample);
criterion_main!(benches);
