//! The registry of live instances has a fixed capacity: the instantiation beyond it returns
//! NULL with a log line saying why, and works again once an instance is freed; for both
//! FMI versions (each layer has a registry of its own). Its own test binary, so that no
//! other test's instances count.
mod common;

use common::{vr, Interface, Osc, Status, Version};
use fmi_export::registry::CAPACITY;

fn one_instance_beyond_the_capacity_is_refused_with_a_reason<D: Osc>() {
    let instantiate = || {
        D::instantiate(
            D::functions(),
            "many",
            &D::token(),
            Interface::CoSimulation,
            false,
        )
    };
    let mut live: Vec<D> = (0..CAPACITY)
        .map(|k| instantiate().unwrap_or_else(|log| panic!("instance {k}: {log:?}")))
        .collect();
    assert!(live.iter().all(|d| d.messages().is_empty()));

    let refused = instantiate()
        .err()
        .expect("one instance beyond the capacity");
    let function = match D::VERSION {
        Version::Fmi2 => "fmi2Instantiate",
        Version::Fmi3 => "fmi3InstantiateCoSimulation",
    };
    let messages: Vec<String> = refused.into_iter().filter_map(|r| r.message).collect();
    assert_eq!(
        messages,
        [format!(
            "{function}: {CAPACITY} instances of this FMU are already live in this \
             process; free one first"
        )]
    );

    // Every instance answers, as its own: each enters initialization and reads a variable.
    for d in &live {
        assert_eq!(d.enter_initialization_mode(0.0, None), Status::Ok);
        assert!(d.real(vr::X0).is_finite());
    }

    drop(live.swap_remove(CAPACITY / 2));
    let again = instantiate().unwrap_or_else(|log| panic!("after a free: {log:?}"));
    live.push(again);
    assert!(live.iter().all(|d| d.messages().is_empty()));
}

both!(one_instance_beyond_the_capacity_is_refused_with_a_reason);
