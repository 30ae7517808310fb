//! The heap one LanderFilter instance holds, measured with a counting global allocator while
//! this test binary drives its own exported C functions: instantiate, initialize, step with
//! every measurement valid and every output read. We bound it at 64 KiB. One test in this
//! binary, so that no other test allocates at the same time.
use fmi_testkit::fmi2::*;
use fmi_testkit::{fmi2_functions, CountingAllocator, Fmi2Functions, Instance};
use fmu_filter::LanderFilter;

#[global_allocator]
static ALLOCATOR: CountingAllocator = CountingAllocator::new();

static FUNCTIONS: Fmi2Functions = fmi2_functions!(fmu_filter);

const LIMIT_BYTES: isize = 64 * 1024;

fn vr(name: &str) -> u32 {
    fmi2_export::variables::<LanderFilter>()
        .iter()
        .find(|v| v.name() == name)
        .unwrap_or_else(|| panic!("no variable {name}"))
        .value_reference
}

#[test]
fn one_instance_holds_less_than_64_kib_of_heap_and_frees_it_all() {
    let guid = fmi2_export::guid::<LanderFilter>();
    let reals = |causality| -> Vec<u32> {
        fmi2_export::variables::<LanderFilter>()
            .iter()
            .filter(|v| v.causality == causality && v.real(&LanderFilter::default()).is_some())
            .map(|v| v.value_reference)
            .collect()
    };
    let (inputs, outputs) = (
        reals(fmi2_export::Causality::Input),
        reals(fmi2_export::Causality::Output),
    );
    assert_eq!(inputs.len(), 10);
    let flags = [
        "altimeter_valid",
        "velocimeter_valid_1",
        "velocimeter_valid_2",
        "velocimeter_valid_3",
    ]
    .map(vr);
    for round in 0..2 {
        let heap = ALLOCATOR.measure(
            || Instance::instantiate(&FUNCTIONS, "heap", &guid),
            |filter| {
                assert_eq!(filter.initialize(), fmi2OK);
                for k in 0..200 {
                    let t = k as f64 * 0.01;
                    // Hovering upright at 800 m: g on the accelerometer, the altimeter's range,
                    // no line-of-sight velocity.
                    let mut meas = [0.0; 10];
                    meas[1] = 1.62;
                    meas[6] = 800.0;
                    assert_eq!(filter.set_reals(&inputs, &meas), fmi2OK);
                    for &flag in &flags {
                        assert_eq!(filter.set_boolean(flag, true), fmi2OK);
                    }
                    assert_eq!(filter.get_reals(&outputs).0, fmi2OK);
                    assert_eq!(filter.do_step(t, 0.01), fmi2OK);
                }
                assert_eq!(filter.get_integer(vr("velocimeter_dof")), 3);
            },
        );
        println!("LanderFilter instance heap (round {round}): {heap:?}");
        assert!(heap.held > 0, "the counter must see the instance");
        assert!(heap.peak < LIMIT_BYTES, "{} bytes at peak", heap.peak);
        if round == 1 {
            assert_eq!(heap.after, 0, "fmi2FreeInstance left {} bytes", heap.after);
        }
    }
}
