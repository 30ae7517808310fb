//! What a version layer tells the core about itself.
use crate::logging::{Category, Logger, Sink};
use crate::registry::Registry;
use crate::state::{Interface, State};
use crate::status::{Refusal, Status};
use fmi_model::Model;
use std::ffi::CStr;

/// One FMI version's function table: each function's C name and the states (and interface)
/// in which it may be called.
pub trait Function: Copy + std::fmt::Debug + 'static {
    /// The C name, e.g. `"fmi3DoStep"`.
    fn name(self) -> &'static str;
    /// `Ok` when the function may run on an instance of `interface` in `state`.
    fn admit(self, interface: Interface, state: State) -> Result<(), Refusal>;
}

/// The functions of `table` that a Fatal instance admits, of either interface: the
/// standards allow nothing after Fatal but freeing the instance, so a sound table answers
/// exactly `[free]`. For each version's table test.
pub fn admitted_when_fatal<F: Function + PartialEq>(table: &[F]) -> Vec<F> {
    table
        .iter()
        .copied()
        .filter(|f| {
            [Interface::ModelExchange, Interface::CoSimulation]
                .into_iter()
                .any(|interface| f.admit(interface, State::Fatal).is_ok())
        })
        .collect()
}

/// Checks a version's function table, for its own test: `count` functions, each named
/// `prefix...` and no name twice, and nothing admitted once Fatal but `free`.
///
/// # Panics
/// With the first property that does not hold.
pub fn assert_function_table<F: Function + PartialEq>(
    table: &[F],
    count: usize,
    prefix: &str,
    free: F,
) {
    assert_eq!(table.len(), count, "functions in the table");
    let mut names: Vec<&str> = table.iter().map(|f| f.name()).collect();
    assert!(
        names.iter().all(|n| n.starts_with(prefix)),
        "{names:?} not all {prefix}*"
    );
    names.sort_unstable();
    names.dedup();
    assert_eq!(names.len(), count, "a name twice in the table");
    assert_eq!(admitted_when_fatal(table), [free], "admitted when Fatal");
}

/// One FMI version, as the core needs to know it.
pub trait Abi: Sized + 'static {
    /// Magic bytes of a serialized FMU state of this version ([`crate::snapshot`]).
    const SNAPSHOT_MAGIC: [u8; 8];
    /// The version's C status type (a C `int`).
    type CStatus: Copy + From<std::os::raw::c_int>;
    /// The version's function table.
    type Function: Function;
    /// The version's logger callback (an optional C function pointer).
    type Callback: Copy + Send + std::fmt::Debug;
    /// The version's view of the variables of `M` (FMI 2.0 scalars, FMI 3.0 arrays), built
    /// once per instance.
    type View<M: Model>;

    #[inline(always)]
    fn status(status: Status) -> Self::CStatus {
        Self::CStatus::from(status.code())
    }
    /// Calls the master's logger. `message` is complete text (never a format string).
    fn emit(sink: &Sink<Self::Callback>, status: Status, category: Category, message: &CStr);
    fn view<M: Model>() -> Self::View<M>;
    /// The registry of this version's live instances of this FMU.
    const REGISTRY: &'static Registry<Logger<Self>>;
    /// The interface identity of `M` written into its model description (GUID or
    /// instantiation token); a serialized FMU state carries it.
    fn interface_uuid<M: Model>() -> uuid::Uuid;
    /// The instantiation argument that carries the model description's identity.
    const TOKEN_ARGUMENT: &'static str;
    /// The function that declares the stop time, named when a step passes it.
    const EXPERIMENT: &'static str;
    /// The states an instance of this version can be in (a restored FMU state in any other
    /// is refused: FMI 3.0 has no StepFailed, FMI 2.0's Co-Simulation no Event Mode).
    const STATES: crate::StateMask;
    /// The categories this version declares in its model description.
    const CATEGORIES: &'static [Category];
}
