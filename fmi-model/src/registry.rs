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
//! The registry is a lock around an ordered map of shared slots: entering a call takes the
//! lock once for the lookup; the call's activity lives in the slot as an atomic, so leaving
//! the call needs neither the lock nor a second lookup. The lock is never held while the
//! master's code runs.
use std::collections::BTreeMap;
use std::sync::atomic::{AtomicU8, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};

/// What a slot's instance is doing (the values of `Slot::activity`).
const IDLE: u8 = 0;
/// A call is running on the instance.
const BUSY: u8 = 1;
/// A call is running and a nested call's refusal is being reported.
const REPORTING: u8 = 2;

/// An instance's activity, shared between the map and the guards of its calls.
#[derive(Debug, Default)]
struct Activity(AtomicU8);

impl Activity {
    /// Moves the activity from `from` to `to`; false if it was not `from`.
    fn change(&self, from: u8, to: u8) -> bool {
        self.0
            .compare_exchange(from, to, Ordering::AcqRel, Ordering::Acquire)
            .is_ok()
    }
}

#[derive(Debug)]
struct Slot<T> {
    activity: Arc<Activity>,
    report: T,
}

/// The live instances of one layer, by address.
#[derive(Debug)]
pub struct Registry<T> {
    live: Mutex<BTreeMap<usize, Slot<T>>>,
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

impl<T: Clone> Registry<T> {
    pub const fn new() -> Registry<T> {
        Registry {
            live: Mutex::new(BTreeMap::new()),
        }
    }

    /// The map; a panic elsewhere while it was held leaves it consistent (every update is
    /// a single map operation), so a poisoned lock is simply taken over.
    fn map(&self) -> MutexGuard<'_, BTreeMap<usize, Slot<T>>> {
        self.live
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner())
    }

    /// Registers a new instance at `address`, idle.
    pub fn insert(&self, address: usize, report: T) {
        let slot = Slot {
            activity: Arc::new(Activity(AtomicU8::new(IDLE))),
            report,
        };
        self.map().insert(address, slot);
    }

    pub fn is_live(&self, address: usize) -> bool {
        self.map().contains_key(&address)
    }

    /// Marks the instance at `address` busy for the duration of the returned guard, or says
    /// why the call must be refused.
    pub fn enter(&self, address: usize) -> Result<Entered<'_, T>, Refusal<'_, T>> {
        let map = self.map();
        let slot = map.get(&address).ok_or(Refusal::Unknown)?;
        let activity = Arc::clone(&slot.activity);
        if activity.change(IDLE, BUSY) {
            return Ok(Entered {
                registry: self,
                address,
                activity,
                removed: false,
            });
        }
        if activity.change(BUSY, REPORTING) {
            return Err(Refusal::Busy(Some(Reporting {
                _registry: std::marker::PhantomData,
                report: slot.report.clone(),
                activity,
            })));
        }
        Err(Refusal::Busy(None))
    }
}

/// A call in progress on a live instance; the instance is idle again when this drops.
#[derive(Debug)]
pub struct Entered<'r, T: Clone> {
    registry: &'r Registry<T>,
    address: usize,
    activity: Arc<Activity>,
    removed: bool,
}

impl<T: Clone> Entered<'_, T> {
    /// Unregisters the instance (its free): every later call with its address is refused.
    pub fn remove(mut self) {
        let mut map = self.registry.map();
        map.remove(&self.address);
        // An emptied BTreeMap keeps its root node; a fresh one owns no memory, so nothing of
        // ours outlives the last instance (and the library's unloading).
        if map.is_empty() {
            *map = BTreeMap::new();
        }
        drop(map);
        self.removed = true;
    }
}

impl<T: Clone> Drop for Entered<'_, T> {
    fn drop(&mut self) {
        if !self.removed {
            // Busy, or Reporting if a nested refusal's report is still held: either way the
            // call is over.
            self.activity.0.store(IDLE, Ordering::Release);
        }
    }
}

/// The channel to report a refused nested call: while it lives, calls on the instance are
/// refused silently.
#[derive(Debug)]
pub struct Reporting<'r, T: Clone> {
    _registry: std::marker::PhantomData<&'r Registry<T>>,
    activity: Arc<Activity>,
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
        // Back to Busy, unless the outer call has ended meanwhile.
        self.activity.change(REPORTING, BUSY);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_unknown_or_removed_address_is_refused_without_a_report() {
        let registry = Registry::<&str>::new();
        assert!(matches!(registry.enter(8), Err(Refusal::Unknown)));
        registry.insert(8, "log");
        registry.enter(8).unwrap().remove();
        assert!(!registry.is_live(8));
        assert!(matches!(registry.enter(8), Err(Refusal::Unknown)));
    }

    #[test]
    fn a_nested_call_is_refused_and_reported_once_per_level() {
        let registry = Registry::<&str>::new();
        registry.insert(16, "log");
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
        registry.insert(24, "log");
        let outer = registry.enter(24).unwrap();
        let nested = registry.enter(24);
        outer.remove();
        drop(nested);
        assert!(!registry.is_live(24));
    }
}
