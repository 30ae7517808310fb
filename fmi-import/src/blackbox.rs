//! The FMI call this process is in, written where a supervising process can read it after
//! this one died inside the call (a crash, an `exit` from FMU code, a hang it was killed for).
//!
//! A supervising master maps a small shared file into its worker and installs it here with
//! [`install`]; from then on every call the importer makes into an FMU first writes the
//! instance, the function and the simulation time there, as small numbers: an instance's name
//! is written once, when it is made, and a function is its index in [`FUNCTIONS`], known at
//! compile time. Without an installed record a call costs one load.
#![allow(unsafe_code)]

use std::sync::atomic::{AtomicPtr, AtomicU32, AtomicU64, Ordering};

/// Instances whose names a record keeps; later ones are told by number.
pub const NAMED_INSTANCES: usize = 24;
/// Bytes kept of an instance's name.
pub const NAME_BYTES: usize = 96;
/// Written first, so a reader can tell a record from a file of zeros.
pub const MAGIC: u64 = 0x464d_4942_4258_0002;
/// The function of "no call": the index after the last name.
const NO_FUNCTION: u32 = u32::MAX;

/// Every function of both standards, by the index a record stores: the entry-point tables'
/// listings (`crate::tables`) one after the other, so a function has one listing.
pub const FUNCTIONS: [&str; FUNCTION_COUNT] = concatenated(LISTINGS);

const LISTINGS: &[&[&str]] = {
    use crate::tables::fmi2::{Fmi2CoSimulation, Fmi2Common, Fmi2ModelExchange};
    use crate::tables::fmi3::{Fmi3CoSimulation, Fmi3Common, Fmi3ModelExchange};
    &[
        Fmi2Common::SYMBOLS,
        Fmi2CoSimulation::SYMBOLS,
        Fmi2ModelExchange::SYMBOLS,
        Fmi3Common::SYMBOLS,
        Fmi3CoSimulation::SYMBOLS,
        Fmi3ModelExchange::SYMBOLS,
    ]
};

const FUNCTION_COUNT: usize = {
    let mut count = 0;
    let mut i = 0;
    while i < LISTINGS.len() {
        count += LISTINGS[i].len();
        i += 1;
    }
    count
};

const fn concatenated(listings: &[&[&'static str]]) -> [&'static str; FUNCTION_COUNT] {
    let mut all = [""; FUNCTION_COUNT];
    let (mut k, mut i) = (0, 0);
    while i < listings.len() {
        let mut j = 0;
        while j < listings[i].len() {
            all[k] = listings[i][j];
            k += 1;
            j += 1;
        }
        i += 1;
    }
    all
}

/// The index of `name` in [`FUNCTIONS`]; a name not there fails the build where it is used
/// in a constant.
pub const fn function(name: &str) -> u32 {
    let mut i = 0;
    while i < FUNCTIONS.len() {
        if equal(FUNCTIONS[i].as_bytes(), name.as_bytes()) {
            return i as u32;
        }
        i += 1;
    }
    panic!("not an FMI function the black box knows")
}

const fn equal(a: &[u8], b: &[u8]) -> bool {
    if a.len() != b.len() {
        return false;
    }
    let mut i = 0;
    while i < a.len() {
        if a[i] != b[i] {
            return false;
        }
        i += 1;
    }
    true
}

/// The index of a function known only at run time (a name passed along); `None` if unknown.
pub fn function_at_run_time(name: &str) -> u32 {
    FUNCTIONS
        .iter()
        .position(|f| *f == name)
        .map_or(NO_FUNCTION, |i| i as u32)
}

/// The record, laid out the same in every process that maps it.
#[repr(C)]
pub struct Record {
    pub magic: AtomicU64,
    /// Calls started so far: a reader that sees it unchanged over a while sees one call
    /// (or no call at all) last that long.
    pub calls: AtomicU64,
    /// 1 from a call's start to its return.
    pub in_call: AtomicU32,
    /// Index in [`FUNCTIONS`].
    pub function: AtomicU32,
    /// The instance's number (see [`register`]).
    pub instance: AtomicU32,
    /// Instances registered so far.
    pub instances: AtomicU32,
    /// The simulation time of the call, as f64 bits.
    pub time_bits: AtomicU64,
    pub name_lens: [AtomicU32; NAMED_INSTANCES],
    pub names: [[AtomicU64; NAME_BYTES / 8]; NAMED_INSTANCES],
}

/// What a record says, read back.
#[derive(Debug, Clone, PartialEq)]
pub struct LastCall {
    pub instance: String,
    pub function: String,
    pub time: f64,
    /// Whether that call had not returned.
    pub in_call: bool,
    pub calls: u64,
}

static RECORD: AtomicPtr<Record> = AtomicPtr::new(std::ptr::null_mut());

/// Makes every later FMI call of this process write to `record`.
///
/// # Safety
/// `record` points to writable memory of `size_of::<Record>()` bytes, aligned to 8, that stays
/// mapped for the rest of the process's life.
pub unsafe fn install(record: *mut Record) {
    // SAFETY: the caller guarantees the memory; atomics need no initialised contents.
    unsafe { (*record).magic.store(MAGIC, Ordering::Relaxed) };
    RECORD.store(record, Ordering::Release);
}

fn installed() -> Option<&'static Record> {
    let pointer = RECORD.load(Ordering::Acquire);
    // SAFETY: only `install` stores a non-null pointer, to memory mapped for good.
    (!pointer.is_null()).then(|| unsafe { &*pointer })
}

/// The number an instance named `name` is noted by (0 when no record is installed).
pub fn register(name: &str) -> u32 {
    let Some(record) = installed() else {
        return 0;
    };
    // One thread makes instances at a time in a worker; a lost race only misnames.
    let number = record.instances.fetch_add(1, Ordering::Relaxed);
    if let Some(slots) = record.names.get(number as usize) {
        let bytes = &name.as_bytes()[..name.len().min(NAME_BYTES)];
        for (slot, chunk) in slots.iter().zip(bytes.chunks(8)) {
            let mut word = [0u8; 8];
            for (w, b) in word.iter_mut().zip(chunk) {
                *w = *b;
            }
            slot.store(u64::from_le_bytes(word), Ordering::Relaxed);
        }
        record.name_lens[number as usize].store(bytes.len() as u32, Ordering::Release);
    }
    number
}

/// Marks the end of a call when dropped; a call noted inside another (an FMI 3.0 step that
/// first leaves Event Mode) gives the outer one back its function.
pub struct Call(Option<(&'static Record, u32)>);

impl Drop for Call {
    #[inline]
    fn drop(&mut self) {
        if let Some((record, outer)) = self.0 {
            if outer == NO_FUNCTION {
                record.in_call.store(0, Ordering::Release);
            } else {
                record.function.store(outer, Ordering::Relaxed);
            }
        }
    }
}

/// Notes the start of a call of the function numbered `function` (see [`function`]) on the
/// instance numbered `instance`; the call ends when the returned guard drops.
#[inline]
pub fn enter(instance: u32, function: u32) -> Call {
    let Some(record) = installed() else {
        return Call(None);
    };
    let outer = if record.in_call.load(Ordering::Relaxed) == 1 {
        record.function.load(Ordering::Relaxed)
    } else {
        NO_FUNCTION
    };
    record.instance.store(instance, Ordering::Relaxed);
    record.function.store(function, Ordering::Relaxed);
    record.in_call.store(1, Ordering::Relaxed);
    // One writer: a plain increment, published with the fields above.
    let calls = record.calls.load(Ordering::Relaxed);
    record.calls.store(calls + 1, Ordering::Release);
    Call(Some((record, outer)))
}

/// The simulation time the following calls belong to.
#[inline]
pub fn set_time(time: f64) {
    if let Some(record) = installed() {
        record.time_bits.store(time.to_bits(), Ordering::Relaxed);
    }
}

/// Reads a record (of this or another process).
pub fn read(record: &Record) -> Option<LastCall> {
    if record.magic.load(Ordering::Acquire) != MAGIC {
        return None;
    }
    let number = record.instance.load(Ordering::Relaxed) as usize;
    let instance = match record.names.get(number) {
        Some(slots) => {
            let len = (record.name_lens[number].load(Ordering::Acquire) as usize).min(NAME_BYTES);
            let bytes: Vec<u8> = slots
                .iter()
                .flat_map(|slot| slot.load(Ordering::Relaxed).to_le_bytes())
                .take(len)
                .collect();
            String::from_utf8_lossy(&bytes).into_owned()
        }
        None => format!("#{number}"),
    };
    let function = FUNCTIONS
        .get(record.function.load(Ordering::Relaxed) as usize)
        .map_or_else(|| "an FMI function".to_owned(), |f| (*f).to_owned());
    Some(LastCall {
        calls: record.calls.load(Ordering::Acquire),
        instance,
        function,
        time: f64::from_bits(record.time_bits.load(Ordering::Relaxed)),
        in_call: record.in_call.load(Ordering::Acquire) == 1,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_record_reads_back_the_last_call_and_an_inner_call_gives_the_outer_one_back() {
        let record: &'static mut Record =
            Box::leak(Box::new(unsafe { std::mem::zeroed::<Record>() }));
        assert_eq!(read(record), None, "zeros are no record");
        let pointer: *mut Record = record;
        // SAFETY: leaked, so mapped for the rest of the process.
        unsafe { install(pointer) };
        let plant = register("plant");
        let long = register(&"x".repeat(200));
        set_time(0.25);
        {
            let _call = enter(plant, function("fmi2DoStep"));
            let seen = read(unsafe { &*pointer }).unwrap();
            assert_eq!(seen.instance, "plant");
            assert_eq!(seen.function, "fmi2DoStep");
            assert_eq!(seen.time, 0.25);
            assert!(seen.in_call);
            assert_eq!(seen.calls, 1);
        }
        assert!(!read(unsafe { &*pointer }).unwrap().in_call);
        {
            let _step = enter(plant, function("fmi3DoStep"));
            drop(enter(plant, function("fmi3EnterStepMode")));
            let seen = read(unsafe { &*pointer }).unwrap();
            assert_eq!(seen.function, "fmi3DoStep", "the outer call named again");
            assert!(seen.in_call);
        }
        assert!(!read(unsafe { &*pointer }).unwrap().in_call);
        drop(enter(long, function_at_run_time("fmi3GetFloat64")));
        let seen = read(unsafe { &*pointer }).unwrap();
        assert_eq!(seen.instance, "x".repeat(NAME_BYTES));
        assert_eq!(seen.function, "fmi3GetFloat64");
        assert_eq!(seen.calls, 4);
        RECORD.store(std::ptr::null_mut(), Ordering::Release);
    }

    #[test]
    fn every_function_has_its_own_index() {
        for (i, name) in FUNCTIONS.iter().enumerate() {
            assert_eq!(function(name), i as u32);
            assert_eq!(function_at_run_time(name), i as u32);
        }
    }
}
