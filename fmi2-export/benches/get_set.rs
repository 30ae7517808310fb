//! The layer's own cost, with a model that does nothing: fmi2GetReal and fmi2SetReal of 14
//! values (the size of the landers' navigation exchange) through the exported C symbols.
//! What is measured here is lookup, checks and bookkeeping, never the model.
#![allow(unsafe_code)]

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use fmi2_export::ffi::*;
use fmi2_export::{decl, Declaration};
use serde::{Deserialize, Serialize};
use std::ffi::CString;

/// 14 inputs `u[i]` and 14 outputs `y[i] = u[i]`, value references 1..=14 and 101..=114.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
struct Exchange {
    u: [f64; 14],
    y: [f64; 14],
}

fmi_testkit::test_model!(
    Exchange,
    DECLARATIONS,
    "14 inputs copied to 14 outputs",
    calculate = |m| m.y = m.u
);

fmi2_export::export_fmi2!(Exchange);

/// Two vectors of 14: FMI 2.0 gives them the scalars `u[1]`.. (vr 1..=14) and `y[1]`..
/// (vr 101..=114).
static DECLARATIONS: [Declaration<Exchange>; 2] = [
    decl!(1, input u[14]: u, "1", "copied to y"),
    decl!(101, output y[14]: y, "1", "copy of u"),
];

fn get_set(c: &mut Criterion) {
    assert_eq!(fmi2_export::check_table::<Exchange>(), Ok(()));
    let logger = Box::<fmi_testkit::TestLogger>::default();
    let functions = logger.callbacks();
    let guid = CString::new(fmi2_export::guid::<Exchange>()).unwrap();
    let inputs: Vec<u32> = (1..=14).collect();
    let outputs: Vec<u32> = (101..=114).collect();
    let values: Vec<f64> = (0..14).map(|i| 0.5 + i as f64).collect();
    let mut read = [0.0; 14];
    unsafe {
        let inst = fmi2Instantiate(
            c"bench".as_ptr(),
            fmi2CoSimulation,
            guid.as_ptr(),
            std::ptr::null(),
            &functions,
            fmi2False,
            fmi2False,
        );
        assert!(!inst.is_null());
        fmi2SetupExperiment(inst, fmi2False, 0.0, 0.0, fmi2False, 0.0);
        fmi2EnterInitializationMode(inst);
        assert_eq!(fmi2ExitInitializationMode(inst), fmi2OK);
        assert_eq!(
            fmi2SetReal(inst, inputs.as_ptr(), 14, values.as_ptr()),
            fmi2OK
        );
        assert_eq!(
            fmi2GetReal(inst, outputs.as_ptr(), 14, read.as_mut_ptr()),
            fmi2OK
        );
        assert_eq!(read.as_slice(), values.as_slice(), "y = u");

        // Nothing changed since the last get: no calculate_values, lookup and copy only.
        c.bench_function("fmi2GetReal of 14 outputs", |b| {
            b.iter(|| {
                let status = fmi2GetReal(inst, black_box(outputs.as_ptr()), 14, read.as_mut_ptr());
                black_box((status, read[13]))
            })
        });
        c.bench_function("fmi2SetReal of 14 inputs", |b| {
            b.iter(|| {
                fmi2SetReal(
                    inst,
                    black_box(inputs.as_ptr()),
                    14,
                    black_box(values.as_ptr()),
                )
            })
        });
        fmi2FreeInstance(inst);
    }
}

criterion_group!(benches, get_set);
criterion_main!(benches);
