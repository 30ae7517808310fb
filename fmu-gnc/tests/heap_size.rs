//! The heap one LanderGnc instance holds, measured with a counting global allocator while
//! this test binary drives its own exported C functions: instantiate, initialize, step,
//! read outputs. We bound it at 64 KiB. One test in this binary, so that no other test
//! allocates at the same time.
use fmi_testkit::fmi2::*;
use fmi_testkit::{fmi2_functions, CountingAllocator, Fmi2Functions, Instance};

#[global_allocator]
static ALLOCATOR: CountingAllocator = CountingAllocator::new();

static FUNCTIONS: Fmi2Functions = fmi2_functions!(fmu_gnc);

const LIMIT_BYTES: isize = 64 * 1024;

#[test]
fn one_instance_holds_less_than_64_kib_of_heap_and_frees_it_all() {
    use fmu_gnc::LanderGnc;
    let guid = fmi2_export::guid::<LanderGnc>();
    let reals = |causality| -> Vec<u32> {
        fmi2_export::variables::<LanderGnc>()
            .iter()
            .filter(|v| v.causality == causality && v.real(&LanderGnc::default()).is_some())
            .map(|v| v.value_reference)
            .collect()
    };
    let (inputs, outputs) = (
        reals(fmi2_export::Causality::Input),
        reals(fmi2_export::Causality::Output),
    );
    assert_eq!(inputs.len(), 14);
    for round in 0..2 {
        let heap = ALLOCATOR.measure(
            || Instance::instantiate(&FUNCTIONS, "heap", &guid),
            |gnc| {
                assert_eq!(gnc.initialize(), fmi2OK);
                for k in 0..200 {
                    let t = k as f64 * 0.01;
                    // A lander at 800 m, slowly sinking, upright, at rest otherwise.
                    let mut navigation = [0.0; 14];
                    navigation[1] = 800.0 - t;
                    navigation[4] = -1.0;
                    navigation[6] = 1.0;
                    navigation[13] = 900.0;
                    assert_eq!(gnc.set_reals(&inputs, &navigation), fmi2OK);
                    assert_eq!(gnc.get_reals(&outputs).0, fmi2OK);
                    assert_eq!(gnc.do_step(t, 0.01), fmi2OK);
                }
            },
        );
        println!("LanderGnc instance heap (round {round}): {heap:?}");
        assert!(heap.held > 0, "the counter must see the instance");
        assert!(heap.peak < LIMIT_BYTES, "{} bytes at peak", heap.peak);
        if round == 1 {
            assert_eq!(heap.after, 0, "fmi2FreeInstance left {} bytes", heap.after);
        }
    }
}
