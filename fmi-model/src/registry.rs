//! The live instances of an FMI layer, and which of them are inside a call.
//!
//! An FMU runs in the master's process and trusts nothing it is handed. Two hazards need
//! bookkeeping outside the instance itself:
//!
//! - A component pointer that is not (or no longer) a live instance: a second
//!   `FreeInstance`, a call after it, or a pointer of some other object. Looking the address
//!   up here, before anything is read through it, refuses all of them without touching the
//!   memory it points to.
//! - A call into an instance while another call on it has not returned: the master calls
//!   back from inside one of the instance's callbacks (the logger, a step-finished callback),
//!   or from another thread. The outer call holds the instance mutably; letting the inner
//!   one in would alias it, and a nested free would pull the memory from under the outer
//!   call. Such a call is refused.
//!
//! Each entry carries a `T` chosen by the layer (its logger), so that a refused nested call
//! can still be reported without reading the busy instance. A report may itself call back
//! into the FMU; a call arriving while its refusal is being reported is refused silently, so
//! a master that re-enters from every log line cannot recurse without bound.
//!
//! The registry is a fixed table of atomic words, one per live instance: its address with
//! the instance's activity in the two low bits (an instance is at least 8-aligned). Entering
//! a call is a lookup by a hash of the address and one compare-and-swap of the word, with no
//! lock: a master calls these millions of times per second. Only registering, unregistering
//! and reporting a refused nested call take a lock, around the `T` of each instance. The lock
//! is never held while the master's code runs, and the table is static memory: nothing of it
//! outlives an unloaded library.
use std::collections::BTreeMap;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, MutexGuard};

/// What an instance is doing (the low bits of its word).
const IDLE: usize = 0;
/// A call is running on the instance.
const BUSY: usize = 1;
/// A call is running and a nested call's refusal is being reported.
const REPORTING: usize = 2;
/// The activity bits of a word; the rest is the address.
const ACTIVITY: usize = 0b11;

/// Log2 of the number of slots: the live instances one layer of one FMU can hold at once.
const SLOT_BITS: u32 = 12;
/// Live instances per layer at once; `fmi2Instantiate` beyond this refuses with a log line.
pub const CAPACITY: usize = 1 << SLOT_BITS;

/// The live instances of one layer, by address.
pub struct Registry<T> {
    /// `address | activity`, or 0 for a free slot. An address lives in the first free slot
    /// at or after its home slot (wrapping), so a lookup scans from the home slot.
    slots: [AtomicUsize; CAPACITY],
    /// Each live instance's report channel; its lock also orders registrations.
    reports: Mutex<BTreeMap<usize, T>>,
}

impl<T> std::fmt::Debug for Registry<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let live = self
            .slots
            .iter()
            .filter(|s| s.load(Ordering::Relaxed) != 0)
            .count();
        f.debug_struct("Registry").field("live", &live).finish()
    }
}

/// `fmi2Instantiate`/`fmi3Instantiate*` found every slot taken.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Full;

impl std::fmt::Display for Full {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{CAPACITY} instances of this FMU are already live in this process; free one first"
        )
    }
}

/// Why [`Registry::enter`] refused a call.
#[derive(Debug)]
pub enum Refusal<'r, T: Clone> {
    /// Not a live instance: nothing may be read through the address.
    Unknown,
    /// Another call on the instance has not returned. `Some`: report the refusal through
    /// the carried value (the refusal of a call from inside that report is `None`).
    Busy(Option<Reporting<'r, T>>),
}

impl<T: Clone> Default for Registry<T> {
    fn default() -> Self {
        Self::new()
    }
}

/// The slots to look at for `address`, in order: all of them, from its home slot.
fn probe(address: usize) -> impl Iterator<Item = usize> {
    // Fibonacci hashing of the address without its alignment bits.
    let home =
        ((address as u64 >> 3).wrapping_mul(0x9E37_79B9_7F4A_7C15) >> (64 - SLOT_BITS)) as usize;
    (0..CAPACITY).map(move |k| (home + k) % CAPACITY)
}

impl<T: Clone> Registry<T> {
    pub const fn new() -> Registry<T> {
        Registry {
            slots: [const { AtomicUsize::new(0) }; CAPACITY],
            reports: Mutex::new(BTreeMap::new()),
        }
    }

    /// The reports; a panic elsewhere while they were held leaves them consistent (every
    /// update is a single map operation), so a poisoned lock is simply taken over.
    fn reports(&self) -> MutexGuard<'_, BTreeMap<usize, T>> {
        self.reports
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner())
    }

    /// The slot holding `address`, if it is live.
    #[inline]
    fn find(&self, address: usize) -> Option<usize> {
        if address == 0 || address & ACTIVITY != 0 {
            return None;
        }
        probe(address).find(|&i| self.slots[i].load(Ordering::Acquire) & !ACTIVITY == address)
    }

    /// Registers a new instance at `address` (non-null, 4-aligned), idle.
    pub fn insert(&self, address: usize, report: T) -> Result<(), Full> {
        assert!(
            address != 0 && address & ACTIVITY == 0,
            "unaligned instance"
        );
        let mut reports = self.reports();
        let free = probe(address)
            .find(|&i| self.slots[i].load(Ordering::Acquire) == 0)
            .ok_or(Full)?;
        reports.insert(address, report);
        self.slots[free].store(address | IDLE, Ordering::Release);
        Ok(())
    }

    pub fn is_live(&self, address: usize) -> bool {
        self.find(address).is_some()
    }

    /// Marks the instance at `address` busy for the duration of the returned guard, or says
    /// why the call must be refused.
    #[inline]
    pub fn enter(&self, address: usize) -> Result<Entered<'_, T>, Refusal<'_, T>> {
        let slot = self.find(address).ok_or(Refusal::Unknown)?;
        match self.slots[slot].compare_exchange(
            address | IDLE,
            address | BUSY,
            Ordering::AcqRel,
            Ordering::Acquire,
        ) {
            Ok(_) => Ok(Entered {
                registry: self,
                slot,
                address,
                removed: false,
            }),
            Err(now) => Err(self.refusal(slot, address, now)),
        }
    }

    /// Why a call on the instance at `slot` found it `now` instead of idle.
    #[cold]
    #[inline(never)]
    fn refusal(&self, slot: usize, address: usize, now: usize) -> Refusal<'_, T> {
        let word = &self.slots[slot];
        if now & !ACTIVITY != address {
            // Freed by another thread since the lookup.
            return Refusal::Unknown;
        }
        if word
            .compare_exchange(
                address | BUSY,
                address | REPORTING,
                Ordering::AcqRel,
                Ordering::Acquire,
            )
            .is_err()
        {
            return Refusal::Busy(None);
        }
        let Some(report) = self.reports().get(&address).cloned() else {
            // Unregistered since the lookup: nobody left to report to.
            let _ = word.compare_exchange(
                address | REPORTING,
                address | BUSY,
                Ordering::AcqRel,
                Ordering::Acquire,
            );
            return Refusal::Busy(None);
        };
        Refusal::Busy(Some(Reporting {
            registry: self,
            slot,
            address,
            report,
        }))
    }
}

/// A call in progress on a live instance; the instance is idle again when this drops.
#[derive(Debug)]
pub struct Entered<'r, T: Clone> {
    registry: &'r Registry<T>,
    slot: usize,
    address: usize,
    removed: bool,
}

impl<T: Clone> Entered<'_, T> {
    /// Unregisters the instance (its free): every later call with its address is refused.
    pub fn remove(mut self) {
        let mut reports = self.registry.reports();
        reports.remove(&self.address);
        self.registry.slots[self.slot].store(0, Ordering::Release);
        // An emptied BTreeMap keeps its root node; a fresh one owns no memory, so nothing of
        // ours outlives the last instance (and the library's unloading).
        if reports.is_empty() {
            *reports = BTreeMap::new();
        }
        drop(reports);
        self.removed = true;
    }
}

impl<T: Clone> Drop for Entered<'_, T> {
    fn drop(&mut self) {
        if !self.removed {
            // Busy, or Reporting if a nested refusal's report is still held: either way the
            // call is over.
            self.registry.slots[self.slot].store(self.address | IDLE, Ordering::Release);
        }
    }
}

/// The channel to report a refused nested call: while it lives, calls on the instance are
/// refused silently.
#[derive(Debug)]
pub struct Reporting<'r, T: Clone> {
    registry: &'r Registry<T>,
    slot: usize,
    address: usize,
    report: T,
}

impl<T: Clone> std::ops::Deref for Reporting<'_, T> {
    type Target = T;
    fn deref(&self) -> &T {
        &self.report
    }
}

impl<T: Clone> Drop for Reporting<'_, T> {
    fn drop(&mut self) {
        // Back to Busy, unless the outer call has ended (or freed the instance) meanwhile.
        let _ = self.registry.slots[self.slot].compare_exchange(
            self.address | REPORTING,
            self.address | BUSY,
            Ordering::AcqRel,
            Ordering::Acquire,
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_unknown_or_removed_address_is_refused_without_a_report() {
        let registry = Registry::<&str>::new();
        assert!(matches!(registry.enter(8), Err(Refusal::Unknown)));
        registry.insert(8, "log").unwrap();
        registry.enter(8).unwrap().remove();
        assert!(!registry.is_live(8));
        assert!(matches!(registry.enter(8), Err(Refusal::Unknown)));
    }

    #[test]
    fn a_nested_call_is_refused_and_reported_once_per_level() {
        let registry = Registry::<&str>::new();
        registry.insert(16, "log").unwrap();
        let outer = registry.enter(16).unwrap();
        {
            // The nested call gets the report channel...
            let Err(Refusal::Busy(Some(report))) = registry.enter(16) else {
                panic!("nested call not refused with a report")
            };
            assert_eq!(*report, "log");
            // ...and a call from inside that report is refused silently.
            assert!(matches!(registry.enter(16), Err(Refusal::Busy(None))));
        }
        // After the report, a further nested call is reported again.
        assert!(matches!(registry.enter(16), Err(Refusal::Busy(Some(_)))));
        drop(outer);
        // After the outer call, the instance is idle.
        drop(registry.enter(16).unwrap());
    }

    #[test]
    fn a_free_during_a_nested_report_leaves_nothing_behind() {
        let registry = Registry::<&str>::new();
        registry.insert(24, "log").unwrap();
        let outer = registry.enter(24).unwrap();
        let nested = registry.enter(24);
        outer.remove();
        drop(nested);
        assert!(!registry.is_live(24));
    }

    /// Addresses whose home slot is the same, so each lands one slot further on.
    fn colliding(count: usize) -> Vec<usize> {
        let home = |a: usize| probe(a).next().unwrap();
        let first = home(8);
        (1..)
            .map(|k| 8 * k)
            .filter(|&a| home(a) == first)
            .take(count)
            .collect()
    }

    #[test]
    fn colliding_addresses_stay_apart_and_a_freed_one_hides_none() {
        let registry = Registry::<usize>::new();
        let addresses = colliding(3);
        for &a in &addresses {
            registry.insert(a, a).unwrap();
        }
        // Freeing the middle one leaves a hole in the chain; the last is still found.
        registry.enter(addresses[1]).unwrap().remove();
        assert!(matches!(
            registry.enter(addresses[1]),
            Err(Refusal::Unknown)
        ));
        let last = registry.enter(addresses[2]).unwrap();
        let Err(Refusal::Busy(Some(report))) = registry.enter(addresses[2]) else {
            panic!("the busy instance was not refused with its own report")
        };
        assert_eq!(*report, addresses[2]);
        drop(report);
        drop(last);
        // The hole is reused, and each address keeps its own activity.
        registry.insert(addresses[1], 0).unwrap();
        let first = registry.enter(addresses[0]).unwrap();
        drop(registry.enter(addresses[1]).unwrap());
        drop(registry.enter(addresses[2]).unwrap());
        drop(first);
    }

    #[test]
    fn a_full_table_refuses_one_more_until_one_is_freed() {
        let registry = Registry::<()>::new();
        let addresses: Vec<usize> = (1..=CAPACITY).map(|k| 8 * k).collect();
        for &a in &addresses {
            registry.insert(a, ()).unwrap();
        }
        let extra = 8 * (CAPACITY + 1);
        assert_eq!(registry.insert(extra, ()), Err(Full));
        assert!(matches!(registry.enter(extra), Err(Refusal::Unknown)));
        assert!(addresses.iter().all(|&a| registry.is_live(a)));
        registry.enter(addresses[CAPACITY / 2]).unwrap().remove();
        registry.insert(extra, ()).unwrap();
        drop(registry.enter(extra).unwrap());
        assert!(!registry.is_live(addresses[CAPACITY / 2]));
    }

    #[test]
    fn null_and_unaligned_addresses_are_unknown() {
        let registry = Registry::<()>::new();
        registry.insert(64, ()).unwrap();
        for address in [0, 65, 66, 67] {
            assert!(matches!(registry.enter(address), Err(Refusal::Unknown)));
        }
    }

    /// Two threads calling on one instance: never both inside, and every refusal is Busy.
    #[test]
    fn two_threads_never_hold_one_instance_at_once() {
        use std::sync::atomic::AtomicBool;
        let registry = Registry::<()>::new();
        registry.insert(8, ()).unwrap();
        let inside = AtomicBool::new(false);
        let entered = AtomicUsize::new(0);
        std::thread::scope(|scope| {
            for _ in 0..2 {
                scope.spawn(|| {
                    for _ in 0..20_000 {
                        match registry.enter(8) {
                            Ok(guard) => {
                                assert!(!inside.swap(true, Ordering::SeqCst), "both inside");
                                entered.fetch_add(1, Ordering::Relaxed);
                                inside.store(false, Ordering::SeqCst);
                                drop(guard);
                            }
                            Err(Refusal::Busy(_)) => {}
                            Err(Refusal::Unknown) => panic!("a live instance was unknown"),
                        }
                    }
                });
            }
        });
        assert!(entered.load(Ordering::Relaxed) > 0);
        assert!(registry.is_live(8));
    }
}
