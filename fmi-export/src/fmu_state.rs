//! FMU states: copies of an instance's [`Core`], handed to the master as opaque handles, and
//! their serialization.
//!
//! A handle is a number from one process-wide counter, never a heap address and never
//! reused: a freed state's handle, a handle of another instance, or any other pointer the
//! master passes is refused by lookup, without reading memory through it, even when the
//! allocator has reused the freed state's memory.
//!
//! A restored state (set, or deserialized) is checked before it replaces anything: a crafted
//! buffer carries a valid header and checksum as easily as a genuine one, so only a state
//! the instance could have reached is accepted. A refusal names the field at fault and
//! leaves the instance as it was.
use crate::instance::{Core, Instance};
use crate::restored::{check_bookkeeping, check_declared_values, Bookkeeping};
use crate::snapshot;
use crate::state::{Interface, State, StateMask};
use crate::status::{CallError, Success};
use crate::version::Abi;
use fmi_model::Model;
use std::collections::HashMap;
use std::os::raw::c_void;
use std::sync::atomic::{AtomicUsize, Ordering};

/// The next FMU-state handle of this library (shared by every instance and version, so
/// that no two live states ever share one).
static NEXT_HANDLE: AtomicUsize = AtomicUsize::new(1);

/// The FMU states an instance handed out and has not freed.
#[derive(Debug)]
pub struct FmuStates<M> {
    states: HashMap<usize, Box<Core<M>>>,
}

impl<M> Default for FmuStates<M> {
    fn default() -> Self {
        FmuStates {
            states: HashMap::new(),
        }
    }
}

impl<M: Model> FmuStates<M> {
    /// The state behind `handle`, if this instance handed it out and has not freed it.
    pub fn get(&self, handle: *mut c_void) -> Result<&Core<M>, CallError> {
        if handle.is_null() {
            return Err(CallError::NullArgument("FMUstate"));
        }
        self.states
            .get(&(handle as usize))
            .map(Box::as_ref)
            .ok_or_else(|| foreign(handle))
    }

    /// Stores `core` in `*slot`: into the state already there (which must be ours) or, for
    /// NULL, a new one whose handle is written to the slot.
    pub fn store(&mut self, slot: &mut *mut c_void, core: Core<M>) -> Result<(), CallError> {
        if slot.is_null() {
            // Handles look like aligned pointers to a master that prints them.
            let handle = NEXT_HANDLE.fetch_add(1, Ordering::Relaxed) << 4;
            self.states.insert(handle, Box::new(core));
            *slot = handle as *mut c_void;
        } else {
            match self.states.get_mut(&(*slot as usize)) {
                Some(existing) => **existing = core,
                None => return Err(foreign(*slot)),
            }
        }
        Ok(())
    }

    /// Frees the state in `*slot` and sets the slot to NULL; a NULL slot is ignored (both
    /// standards say so).
    pub fn free(&mut self, slot: &mut *mut c_void) -> Result<(), CallError> {
        if slot.is_null() {
            return Ok(());
        }
        self.states
            .remove(&(*slot as usize))
            .ok_or_else(|| foreign(*slot))?;
        *slot = std::ptr::null_mut();
        Ok(())
    }
}

#[cold]
fn foreign(handle: *mut c_void) -> CallError {
    CallError::InvalidArgument(format!(
        "FMU state {handle:p} was not created by this instance (or was freed)"
    ))
}

/// What identifies a serialized state of this FMU and version.
fn header<M: Model, A: Abi>(inst: &Instance<M, A>) -> snapshot::Header {
    snapshot::Header {
        magic: A::SNAPSHOT_MAGIC,
        state_version: M::STATE_VERSION,
        guid: inst.uuid,
        interface: inst.interface(),
    }
}

/// `Ok` if `core` is a state this instance could have been in.
pub fn validate<M: Model, A: Abi>(inst: &Instance<M, A>, core: &Core<M>) -> Result<(), CallError> {
    if core.interface != inst.interface() {
        return Err(CallError::InvalidArgument(format!(
            "FMU state of a {} instance; this instance is {}",
            core.interface.name(),
            inst.interface().name()
        )));
    }
    if !reachable(inst, core.state) {
        return Err(CallError::InvalidArgument(format!(
            "FMU state in state {:?}, which a {} instance of this FMU never enters",
            core.state,
            inst.interface().name()
        )));
    }
    let bookkeeping = Bookkeeping {
        time: core.time,
        start_time: core.start_time,
        last_successful_time: Some(core.last_successful_time),
        stop_time: core.stop_time,
        fatal: core.state == State::Fatal,
    };
    check_bookkeeping(&bookkeeping, crate::TIME_TOLERANCE)
        .and_then(|()| check_declared_values(&core.model))
        .map_err(CallError::InvalidArgument)?;
    // The model's own invariants (validated parameters, admissible state).
    core.model
        .validate_restored(!core.state.initializing())
        .map_err(|e| {
            CallError::Model(format!(
                "FMU state refused: {}",
                crate::describe_model_error::<M>(&e)
            ))
        })
}

/// Whether an instance like `inst` (its version, interface and options) can be in `state`.
fn reachable<A: Abi, M: Model>(inst: &Instance<M, A>, state: State) -> bool {
    use State::*;
    let interface_states = match inst.interface() {
        Interface::ModelExchange => StateMask::of(&[
            Instantiated,
            InitializationMode,
            EventMode,
            ContinuousTimeMode,
            Terminated,
            Error,
        ]),
        Interface::CoSimulation if inst.options.event_mode_used => StateMask::of(&[
            Instantiated,
            InitializationMode,
            StepComplete,
            StepFailed,
            EventMode,
            Terminated,
            Error,
        ]),
        Interface::CoSimulation => StateMask::of(&[
            Instantiated,
            InitializationMode,
            StepComplete,
            StepFailed,
            Terminated,
            Error,
        ]),
    };
    interface_states.contains(state) && A::STATES.contains(state)
}

/// A copy of the instance's state into `*slot`.
pub fn get<M: Model, A: Abi>(
    inst: &mut Instance<M, A>,
    slot: &mut *mut c_void,
) -> Result<Success, CallError> {
    let core = inst.core.clone();
    inst.fmu_states.store(slot, core)?;
    Ok(Success::Ok)
}

/// The instance takes the state behind `handle` (checked first).
pub fn set<M: Model, A: Abi>(
    inst: &mut Instance<M, A>,
    handle: *mut c_void,
) -> Result<Success, CallError> {
    let core = inst.fmu_states.get(handle)?;
    validate(inst, core)?;
    let core = core.clone();
    inst.core = core;
    inst.dirty = true;
    Ok(Success::Ok)
}

pub fn free<M: Model, A: Abi>(
    inst: &mut Instance<M, A>,
    slot: &mut *mut c_void,
) -> Result<Success, CallError> {
    inst.fmu_states.free(slot)?;
    Ok(Success::Ok)
}

/// The serialized state behind `handle`.
pub fn serialize<M: Model, A: Abi>(
    inst: &Instance<M, A>,
    handle: *mut c_void,
) -> Result<Vec<u8>, CallError> {
    Ok(snapshot::encode(
        inst.fmu_states.get(handle)?,
        header(inst),
    )?)
}

/// Writes the serialized state behind `handle` into `buffer`, whose length must be what
/// the size function (`size_function`, named in the refusal) answered.
pub fn serialize_into<M: Model, A: Abi>(
    inst: &Instance<M, A>,
    handle: *mut c_void,
    buffer: &mut [u8],
    size_function: &str,
) -> Result<Success, CallError> {
    let bytes = serialize(inst, handle)?;
    if buffer.len() != bytes.len() {
        return Err(CallError::InvalidArgument(format!(
            "size {} differs from {size_function} = {}",
            buffer.len(),
            bytes.len()
        )));
    }
    buffer.copy_from_slice(&bytes);
    Ok(Success::Ok)
}

/// A state from its serialization (checked), into `*slot` as [`get`] does.
pub fn deserialize<M: Model, A: Abi>(
    inst: &mut Instance<M, A>,
    bytes: &[u8],
    slot: &mut *mut c_void,
) -> Result<Success, CallError> {
    let core = snapshot::decode::<Core<M>>(bytes, header(inst))?;
    validate(inst, &core)?;
    inst.fmu_states.store(slot, core)?;
    Ok(Success::Ok)
}
