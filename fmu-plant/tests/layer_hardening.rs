//! What a hostile or merely unusual master can do to the export layer, through the C ABI of
//! both FMI versions: states of the other interface, reserved header bytes, stale handles
//! whose memory the allocator has reused, an over-long step, bounds at the declared min and
//! max, extreme numbers in log lines. Each refusal leaves the instance usable.
use crate::common;

use fmi_model::Model;
use fmi_testkit::fmi2::{fmi2Error, fmi2OK};
use fmi_testkit::{Driver, Fmi2, Fmi3, Interface, Status};
use fmu_plant::LanderPlant;

static FUNCTIONS3: fmi_testkit::Fmi3Functions = fmi_testkit::fmi3_functions!(fmu_plant);

/// A driver of LanderPlant: the version's function table and token.
trait Plant: Driver {
    fn functions() -> &'static Self::Functions;
    fn token() -> String;

    fn open(interface: Interface) -> Self {
        Self::instantiate(Self::functions(), "plant", &Self::token(), interface, false)
            .unwrap_or_else(|log| panic!("instantiate failed: {log:?}"))
    }

    /// `(value reference, bound)` of every `min` and `max` the version's model description
    /// declares for a scalar real parameter or input.
    fn declared_bounds() -> Vec<(u32, f64)>;

    /// A Co-Simulation instance after initialization.
    fn started() -> Self {
        let plant = Self::open(Interface::CoSimulation);
        plant.initialize();
        plant
    }
}

impl Plant for Fmi2 {
    fn functions() -> &'static fmi_testkit::Fmi2Functions {
        &common::FUNCTIONS
    }
    fn token() -> String {
        fmi2_export::guid::<LanderPlant>()
    }
    fn declared_bounds() -> Vec<(u32, f64)> {
        use model_description::Causality;
        let description = fmi2_export::model_description::<LanderPlant>();
        let mut bounds = Vec::new();
        for sv in &description.model_variables.variables {
            let Some(real) = &sv.real else { continue };
            if matches!(sv.causality, Some(Causality::Parameter | Causality::Input)) {
                for b in [real.min, real.max].into_iter().flatten() {
                    bounds.push((sv.value_reference, b));
                }
            }
        }
        bounds
    }
}

impl Plant for Fmi3 {
    fn functions() -> &'static fmi_testkit::Fmi3Functions {
        &FUNCTIONS3
    }
    fn token() -> String {
        fmi3_export::instantiation_token::<LanderPlant>()
    }
    fn declared_bounds() -> Vec<(u32, f64)> {
        // The writer puts each variable's attributes on its opening line.
        let xml = fmi3_export::model_description_xml::<LanderPlant>();
        let attribute = |line: &str, name: &str| -> Option<String> {
            let start = line.find(&format!(" {name}=\""))? + name.len() + 3;
            Some(line[start..].split('"').next()?.to_string())
        };
        let mut bounds = Vec::new();
        for line in xml
            .lines()
            .filter(|l| l.trim_start().starts_with("<Float64 "))
        {
            let scalar = !line.ends_with('>') || line.ends_with("/>");
            let causal = matches!(
                attribute(line, "causality").as_deref(),
                Some("parameter" | "input")
            );
            if !(scalar && causal) {
                continue;
            }
            let vr: u32 = attribute(line, "valueReference").unwrap().parse().unwrap();
            for name in ["min", "max"] {
                if let Some(v) = attribute(line, name) {
                    bounds.push((vr, v.parse().unwrap()));
                }
            }
        }
        bounds
    }
}

macro_rules! both {
    ($($case:ident),* $(,)?) => {$(
        mod $case {
            #[test]
            fn fmi2() {
                super::$case::<fmi_testkit::Fmi2>()
            }
            #[test]
            fn fmi3() {
                super::$case::<fmi_testkit::Fmi3>()
            }
        }
    )*};
}

both!(
    a_serialized_state_of_the_other_interface_is_refused_by_name,
    a_nonzero_reserved_header_byte_is_refused,
    a_freed_fmu_state_handle_is_refused_when_its_memory_is_reused,
    an_over_long_step_is_refused_and_the_instance_steps_on,
    every_declared_real_bound_is_accepted_by_a_set,
    extreme_values_in_log_lines_are_short,
);

fn a_serialized_state_of_the_other_interface_is_refused_by_name<D: Plant>() {
    // GIVEN a serialized state of a Co-Simulation instance after a step
    let cs = D::started();
    assert_eq!(cs.step(0.0, 0.1).status, Status::Ok);
    let (_, state) = cs.get_state();
    let (_, bytes) = cs.serialize(state);
    // WHEN a Model Exchange instance is asked to deserialize it
    let me = D::open(Interface::ModelExchange);
    me.initialize();
    let (status, _) = me.deserialize(&bytes);
    // THEN it is refused, naming both interfaces, and the instance goes on
    assert_eq!(status, Status::Error);
    let message = me.last_message();
    assert!(
        message.contains("state of a Co-Simulation instance; this instance is Model Exchange"),
        "{message}"
    );
    let (_, mine) = me.get_state();
    assert_eq!(me.set_state(mine), Status::Ok, "{:?}", me.messages());
    // AND the reverse direction is refused the same way
    let (_, me_bytes) = me.serialize(mine);
    assert_eq!(cs.deserialize(&me_bytes).0, Status::Error);
    assert!(
        cs.last_message().contains("Model Exchange instance"),
        "{}",
        cs.last_message()
    );
}

fn a_nonzero_reserved_header_byte_is_refused<D: Plant>() {
    let plant = D::started();
    let (_, state) = plant.get_state();
    let (_, mut bytes) = plant.serialize(state);
    // byte 11 of the header is reserved; the checksum covers the payload only
    bytes[11] = 1;
    assert_eq!(plant.deserialize(&bytes).0, Status::Error);
    assert!(
        plant.last_message().contains("reserved header byte 11"),
        "{}",
        plant.last_message()
    );
    bytes[11] = 0;
    assert_eq!(
        plant.deserialize(&bytes).0,
        Status::Ok,
        "{:?}",
        plant.messages()
    );
}

fn a_freed_fmu_state_handle_is_refused_when_its_memory_is_reused<D: Plant>() {
    let plant = D::started();
    let (_, first) = plant.get_state();
    assert_eq!(plant.free_state(first), Status::Ok);
    // the allocator may hand the freed state's memory to the next one
    let (_, second) = plant.get_state();
    assert_eq!(plant.set_state(first), Status::Error);
    assert!(
        plant
            .last_message()
            .contains("was not created by this instance (or was freed)"),
        "{}",
        plant.last_message()
    );
    assert_eq!(plant.set_state(second), Status::Ok);
}

fn an_over_long_step_is_refused_and_the_instance_steps_on<D: Plant>() {
    let plant = D::started();
    // 1e5 s in RK4 sub-steps of 0.01 s: ten million sub-steps, more than one step may take
    assert_eq!(plant.step(0.0, 1e5).status, Status::Error);
    assert!(
        plant.last_message().contains("RK4 sub-steps"),
        "{}",
        plant.last_message()
    );
    // the refusal changed nothing: the instance is not in state Error
    let outcome = plant.step(0.0, 0.1);
    assert_eq!(outcome.status, Status::Ok, "{:?}", plant.messages());
    assert!((outcome.last_successful_time - 0.1).abs() < 1e-12);
}

/// FMI's `min` and `max` are inclusive: every bound a model description declares for a
/// scalar real parameter or input is a value a set accepts (an exclusive bound is written as
/// the nearest admitted value).
fn every_declared_real_bound_is_accepted_by_a_set<D: Plant>() {
    let bounds = D::declared_bounds();
    assert!(bounds.len() >= 10, "only {} bounds", bounds.len());
    for (vr, bound) in bounds {
        let plant = D::open(Interface::CoSimulation);
        let status = plant.set_real(vr, bound);
        assert_eq!(
            status,
            Status::Ok,
            "vr {vr} = {bound}: {:?}",
            plant.messages()
        );
    }
}

fn extreme_values_in_log_lines_are_short<D: Plant>() {
    let plant = D::started();
    assert_eq!(plant.step(0.0, 1.0).status, Status::Ok);
    // a step of the smallest positive double does not advance the time from 1 s
    assert_eq!(plant.step(1.0, 5e-324).status, Status::Error);
    let message = plant.last_message();
    assert!(message.contains("5e-324"), "{message}");
    assert!(
        message.len() < 200,
        "{} characters: {message}",
        message.len()
    );
}

/// Stale instance handles, FMI 2.0: a freed instance's handle never reaches the instance
/// the allocator puts in its memory.
#[test]
fn a_stale_instance_handle_is_refused_when_its_memory_is_reused() {
    let guid = fmi2_export::guid::<LanderPlant>();
    let mut stale = Vec::new();
    // GIVEN instances freed one after the other, each new one where the allocator puts it
    // (often the memory of the one freed just before)
    for _ in 0..32 {
        let fresh = fmi_testkit::Instance::instantiate(&common::FUNCTIONS, "fresh", &guid);
        // WHEN the master calls through the handles of the freed ones
        for &old in &stale {
            // SAFETY: a stale handle is what a buggy master passes; the FMU must refuse it
            // without reading memory through it.
            let status = unsafe { (common::FUNCTIONS.enter_initialization_mode)(old) };
            // THEN each call is refused and the live instance is untouched
            assert_eq!(status, fmi2Error);
            assert_ne!(old, fresh.component(), "handles are never reused");
        }
        assert!(fresh.messages().is_empty(), "{:?}", fresh.messages());
        assert_eq!(
            fresh.setup_experiment(0.0, None),
            fmi2OK,
            "still Instantiated"
        );
        stale.push(fresh.component());
    }
}

/// The same in FMI 3.0.
#[test]
fn a_stale_fmi3_instance_handle_is_refused_when_its_memory_is_reused() {
    let mut stale = Vec::new();
    for _ in 0..32 {
        let fresh = <Fmi3 as Plant>::open(Interface::CoSimulation);
        for &old in &stale {
            // SAFETY: as above.
            let status =
                unsafe { (FUNCTIONS3.enter_initialization_mode)(old, false, 0.0, 0.0, false, 0.0) };
            assert_eq!(Status::from(status), Status::Error);
            assert_ne!(old, fresh.instance(), "handles are never reused");
        }
        assert!(fresh.messages().is_empty(), "{:?}", fresh.messages());
        assert_eq!(
            Status::from(fresh.enter_initialization_mode(0.0, None)),
            Status::Ok
        );
        stale.push(fresh.instance());
    }
}

/// FMI 3.0: once a step returned `terminateSimulation`, the run is over; a further step is
/// refused (nothing changes), and termination or a reset lead on.
#[test]
fn an_fmi3_step_after_terminate_simulation_is_refused() {
    let plant = <Fmi3 as Plant>::open(Interface::CoSimulation);
    let vr = LanderPlant::declarations()
        .iter()
        .find(|d| d.name == "r0_nue")
        .unwrap()
        .value_reference;
    assert_eq!(
        Status::from(plant.set_float64(&[vr], &[0.0, 0.81, 0.0])),
        Status::Ok
    );
    plant.initialize();
    let touchdown = plant.step(0.0, 2.0);
    assert!(
        touchdown.terminated && touchdown.status == Status::Ok,
        "{touchdown:?}"
    );
    let again = plant.step(touchdown.last_successful_time, 0.1);
    assert_eq!(again.status, Status::Error);
    assert!(
        plant.last_message().contains("terminateSimulation"),
        "{}",
        plant.last_message()
    );
    assert_eq!(Driver::terminate(&plant), Status::Ok);
    assert_eq!(Driver::reset(&plant), Status::Ok);
}
