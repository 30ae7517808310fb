//! The heap one LanderNav instance holds, measured with a counting global allocator while
//! this test binary drives its own exported C functions. The latency history is sized by the
//! longest latency in use, not by its bound `max_latency_steps`. One test in this binary, so
//! that no other test allocates at the same time.
use fmi_testkit::fmi2::*;
use fmi_testkit::{fmi2_functions, CountingAllocator, Fmi2Functions, HeapUse, Instance};
use fmu_nav::LanderNav;

#[global_allocator]
static ALLOCATOR: CountingAllocator = CountingAllocator::new();

static FUNCTIONS: Fmi2Functions = fmi2_functions!(fmu_nav);

const LIMIT_BYTES: isize = 64 * 1024;
/// The 14 navigation values of one communication point.
const SAMPLE_BYTES: isize = 14 * 8;

fn vr(name: &str) -> u32 {
    fmi2_export::variables::<LanderNav>()
        .iter()
        .find(|v| v.name() == name)
        .unwrap_or_else(|| panic!("no variable {name}"))
        .value_reference
}

/// The heap of an instance with `max_latency_steps` = `bound` and the velocity `latency`
/// steps late, flown 300 steps.
fn heap(bound: i32, latency: i32) -> HeapUse {
    let guid = fmi2_export::guid::<LanderNav>();
    let reals = |causality| -> Vec<u32> {
        fmi2_export::variables::<LanderNav>()
            .iter()
            .filter(|v| v.causality == causality && v.real(&LanderNav::default()).is_some())
            .map(|v| v.value_reference)
            .collect()
    };
    let (inputs, outputs) = (
        reals(fmi2_export::Causality::Input),
        reals(fmi2_export::Causality::Output),
    );
    ALLOCATOR.measure(
        || Instance::instantiate(&FUNCTIONS, "heap", &guid),
        |nav| {
            nav.enter_init();
            assert_eq!(nav.set_integer(vr("max_latency_steps"), bound), fmi2OK);
            assert_eq!(nav.set_integer(vr("v_nue_latency"), latency), fmi2OK);
            assert_eq!(nav.set_real(vr("r_nue_noise_sigma"), 0.5), fmi2OK);
            assert_eq!(nav.exit_initialization_mode(), fmi2OK);
            for k in 0..300 {
                let truth: Vec<f64> = (0..inputs.len()).map(|i| (i + k) as f64).collect();
                assert_eq!(nav.set_reals(&inputs, &truth), fmi2OK);
                assert_eq!(nav.get_reals(&outputs).0, fmi2OK);
                assert_eq!(nav.do_step(k as f64 * 0.01, 0.01), fmi2OK);
            }
        },
    )
}

#[test]
fn an_instance_holds_its_latency_history_and_frees_it_all() {
    heap(0, 0);
    // No latency in use: small, however large the bound.
    for bound in [0, 10_000] {
        let use_ = heap(bound, 0);
        println!("LanderNav, bound {bound}, no latency: {use_:?}");
        assert!(use_.held > 0, "the counter must see the instance");
        assert!(use_.peak < LIMIT_BYTES, "{} bytes at peak", use_.peak);
        assert_eq!(use_.after, 0, "fmi2FreeInstance left {} bytes", use_.after);
    }
    // 200 steps of latency: the history of 200 samples, and not much more.
    let small = heap(10_000, 0);
    let late = heap(10_000, 200);
    println!("LanderNav, latency 200: {late:?}");
    let extra = late.held - small.held;
    assert!(
        (200 * SAMPLE_BYTES..2 * 200 * SAMPLE_BYTES).contains(&extra),
        "{extra} bytes for 200 samples"
    );
    assert_eq!(late.after, 0);
}
