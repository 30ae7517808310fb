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
//! The registry is a lock around an ordered map: one uncontended lock and one lookup per
//! call, and never held while the master's code runs.
use std::collections::BTreeMap;
use std::sync::{Mutex, MutexGuard};

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Activity {
    Idle,
    /// A call is running on the instance.
    Busy,
    /// A call is running and a nested call's refusal is being reported.
    Reporting,
}

#[derive(Debug)]
struct Slot<T> {
    activity: Activity,
    report: T,
}

/// The live instances of a layer (one `static` per layer), keyed by address.
#[derive(Debug)]
pub struct Registry<T> {
    live: Mutex<BTreeMap<usize, Slot<T>>>,
}

/// Why a call may not use an instance.
#[derive(Debug)]
pub enum Refusal<'r, T: Clone> {
    /// No live instance has this address (never instantiated, or already freed): nothing
    /// may be read through it, and there is no logger to tell.
    Unknown,
    /// Another call on the instance has not returned. `Some` carries the instance's report
    /// channel, to be used before the guard is dropped; `None` when a refusal is already
    /// being reported (stay silent).
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

    /// The map, also after a panic elsewhere poisoned the lock (every update is one insert,
    /// remove or field store, so the map is never half-written).
    fn map(&self) -> MutexGuard<'_, BTreeMap<usize, Slot<T>>> {
        self.live
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner())
    }

    /// Registers a new instance at `address`, idle.
    pub fn insert(&self, address: usize, report: T) {
        self.map().insert(
            address,
            Slot {
                activity: Activity::Idle,
                report,
            },
        );
    }

    /// Whether `address` is a live instance.
    pub fn is_live(&self, address: usize) -> bool {
        self.map().contains_key(&address)
    }

    /// Marks the instance at `address` busy for the lifetime of the returned guard.
    pub fn enter(&self, address: usize) -> Result<Entered<'_, T>, Refusal<'_, T>> {
        let mut map = self.map();
        let slot = map.get_mut(&address).ok_or(Refusal::Unknown)?;
        match slot.activity {
            Activity::Idle => {
                slot.activity = Activity::Busy;
                Ok(Entered {
                    registry: self,
                    address,
                    removed: false,
                })
            }
            Activity::Busy => {
                slot.activity = Activity::Reporting;
                Err(Refusal::Busy(Some(Reporting {
                    registry: self,
                    address,
                    report: slot.report.clone(),
                })))
            }
            Activity::Reporting => Err(Refusal::Busy(None)),
        }
    }

    /// Sets the activity of a live instance, if it is one of `from`.
    fn set(&self, address: usize, from: &[Activity], to: Activity) {
        if let Some(slot) = self.map().get_mut(&address) {
            if from.contains(&slot.activity) {
                slot.activity = to;
            }
        }
    }
}

/// A running call on a live instance; dropping it makes the instance idle again.
#[derive(Debug)]
pub struct Entered<'r, T: Clone> {
    registry: &'r Registry<T>,
    address: usize,
    removed: bool,
}

impl<T: Clone> Entered<'_, T> {
    /// Unregisters the instance (it is about to be freed): from now on its address is
    /// [`Refusal::Unknown`], also to a nested call still running and to a second free.
    pub fn remove(mut self) {
        let mut map = self.registry.map();
        map.remove(&self.address);
        if map.is_empty() {
            // An emptied BTreeMap keeps its root node; the registry is a static of the FMU's
            // library, so that node would outlive a master's dlclose and leak once per load.
            *map = BTreeMap::new();
        }
        drop(map);
        self.removed = true;
    }
}

impl<T: Clone> Drop for Entered<'_, T> {
    fn drop(&mut self) {
        if !self.removed {
            let running = [Activity::Busy, Activity::Reporting];
            self.registry.set(self.address, &running, Activity::Idle);
        }
    }
}

/// The report channel of a busy instance while a nested call's refusal is reported;
/// dropping it lets the next nested call be reported again.
#[derive(Debug)]
pub struct Reporting<'r, T: Clone> {
    registry: &'r Registry<T>,
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
        // Back to Busy: the outer call is still running, unless it ended meanwhile (a nested
        // call from another thread) or freed the instance; then there is nothing to restore.
        let reporting = [Activity::Reporting];
        self.registry.set(self.address, &reporting, Activity::Busy);
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
