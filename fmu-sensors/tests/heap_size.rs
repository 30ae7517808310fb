//! The heap one LanderSensors instance holds, measured with a counting global allocator while
//! this test binary drives its own exported C functions: instantiate, initialize, step with a
//! true state set and every measurement read. We bound it at 64 KiB. One test in this binary,
//! so that no other test allocates at the same time.
use fmi_testkit::fmi2::*;
use fmi_testkit::{fmi2_functions, CountingAllocator, Fmi2Functions, Instance};
use fmu_sensors::LanderSensors;

#[global_allocator]
static ALLOCATOR: CountingAllocator = CountingAllocator::new();

static FUNCTIONS: Fmi2Functions = fmi2_functions!(fmu_sensors);

const LIMIT_BYTES: isize = 64 * 1024;

#[test]
fn one_instance_holds_less_than_64_kib_of_heap_and_frees_it_all() {
    let guid = fmi2_export::guid::<LanderSensors>();
    let variables = fmi2_export::variables::<LanderSensors>();
    let of = |causality, real: bool| -> Vec<u32> {
        variables
            .iter()
            .filter(|v| {
                v.causality == causality && v.real(&LanderSensors::default()).is_some() == real
            })
            .map(|v| v.value_reference)
            .collect()
    };
    let inputs = of(fmi2_export::Causality::Input, true);
    let (outputs, flags) = (
        of(fmi2_export::Causality::Output, true),
        of(fmi2_export::Causality::Output, false),
    );
    assert_eq!((inputs.len(), flags.len()), (16, 4));
    for round in 0..2 {
        let heap = ALLOCATOR.measure(
            || Instance::instantiate(&FUNCTIONS, "heap", &guid),
            |sensors| {
                assert_eq!(sensors.initialize(), fmi2OK);
                for k in 0..200 {
                    let t = k as f64 * 0.01;
                    // At 800 m, sinking at 1 m/s, upright, hovering (specific force = g up).
                    let mut truth = [0.0; 16];
                    truth[1] = 800.0 - t;
                    truth[4] = -1.0;
                    truth[6] = 1.0;
                    truth[14] = 1.62;
                    assert_eq!(sensors.set_reals(&inputs, &truth), fmi2OK);
                    assert_eq!(sensors.get_reals(&outputs).0, fmi2OK);
                    assert!(flags.iter().all(|&vr| sensors.get_boolean(vr)));
                    assert_eq!(sensors.do_step(t, 0.01), fmi2OK);
                }
            },
        );
        println!("LanderSensors instance heap (round {round}): {heap:?}");
        assert!(heap.held > 0, "the counter must see the instance");
        assert!(heap.peak < LIMIT_BYTES, "{} bytes at peak", heap.peak);
        if round == 1 {
            assert_eq!(heap.after, 0, "fmi2FreeInstance left {} bytes", heap.after);
        }
    }
}
