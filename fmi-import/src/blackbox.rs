//! The FMI call this process is in, written where a supervising process can read it after
//! this one died inside the call (a crash, an `exit` from FMU code, a hang it was killed for).
//!
//! A supervising master maps a small shared file into its worker and installs it here with
//! [`install`]; from then on every call the importer makes into an FMU first writes the
//! instance, the function and the simulation time there. Without an installed record each call
//! costs one relaxed load.
#![allow(unsafe_code)]

use std::sync::atomic::{AtomicPtr, AtomicU32, AtomicU64, Ordering};

/// Bytes kept of an instance's name.
pub const INSTANCE_BYTES: usize = 96;
/// Bytes kept of a function's name (the longest FMI name is 38 bytes).
pub const FUNCTION_BYTES: usize = 48;
/// Written first, so a reader can tell a record from a file of zeros.
pub const MAGIC: u64 = 0x464d_4942_4258_0001;

/// The record, laid out the same in every process that maps it.
#[repr(C)]
pub struct Record {
    pub magic: AtomicU64,
    /// Calls started so far: a reader that sees it unchanged over a while sees one call
    /// (or no call at all) last that long.
    pub calls: AtomicU64,
    /// 1 from a call's start to its return.
    pub in_call: AtomicU32,
    pub instance_len: AtomicU32,
    pub function_len: AtomicU32,
    _pad: u32,
    /// The simulation time of the call, as f64 bits.
    pub time_bits: AtomicU64,
    pub instance: [AtomicU64; INSTANCE_BYTES / 8],
    pub function: [AtomicU64; FUNCTION_BYTES / 8],
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

/// Marks the end of a call when dropped; a call noted inside another (an FMI 3.0 step that
/// first leaves Event Mode) gives the outer one back its name.
pub struct Call(Option<(&'static Record, Option<&'static str>)>);

std::thread_local! {
    /// The function of the call this thread is in, if any.
    static CURRENT: std::cell::Cell<Option<&'static str>> = const { std::cell::Cell::new(None) };
}

impl Drop for Call {
    fn drop(&mut self) {
        if let Some((record, outer)) = self.0 {
            CURRENT.with(|current| current.set(outer));
            match outer {
                Some(function) => store_text(&record.function, &record.function_len, function),
                None => record.in_call.store(0, Ordering::Release),
            }
        }
    }
}

fn installed() -> Option<&'static Record> {
    let pointer = RECORD.load(Ordering::Acquire);
    // SAFETY: only `install` stores a non-null pointer, to memory mapped for good.
    (!pointer.is_null()).then(|| unsafe { &*pointer })
}

fn store_text(slots: &[AtomicU64], len: &AtomicU32, text: &str) {
    let bytes = text.as_bytes();
    let kept = bytes.len().min(slots.len() * 8);
    for (slot, chunk) in slots.iter().zip(bytes[..kept].chunks(8)) {
        let mut word = [0u8; 8];
        word[..chunk.len()].copy_from_slice(chunk);
        slot.store(u64::from_le_bytes(word), Ordering::Relaxed);
    }
    len.store(kept as u32, Ordering::Relaxed);
}

fn load_text(slots: &[AtomicU64], len: &AtomicU32) -> String {
    let len = (len.load(Ordering::Relaxed) as usize).min(slots.len() * 8);
    let bytes: Vec<u8> = slots
        .iter()
        .flat_map(|slot| slot.load(Ordering::Relaxed).to_le_bytes())
        .take(len)
        .collect();
    String::from_utf8_lossy(&bytes).into_owned()
}

/// Notes the start of a call of `function` on `instance` (both asked only when a record is
/// installed); the call ends when the returned guard drops.
#[inline]
pub fn enter<'a>(what: impl FnOnce() -> (&'static str, &'a str)) -> Call {
    let Some(record) = installed() else {
        return Call(None);
    };
    let (function, instance) = what();
    store_text(&record.instance, &record.instance_len, instance);
    store_text(&record.function, &record.function_len, function);
    record.in_call.store(1, Ordering::Relaxed);
    record.calls.fetch_add(1, Ordering::Release);
    let outer = CURRENT.with(|current| current.replace(Some(function)));
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
    Some(LastCall {
        calls: record.calls.load(Ordering::Acquire),
        instance: load_text(&record.instance, &record.instance_len),
        function: load_text(&record.function, &record.function_len),
        time: f64::from_bits(record.time_bits.load(Ordering::Relaxed)),
        in_call: record.in_call.load(Ordering::Acquire) == 1,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_record_reads_back_what_the_last_call_wrote_and_truncates_long_names() {
        let record: &'static mut Record =
            Box::leak(Box::new(unsafe { std::mem::zeroed::<Record>() }));
        assert_eq!(read(record), None, "zeros are no record");
        let pointer: *mut Record = record;
        // SAFETY: leaked, so mapped for the rest of the process.
        unsafe { install(pointer) };
        set_time(0.25);
        {
            let _call = enter(|| ("fmi2DoStep", "plant"));
            let seen = read(unsafe { &*pointer }).unwrap();
            assert_eq!(seen.instance, "plant");
            assert_eq!(seen.function, "fmi2DoStep");
            assert_eq!(seen.time, 0.25);
            assert!(seen.in_call);
            assert_eq!(seen.calls, 1);
        }
        assert!(!read(unsafe { &*pointer }).unwrap().in_call);
        {
            let _step = enter(|| ("fmi3DoStep", "gnc"));
            drop(enter(|| ("fmi3EnterStepMode", "gnc")));
            let seen = read(unsafe { &*pointer }).unwrap();
            assert_eq!(seen.function, "fmi3DoStep", "the outer call named again");
            assert!(seen.in_call);
        }
        assert!(!read(unsafe { &*pointer }).unwrap().in_call);
        let long = "x".repeat(200);
        drop(enter(|| ("fmi3GetFloat64", long.as_str())));
        let seen = read(unsafe { &*pointer }).unwrap();
        assert_eq!(seen.instance, "x".repeat(INSTANCE_BYTES));
        assert_eq!(seen.function, "fmi3GetFloat64");
        assert_eq!(seen.calls, 4);
        RECORD.store(std::ptr::null_mut(), Ordering::Release);
    }
}
