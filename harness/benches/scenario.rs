//! One full paper scenario (172 s, 17,200 communication steps of both FMUs through the C ABI,
//! all outputs recorded) per law. Target: under 20 ms.
use cosim::master::{Simulation, Trajectory};
use criterion::{criterion_group, criterion_main, Criterion};
use lander::laws::{Law, Laws};
use lander::scenarios;
use std::path::PathBuf;

fn fmu_dir() -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../target/fmu");
    assert!(
        dir.join("LanderGnc.fmu").is_file(),
        "run `cargo xtask fmus` first"
    );
    dir
}

fn paper_scenario(c: &mut Criterion) {
    let mut group = c.benchmark_group("paper_scenario");
    group.sample_size(20);
    for law in [Law::COUPLED, Law::DECOUPLED] {
        let mut system = scenarios::load("paper").unwrap();
        let laws = Laws::of_instance(&system, "gnc", &fmu_dir()).unwrap();
        system.set_parameter("gnc", "control_law", laws.parameter(law).unwrap());
        let mut simulation = Simulation::new(system.clone(), &fmu_dir()).unwrap();
        group.bench_function(format!("{}_all_outputs", law.name()), |b| {
            b.iter(|| {
                let mut trajectory = Trajectory {
                    names: simulation.column_names().to_vec(),
                    ..Default::default()
                };
                simulation.run(&mut trajectory).unwrap();
                trajectory.len()
            })
        });
        // The columns a Monte Carlo run keeps: the cost of the co-simulation itself.
        system.record = Some(vec!["plant.r_nue".into(), "gnc.phi_b".into()]);
        let mut lean = Simulation::new(system, &fmu_dir()).unwrap();
        group.bench_function(format!("{}_few_columns", law.name()), |b| {
            b.iter(|| {
                let mut trajectory = Trajectory::default();
                lean.run(&mut trajectory).unwrap();
                trajectory.len()
            })
        });
    }
    group.finish();
}

criterion_group!(benches, paper_scenario);
criterion_main!(benches);
