//! FMU states of the FMI 3.0 backend: `fmi3GetFMUState` and its kin, and what the importer
//! keeps beside each state so that the instance it restores is driven as the one it saved.
//!
//! An FMU state holds the FMU's state machine too (ours and the Reference FMUs' copy it
//! whole), so after `fmi3SetFMUState` the FMU is in the mode it was saved in: the importer
//! takes back its own record of that mode (Step or Event Mode, whether a set happened since
//! the step, the last step's outcome) with the state. A serialized state carries that record
//! ahead of the FMU's bytes, because a state deserialized into a fresh instance has no other
//! way to say which mode it restores; the importer's shadow of the values it last set (see
//! `instance.rs`) is kept with an in-memory state only. Elements a master never sets keep
//! their start values in both, so only a master that sets part of an array, and then
//! restores a deserialized state taken after another set of it, would see the difference.
use super::{Fmi3Instance, Mode};
use crate::error::{CallError, FmiError};
use crate::fmi3::view::Starts;
use crate::state::FmuState;
use crate::status::Success;
use fmi_abi::fmi3::fmi3FMUState;
use std::ptr;
use std::sync::Arc;

/// What the importer restores with an FMU state.
#[derive(Debug, Clone)]
struct Bookkeeping {
    mode: Mode,
    set_since_step: bool,
    last_successful_time: f64,
    terminated: bool,
    /// `None` for a deserialized state.
    shadow: Option<Starts>,
}

/// A live FMU state of this instance and what was true of the instance when it was taken.
#[derive(Debug)]
pub(super) struct Slot {
    pointer: fmi3FMUState,
    saved: Bookkeeping,
}

/// The serialized form's header: what the importer restores, ahead of the FMU's bytes.
const MAGIC: &[u8; 8] = b"FMI3IMP\x01";
const HEADER_LEN: usize = MAGIC.len() + 3 + 8;

impl Mode {
    fn code(self) -> u8 {
        match self {
            Mode::Instantiated => 0,
            Mode::Initialization => 1,
            Mode::Event => 2,
            Mode::Step => 3,
            Mode::ContinuousTime => 4,
            Mode::Terminated => 5,
        }
    }

    fn from_code(code: u8) -> Option<Self> {
        Some(match code {
            0 => Mode::Instantiated,
            1 => Mode::Initialization,
            2 => Mode::Event,
            3 => Mode::Step,
            4 => Mode::ContinuousTime,
            5 => Mode::Terminated,
            _ => return None,
        })
    }
}

impl Fmi3Instance {
    fn bookkeeping(&self) -> Bookkeeping {
        Bookkeeping {
            mode: self.mode,
            set_since_step: self.set_since_step,
            last_successful_time: self.last_successful_time,
            terminated: self.terminated,
            shadow: Some(self.shadow.clone()),
        }
    }

    fn restore(&mut self, saved: &Bookkeeping) {
        self.mode = saved.mode;
        self.set_since_step = saved.set_since_step;
        self.last_successful_time = saved.last_successful_time;
        self.terminated = saved.terminated;
        if let Some(shadow) = &saved.shadow {
            self.shadow.clone_from(shadow);
        }
    }

    /// The slot behind `state`, if this instance made it and has not freed it.
    fn owned_slot(&self, function: &'static str, state: &FmuState) -> Result<usize, CallError> {
        let ours = ptr::eq(state.owner.as_ptr(), Arc::as_ptr(&self.log))
            && self.states.get(state.slot).is_some_and(Option::is_some);
        if ours {
            Ok(state.slot)
        } else {
            Err(self.invalid(
                function,
                "the FMU state belongs to another instance".to_owned(),
            ))
        }
    }

    fn store_state(&mut self, slot: Slot) -> FmuState {
        let index = match self.states.iter().position(Option::is_none) {
            Some(free) => {
                self.states[free] = Some(slot);
                free
            }
            None => {
                self.states.push(Some(slot));
                self.states.len() - 1
            }
        };
        FmuState {
            slot: index,
            owner: Arc::downgrade(&self.log),
        }
    }

    fn slot(&self, index: usize) -> &Slot {
        self.states[index].as_ref().expect("checked by owned_slot")
    }

    /// `fmi3GetFMUState` into a new state.
    pub(crate) fn get_fmu_state(&mut self) -> Result<FmuState, FmiError> {
        let mut pointer: fmi3FMUState = ptr::null_mut();
        let mark = self.log.mark();
        let noted = crate::blackbox::enter(
            self.black_box,
            const { crate::blackbox::function("fmi3GetFMUState") },
        );
        // SAFETY: a null state asks the FMU to allocate a new one.
        let raw = unsafe { (self.functions.get_fmu_state)(self.c(), &mut pointer) };
        drop(noted);
        self.check("fmi3GetFMUState", mark, raw)?;
        let saved = self.bookkeeping();
        Ok(self.store_state(Slot { pointer, saved }))
    }

    /// `fmi3GetFMUState` overwriting an existing state, without a new allocation.
    pub(crate) fn update_fmu_state(&mut self, state: &FmuState) -> Result<Success, CallError> {
        const F: &str = "fmi3GetFMUState";
        let index = self.owned_slot(F, state)?;
        let mut pointer = self.slot(index).pointer;
        let mark = self.log.mark();
        // SAFETY: `pointer` is a live state of this instance.
        let raw = unsafe { (self.functions.get_fmu_state)(self.c(), &mut pointer) };
        let saved = self.bookkeeping();
        // The FMU may hand back a different pointer even on failure; keep whatever it returned.
        let slot = self.states[index].as_mut().expect("checked by owned_slot");
        slot.pointer = pointer;
        let success = self.check(F, mark, raw)?;
        self.states[index].as_mut().expect("still there").saved = saved;
        Ok(success)
    }

    /// `fmi3SetFMUState`: continue from a saved state, in the mode it was saved in.
    pub(crate) fn set_fmu_state(&mut self, state: &FmuState) -> Result<Success, CallError> {
        const F: &str = "fmi3SetFMUState";
        let index = self.owned_slot(F, state)?;
        let pointer = self.slot(index).pointer;
        let mark = self.log.mark();
        let noted = crate::blackbox::enter(
            self.black_box,
            const { crate::blackbox::function("fmi3SetFMUState") },
        );
        // SAFETY: `pointer` is a live state of this instance.
        let raw = unsafe { (self.functions.set_fmu_state)(self.c(), pointer) };
        drop(noted);
        let success = self.check(F, mark, raw)?;
        let saved = self.slot(index).saved.clone();
        self.restore(&saved);
        Ok(success)
    }

    /// `fmi3FreeFMUState`.
    pub(crate) fn free_fmu_state(&mut self, state: FmuState) -> Result<Success, CallError> {
        const F: &str = "fmi3FreeFMUState";
        let index = self.owned_slot(F, &state)?;
        let mut pointer = self.states[index].take().expect("checked").pointer;
        let mark = self.log.mark();
        // SAFETY: `pointer` is a live state of this instance, freed exactly once (its slot is
        // cleared).
        let raw = unsafe { (self.functions.free_fmu_state)(self.c(), &mut pointer) };
        Ok(self.check(F, mark, raw)?)
    }

    /// The importer's header, then `fmi3SerializedFMUStateSize` + `fmi3SerializeFMUState`.
    pub(crate) fn serialize_fmu_state(&mut self, state: &FmuState) -> Result<Vec<u8>, CallError> {
        let index = self.owned_slot("fmi3SerializeFMUState", state)?;
        let Slot { pointer, saved } = self.slot(index);
        let (pointer, saved) = (*pointer, saved.clone());
        let mut size = 0usize;
        let mark = self.log.mark();
        // SAFETY: `pointer` is a live state of this instance; `size` is a valid out-pointer.
        let raw =
            unsafe { (self.functions.serialized_fmu_state_size)(self.c(), pointer, &mut size) };
        self.check("fmi3SerializedFMUStateSize", mark, raw)?;
        let mut bytes = Vec::with_capacity(HEADER_LEN + size);
        bytes.extend_from_slice(MAGIC);
        bytes.push(saved.mode.code());
        bytes.push(u8::from(saved.set_since_step));
        bytes.push(u8::from(saved.terminated));
        bytes.extend_from_slice(&saved.last_successful_time.to_le_bytes());
        bytes.resize(HEADER_LEN + size, 0);
        let mark = self.log.mark();
        // SAFETY: the bytes after the header are exactly the `size` the FMU asked for.
        let raw = unsafe {
            (self.functions.serialize_fmu_state)(
                self.c(),
                pointer,
                bytes[HEADER_LEN..].as_mut_ptr(),
                size,
            )
        };
        self.check("fmi3SerializeFMUState", mark, raw)?;
        Ok(bytes)
    }

    /// The importer's header checked, then `fmi3DeserializeFMUState` into a new state.
    pub(crate) fn deserialize_fmu_state(&mut self, bytes: &[u8]) -> Result<FmuState, FmiError> {
        const F: &str = "fmi3DeserializeFMUState";
        let refuse = |reason: &str| {
            FmiError::from_importer(
                F,
                &self.name,
                crate::version::FmiVersion::Fmi3,
                format!("not called: {reason}"),
            )
        };
        if bytes.len() < HEADER_LEN || !bytes.starts_with(MAGIC) {
            return Err(refuse(
                "the bytes are not an FMU state serialized by this importer from an FMI 3.0 \
                 instance (no header)",
            ));
        }
        let header = &bytes[MAGIC.len()..HEADER_LEN];
        let (Some(mode), Some(set_since_step), Some(terminated)) =
            (Mode::from_code(header[0]), flag(header[1]), flag(header[2]))
        else {
            return Err(refuse("the importer's header of the FMU state is corrupt"));
        };
        let last_successful_time =
            f64::from_le_bytes(header[3..11].try_into().expect("eight bytes"));
        let fmu_bytes = &bytes[HEADER_LEN..];
        let mut pointer: fmi3FMUState = ptr::null_mut();
        let mark = self.log.mark();
        // SAFETY: `fmu_bytes` is readable for its length; a null state asks for a new one.
        let raw = unsafe {
            (self.functions.deserialize_fmu_state)(
                self.c(),
                fmu_bytes.as_ptr(),
                fmu_bytes.len(),
                &mut pointer,
            )
        };
        self.check(F, mark, raw)?;
        let saved = Bookkeeping {
            mode,
            set_since_step,
            last_successful_time,
            terminated,
            shadow: None,
        };
        Ok(self.store_state(Slot { pointer, saved }))
    }

    /// Frees every state still held; on drop, before the instance goes.
    pub(super) fn free_all_states(&mut self) {
        let free = self.functions.free_fmu_state;
        for slot in self.states.iter_mut().filter_map(Option::take) {
            let mut pointer = slot.pointer;
            // SAFETY: each held slot is a live state of this instance, freed once here. A
            // failure cannot be reported from drop; the FMU has logged it.
            unsafe { free(self.instance.as_ptr(), &mut pointer) };
        }
    }
}

fn flag(byte: u8) -> Option<bool> {
    match byte {
        0 => Some(false),
        1 => Some(true),
        _ => None,
    }
}
