//! A master's cycle on LanderNav through the exported C functions: set the 14 true signals,
//! read the 14 estimates, step 0.01 s; with every error off (the default) and with every
//! kind of error on.
use criterion::{black_box, criterion_group, criterion_main, Criterion};
use fmi_testkit::fmi2::*;
use fmi_testkit::{fmi2_functions, Fmi2Functions, Instance};
use fmu_nav::LanderNav;

static FUNCTIONS: Fmi2Functions = fmi2_functions!(fmu_nav);

fn vr(name: &str) -> u32 {
    fmi2_export::variables::<LanderNav>()
        .iter()
        .find(|v| v.name() == name)
        .unwrap_or_else(|| panic!("no variable {name}"))
        .value_reference
}

fn instance(errors_on: bool) -> Instance {
    let fmu = Instance::instantiate(&FUNCTIONS, "nav", &fmi2_export::guid::<LanderNav>());
    fmu.enter_init();
    if errors_on {
        for (name, value) in [
            ("r_nue_noise_sigma", 0.5),
            ("r_nue_random_walk", 0.1),
            ("r_nue_quantum", 0.01),
            ("v_nue_noise_sigma", 0.05),
            ("attitude_noise_sigma", 1e-3),
            ("attitude_bias[1]", 1e-3),
            ("omega_body_random_walk", 1e-4),
            ("mass_bias", 3.0),
        ] {
            assert_eq!(fmu.set_real(vr(name), value), fmi2OK);
        }
        for (name, value) in [("max_latency_steps", 5), ("v_nue_latency", 5)] {
            assert_eq!(fmu.set_integer(vr(name), value), fmi2OK);
        }
    }
    assert_eq!(fmu.exit_initialization_mode(), fmi2OK);
    fmu
}

fn cycle(c: &mut Criterion) {
    let vrs = |suffix: &str| -> Vec<u32> {
        ["r_nue", "v_nue", "q_body_to_nue", "omega_body"]
            .iter()
            .zip([3, 3, 4, 3])
            .flat_map(|(base, n)| (1..=n).map(move |k| vr(&format!("{base}{suffix}[{k}]"))))
            .chain([vr(&format!("mass{suffix}"))])
            .collect()
    };
    let (inputs, outputs) = (vrs("_true"), vrs(""));
    let truth = [
        0.0, 800.0, 0.0, 0.0, -2.0, 0.0, 0.99, 0.0, 0.0, -0.13, 0.0, 0.01, 0.0, 900.0,
    ];
    for (label, errors_on) in [("errors off", false), ("errors on", true)] {
        let fmu = instance(errors_on);
        let mut t = 0.0;
        c.bench_function(
            &format!("set 14 + get 14 + fmi2DoStep 0.01 s ({label})"),
            |b| {
                b.iter(|| {
                    fmu.set_reals(&inputs, black_box(&truth));
                    let (_, estimate) = fmu.get_reals(&outputs);
                    let status = fmu.do_step(t, 0.01);
                    t += 0.01;
                    black_box((status, estimate[1]))
                })
            },
        );
    }
}

criterion_group!(benches, cycle);
criterion_main!(benches);
