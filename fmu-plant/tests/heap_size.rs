//! The heap one LanderPlant instance holds, measured with a counting global allocator while
//! this test binary drives its own exported C functions: instantiate, initialize, step,
//! read outputs. We bound it at 64 KiB. One test in this binary, so that no other test
//! allocates at the same time.
use fmi_testkit::fmi2::*;
use fmi_testkit::{fmi2_functions, CountingAllocator, Fmi2Functions, Instance};

#[global_allocator]
static ALLOCATOR: CountingAllocator = CountingAllocator::new();

static FUNCTIONS: Fmi2Functions = fmi2_functions!(fmu_plant);

const LIMIT_BYTES: isize = 64 * 1024;

#[test]
fn one_instance_holds_less_than_64_kib_of_heap_and_frees_it_all() {
    use fmu_plant::LanderPlant;
    let guid = fmi2_export::guid::<LanderPlant>();
    let reals = |causality| -> Vec<u32> {
        fmi2_export::variables::<LanderPlant>()
            .iter()
            .filter(|v| v.causality == causality && v.real(&LanderPlant::default()).is_some())
            .map(|v| v.value_reference)
            .collect()
    };
    let (inputs, outputs) = (
        reals(fmi2_export::Causality::Input),
        reals(fmi2_export::Causality::Output),
    );
    assert_eq!(inputs.len(), 12);
    for round in 0..2 {
        let heap = ALLOCATOR.measure(
            || Instance::instantiate(&FUNCTIONS, "heap", &guid),
            |plant| {
                assert_eq!(plant.initialize(), fmi2OK);
                for k in 0..200 {
                    let t = k as f64 * 0.01;
                    // Thrust, torque and the eight RCS duties (ignored by the default torque model).
                    let commands = [
                        1300.0, 1.0, -2.0, 0.5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0,
                    ];
                    assert_eq!(plant.set_reals(&inputs, &commands), fmi2OK);
                    assert_eq!(plant.get_reals(&outputs).0, fmi2OK);
                    assert_eq!(plant.do_step(t, 0.01), fmi2OK);
                }
            },
        );
        println!("LanderPlant instance heap (round {round}): {heap:?}");
        assert!(heap.held > 0, "the counter must see the instance");
        assert!(heap.peak < LIMIT_BYTES, "{} bytes at peak", heap.peak);
        if round == 1 {
            assert_eq!(heap.after, 0, "fmi2FreeInstance left {} bytes", heap.after);
        }
    }
}
