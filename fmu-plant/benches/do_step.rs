//! One `fmi2DoStep` of 0.01 s (the default sub-step, so one RK4 step and its event checks)
//! through the exported C functions, and a full master cycle around it.
//! Target: under 2 us median.
#![allow(unsafe_code)]

#[path = "../tests/common/mod.rs"]
mod common;

use common::{navigation_vrs, vr, Plant};
use criterion::{black_box, criterion_group, criterion_main, Criterion};
use fmi_testkit::fmi2::*;

/// A hovering plant whose state does not drift away over millions of steps: thrust exactly
/// m g with the mass flow switched off, so every iteration does the same work.
fn hovering(translation_model: i32) -> Plant {
    let fmu = Plant::new();
    fmu.enter_init();
    fmu.set("isp", 1e15);
    fmu.set_integer("translation_model", translation_model);
    assert_eq!(fmu.exit_init(), fmi2OK);
    fmu.set("thrust_cmd", 900.0 * 1.62);
    fmu
}

fn do_step(c: &mut Criterion) {
    for (label, model) in [("flat", 1), ("spherical", 2)] {
        let fmu = hovering(model);
        let mut t = 0.0;
        c.bench_function(&format!("fmi2DoStep 0.01 s ({label})"), |b| {
            b.iter(|| {
                let status = fmu.step(black_box(t), black_box(0.01));
                t += 0.01;
                status
            })
        });
    }

    // What a master does each cycle: set the 4 inputs, step, read the 14 navigation outputs.
    let fmu = hovering(1);
    let inputs = [
        vr("thrust_cmd"),
        vr("torque_cmd_body[1]"),
        vr("torque_cmd_body[2]"),
        vr("torque_cmd_body[3]"),
    ];
    let values = [900.0 * 1.62, 0.0, 0.0, 0.0];
    let outputs = navigation_vrs();
    let mut read = vec![0.0; outputs.len()];
    let mut t = 0.0;
    c.bench_function(
        "set 4 inputs + fmi2DoStep 0.01 s + get 14 outputs (flat)",
        |b| {
            b.iter(|| unsafe {
                fmu_plant::fmi2SetReal(
                    fmu.component(),
                    inputs.as_ptr(),
                    inputs.len(),
                    values.as_ptr(),
                );
                let status = fmu.step(t, 0.01);
                fmu_plant::fmi2GetReal(
                    fmu.component(),
                    outputs.as_ptr(),
                    outputs.len(),
                    read.as_mut_ptr(),
                );
                t += 0.01;
                black_box((status, read[1]))
            })
        },
    );
}

criterion_group!(benches, do_step);
criterion_main!(benches);
