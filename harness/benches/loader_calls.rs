//! Cost of driving an FMU through the loader: one communication step of the Oscillator
//! (set the input, step, read two outputs) and one instance lifecycle.
#[path = "../tests/common/mod.rs"]
mod common;

use criterion::{criterion_group, criterion_main, Criterion};
use fmi_import::Fmu;
use std::hint::black_box;

fn communication_step(c: &mut Criterion) {
    let file = common::oscillator_fmu();
    let fmu = Fmu::load(&file.path).expect("load Oscillator");
    let mut instance = fmu.instantiate("bench", false).unwrap();
    instance.setup_experiment(None, 0.0, None).unwrap();
    instance.enter_initialization_mode().unwrap();
    instance.exit_initialization_mode().unwrap();
    let u = [instance.variable("u").unwrap().value_reference];
    let xv = [
        instance.variable("x").unwrap().value_reference,
        instance.variable("v").unwrap().value_reference,
    ];
    let step_s = 1e-3;
    let mut step: u64 = 0;
    let mut outputs = [0.0; 2];
    c.bench_function("oscillator: set u, do_step, get x v", |b| {
        b.iter(|| {
            let t = step as f64 * step_s;
            instance.set_real(&u, &[black_box(0.1)]).unwrap();
            instance.do_step(t, step_s).unwrap();
            instance.get_real(&xv, &mut outputs).unwrap();
            step += 1;
            black_box(outputs)
        })
    });
}

fn instance_lifecycle(c: &mut Criterion) {
    let file = common::oscillator_fmu();
    let fmu = Fmu::load(&file.path).expect("load Oscillator");
    c.bench_function("oscillator: instantiate, initialize, free", |b| {
        b.iter(|| {
            let mut instance = fmu.instantiate("lifecycle", false).unwrap();
            instance.setup_experiment(None, 0.0, None).unwrap();
            instance.enter_initialization_mode().unwrap();
            instance.exit_initialization_mode().unwrap();
            black_box(instance)
        })
    });
}

criterion_group!(benches, communication_step, instance_lifecycle);
criterion_main!(benches);
