//! The live instances of an FMI layer, and which of them are inside a call.
//!
//! An FMU runs in the master's process and trusts nothing it is handed. Two hazards need
//! bookkeeping outside the instance itself:
//!
//! - A component that is not (or no longer) a live instance: a second `FreeInstance`, a call
//!   after it, or a pointer of some other object. The master is therefore never given the
//!   instance's address: it gets an opaque *handle* ([`Registry::insert`]), which nobody
//!   dereferences, and the address is known only once the registry has found the handle
//!   live ([`Entered::address`]). A handle is a slot index and that slot's *generation*;
//!   freeing an instance advances the generation, so its handle stays dead even when the
//!   allocator gives the same address to the next instance and the slot is reused for it.
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
//! The registry is a fixed table of slots, each an atomic word `generation << 2 | activity`
//! (free, idle, busy, reporting) next to an atomic holding the instance's address. Entering
//! a call is one compare-and-swap of the word the handle names, from "this generation,
//! idle" to "this generation, busy", then one load of the address, with no lock: a master
//! calls these millions of times per second. Only registering, unregistering and reporting
//! a refused nested call take a lock, around the `T` of each instance. The lock is never
//! held while the master's code runs, and the table is static memory: nothing of it outlives
//! an unloaded library.
//!
//! A slot's generation starts at a random value the first time the slot is used, and then
//! counts up by one per instance (wrapping past 0, which no handle has). So:
//!
//! - a freed instance's handle comes back only after `2^(usize::BITS - 12) - 1` (2^52 on a
//!   64-bit target) later instances in its slot;
//! - a handle of another registry (another FMU in the process, or this library before it
//!   was unloaded and loaded again at the same address), or any other value a master makes
//!   up, names a live instance only by chance: its generation must equal that slot's;
//! - no handle is 0, and two live instances never share one (distinct slots).
use std::collections::BTreeMap;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, MutexGuard};

/// What a slot is doing (the low bits of its word). Free is 0 so that a new table is empty.
const FREE: usize = 0;
/// An instance is registered and no call is running on it.
const IDLE: usize = 1;
/// A call is running on the instance.
const BUSY: usize = 2;
/// A call is running and a nested call's refusal is being reported.
const REPORTING: usize = 3;
/// The activity bits of a word; the rest is the generation.
const ACTIVITY: usize = 0b11;
/// Bits of a word below the generation.
const ACTIVITY_BITS: u32 = 2;

/// Log2 of the number of slots: the live instances one layer of one FMU can hold at once.
const SLOT_BITS: u32 = 12;
/// Live instances per layer at once; `fmi2Instantiate` beyond this refuses with a log line.
pub const CAPACITY: usize = 1 << SLOT_BITS;
/// The slot index bits of a handle; the rest is the generation.
const INDEX: usize = CAPACITY - 1;
/// The largest generation (all the bits of a handle above the index).
const LAST_GENERATION: usize = usize::MAX >> SLOT_BITS;

/// The generation after `generation`: one more, past the last back to 1 (0 is never live).
const fn next_generation(generation: usize) -> usize {
    if generation >= LAST_GENERATION {
        1
    } else {
        generation + 1
    }
}

/// The handle of generation `generation` (non-zero) of slot `index`.
const fn handle_of(index: usize, generation: usize) -> usize {
    generation << SLOT_BITS | index
}

/// The word of a slot holding generation `generation` doing `activity`.
const fn word(generation: usize, activity: usize) -> usize {
    generation << ACTIVITY_BITS | activity
}

/// A starting generation for slot `index` of the registry at `registry`, unpredictable
/// across registries and loads of the library (std's randomly keyed hasher), never 0.
fn first_generation(registry: usize, index: usize) -> usize {
    use std::hash::{BuildHasher, Hasher};
    let mut hasher = std::collections::hash_map::RandomState::new().build_hasher();
    hasher.write_usize(registry);
    hasher.write_usize(index);
    // Truncating to usize on a 32-bit target keeps bits enough for LAST_GENERATION.
    let generation = hasher.finish() as usize & LAST_GENERATION;
    generation.max(1)
}

/// One instance's place in the table.
#[derive(Debug)]
struct Slot {
    /// `generation << 2 | activity`; a free slot keeps the generation its next instance
    /// gets (0: never used, the first one draws a random generation).
    word: AtomicUsize,
    /// The instance's address while the slot is not free; written before the word makes it
    /// idle (release), read after the word was found idle (acquire).
    address: AtomicUsize,
}

/// What registering takes the lock for.
#[derive(Debug)]
struct Registered<T> {
    /// Each live instance's report channel, by handle.
    reports: BTreeMap<usize, T>,
    /// Where the search for a free slot starts: after the last one taken, so that slots are
    /// used in turn rather than the same one again and again.
    next: usize,
}

/// The live instances of one layer, by handle.
pub struct Registry<T> {
    slots: [Slot; CAPACITY],
    /// The report channels; the lock also orders registrations and removals.
    registered: Mutex<Registered<T>>,
}

impl<T> std::fmt::Debug for Registry<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let live = self
            .slots
            .iter()
            .filter(|s| s.word.load(Ordering::Relaxed) & ACTIVITY != FREE)
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
    /// Not the handle of a live instance: there is no address to read anything through.
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
            slots: [const {
                Slot {
                    word: AtomicUsize::new(word(0, FREE)),
                    address: AtomicUsize::new(0),
                }
            }; CAPACITY],
            registered: Mutex::new(Registered {
                reports: BTreeMap::new(),
                next: 0,
            }),
        }
    }

    /// The registrations; a panic elsewhere while they were held leaves them consistent
    /// (every update is a single map operation), so a poisoned lock is simply taken over.
    fn registered(&self) -> MutexGuard<'_, Registered<T>> {
        self.registered
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner())
    }

    /// Registers a new instance at `address`, idle, and returns the handle to give the
    /// master in its place (never 0, never the handle of another live instance).
    pub fn insert(&self, address: usize, report: T) -> Result<usize, Full> {
        let mut registered = self.registered();
        // Only this function, under the lock, takes a free slot: the scan cannot race.
        let (index, free) = (0..CAPACITY)
            .map(|k| (registered.next + k) % CAPACITY)
            .map(|i| (i, self.slots[i].word.load(Ordering::Acquire)))
            .find(|&(_, w)| w & ACTIVITY == FREE)
            .ok_or(Full)?;
        let generation = match free >> ACTIVITY_BITS {
            0 => first_generation(self as *const Self as usize, index),
            generation => generation,
        };
        let handle = handle_of(index, generation);
        registered.reports.insert(handle, report);
        registered.next = (index + 1) % CAPACITY;
        let slot = &self.slots[index];
        slot.address.store(address, Ordering::Relaxed);
        slot.word.store(word(generation, IDLE), Ordering::Release);
        Ok(handle)
    }

    /// Whether `handle` is a live instance's (idle or inside a call).
    pub fn is_live(&self, handle: usize) -> bool {
        let now = self.slots[handle & INDEX].word.load(Ordering::Acquire);
        now & ACTIVITY != FREE && now >> ACTIVITY_BITS == handle >> SLOT_BITS
    }

    /// Marks the instance of `handle` busy for the duration of the returned guard, or says
    /// why the call must be refused.
    #[inline]
    pub fn enter(&self, handle: usize) -> Result<Entered<'_, T>, Refusal<'_, T>> {
        let index = handle & INDEX;
        let generation = handle >> SLOT_BITS;
        let slot = &self.slots[index];
        // A handle with generation 0 (such as 0 itself) expects a word no slot ever holds.
        match slot.word.compare_exchange(
            word(generation, IDLE),
            word(generation, BUSY),
            Ordering::AcqRel,
            Ordering::Acquire,
        ) {
            Ok(_) => Ok(Entered {
                registry: self,
                handle,
                word: &slot.word,
                idle: word(generation, IDLE),
                address: slot.address.load(Ordering::Relaxed),
            }),
            Err(now) => Err(self.refusal(handle, now)),
        }
    }

    /// [`enter`](Self::enter) for a call's fast path: the instance of `handle` marked busy
    /// until [`Quick::leave`], or `None` (nothing changed) for anything but a live, idle
    /// instance, whose refusal the caller leaves to `enter`. No guard drops it: the fast
    /// path has no landing pad and leaves on every way out.
    #[inline(always)]
    pub fn try_enter(&self, handle: usize) -> Option<Quick<'_>> {
        let generation = handle >> SLOT_BITS;
        // Always a slot (`handle & INDEX` is below CAPACITY): `get` only keeps a panic out.
        let slot = self.slots.get(handle & INDEX)?;
        let idle = word(generation, IDLE);
        slot.word
            .compare_exchange(
                idle,
                word(generation, BUSY),
                Ordering::AcqRel,
                Ordering::Relaxed,
            )
            .ok()?;
        Some(Quick {
            word: &slot.word,
            idle,
            address: slot.address.load(Ordering::Relaxed),
        })
    }

    /// Why a call with `handle` found its slot's word `now` instead of idle.
    #[cold]
    #[inline(never)]
    fn refusal(&self, handle: usize, now: usize) -> Refusal<'_, T> {
        let generation = handle >> SLOT_BITS;
        if now >> ACTIVITY_BITS != generation || now & ACTIVITY == FREE {
            // Freed, never handed out, or another registry's.
            return Refusal::Unknown;
        }
        let word_of = &self.slots[handle & INDEX].word;
        if word_of
            .compare_exchange(
                word(generation, BUSY),
                word(generation, REPORTING),
                Ordering::AcqRel,
                Ordering::Acquire,
            )
            .is_err()
        {
            return Refusal::Busy(None);
        }
        let Some(report) = self.registered().reports.get(&handle).cloned() else {
            // Unregistered since: nobody left to report to.
            let _ = word_of.compare_exchange(
                word(generation, REPORTING),
                word(generation, BUSY),
                Ordering::AcqRel,
                Ordering::Acquire,
            );
            return Refusal::Busy(None);
        };
        Refusal::Busy(Some(Reporting {
            registry: self,
            handle,
            report,
        }))
    }
}

/// A call in progress on a live instance; the instance is idle again when this drops.
#[derive(Debug)]
pub struct Entered<'r, T: Clone> {
    registry: &'r Registry<T>,
    handle: usize,
    /// The slot's word and its idle value, kept so that the end of a call is one store.
    word: &'r AtomicUsize,
    idle: usize,
    address: usize,
}

impl<T: Clone> Entered<'_, T> {
    /// The address registered with the instance: what the layer reads the instance through.
    #[inline]
    pub fn address(&self) -> usize {
        self.address
    }

    /// The handle the call came with.
    pub fn handle(&self) -> usize {
        self.handle
    }

    /// Unregisters the instance (its free): its handle is refused from now on, whichever
    /// instance its slot and address hold next.
    pub fn remove(self) {
        // Not idle again at its end: the slot is free (no flag for `drop` to test).
        let this = std::mem::ManuallyDrop::new(self);
        let mut registered = this.registry.registered();
        registered.reports.remove(&this.handle);
        let slot = &this.registry.slots[this.handle & INDEX];
        let next = next_generation(this.handle >> SLOT_BITS);
        slot.address.store(0, Ordering::Relaxed);
        slot.word.store(word(next, FREE), Ordering::Release);
        // An emptied BTreeMap keeps its root node; a fresh one owns no memory, so nothing of
        // ours outlives the last instance (and the library's unloading).
        if registered.reports.is_empty() {
            registered.reports = BTreeMap::new();
        }
        drop(registered);
    }
}

impl<T: Clone> Drop for Entered<'_, T> {
    #[inline(always)]
    fn drop(&mut self) {
        // Busy, or Reporting if a nested refusal's report is still held: either way the
        // call is over.
        self.word.store(self.idle, Ordering::Release);
    }
}

/// A call's fast path in progress on a live instance ([`Registry::try_enter`]): idle again
/// at [`leave`](Quick::leave), which every way out of the fast path calls.
#[derive(Debug)]
#[must_use = "the instance stays busy until `leave`"]
pub struct Quick<'r> {
    word: &'r AtomicUsize,
    idle: usize,
    address: usize,
}

impl Quick<'_> {
    /// The address registered with the instance.
    #[inline(always)]
    pub fn address(&self) -> usize {
        self.address
    }

    /// The call is over: the instance is idle again.
    #[inline(always)]
    pub fn leave(self) {
        self.word.store(self.idle, Ordering::Release);
    }
}

/// The channel to report a refused nested call: while it lives, calls on the instance are
/// refused silently.
#[derive(Debug)]
pub struct Reporting<'r, T: Clone> {
    registry: &'r Registry<T>,
    handle: usize,
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
        let generation = self.handle >> SLOT_BITS;
        let _ = self.registry.slots[self.handle & INDEX]
            .word
            .compare_exchange(
                word(generation, REPORTING),
                word(generation, BUSY),
                Ordering::AcqRel,
                Ordering::Acquire,
            );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Sets every free slot's next generation, as if each had served that many instances.
    fn age(registry: &Registry<impl Clone>, generation: usize) {
        for slot in &registry.slots {
            assert_eq!(slot.word.load(Ordering::Relaxed) & ACTIVITY, FREE);
            slot.word.store(word(generation, FREE), Ordering::Relaxed);
        }
    }

    #[test]
    fn an_unknown_or_removed_handle_is_refused_without_a_report() {
        let registry = Registry::<&str>::new();
        assert!(matches!(registry.enter(8), Err(Refusal::Unknown)));
        let handle = registry.insert(8, "log").unwrap();
        assert_ne!(handle, 0);
        assert!(registry.is_live(handle));
        let entered = registry.enter(handle).unwrap();
        assert_eq!((entered.address(), entered.handle()), (8, handle));
        entered.remove();
        assert!(!registry.is_live(handle));
        assert!(matches!(registry.enter(handle), Err(Refusal::Unknown)));
    }

    #[test]
    fn a_stale_handle_is_refused_when_its_slot_and_address_are_reused() {
        let registry = Registry::<usize>::new();
        // Every slot but one taken, so the instance after the free gets the same slot.
        let others: Vec<usize> = (1..CAPACITY).map(|k| 16 * k).collect();
        for &a in &others {
            registry.insert(a, a).unwrap();
        }
        let address = 0x1000;
        let stale = registry.insert(address, 1).unwrap();
        registry.enter(stale).unwrap().remove();
        let fresh = registry.insert(address, 2).unwrap();
        assert_eq!(fresh & INDEX, stale & INDEX, "the slot was not reused");
        assert_ne!(fresh, stale);
        assert!(!registry.is_live(stale));
        assert!(matches!(registry.enter(stale), Err(Refusal::Unknown)));
        // Refused while the new instance is busy too, and without its report.
        let busy = registry.enter(fresh).unwrap();
        assert!(matches!(registry.enter(stale), Err(Refusal::Unknown)));
        let Err(Refusal::Busy(Some(report))) = registry.enter(fresh) else {
            panic!("the busy instance was not refused with its report")
        };
        assert_eq!(*report, 2);
        drop(report);
        assert_eq!(busy.address(), address);
        drop(busy);
        assert_eq!(registry.enter(fresh).unwrap().address(), address);
    }

    #[test]
    fn a_stale_handle_stays_dead_over_many_reuses_of_its_slot() {
        let registry = Registry::<()>::new();
        let mut freed = std::collections::HashSet::new();
        for _ in 0..3 * CAPACITY {
            let handle = registry.insert(64, ()).unwrap();
            assert!(!freed.contains(&handle), "a freed handle came back");
            registry.enter(handle).unwrap().remove();
            freed.insert(handle);
        }
        // Every slot served three instances; none of their handles enters.
        assert!(freed.iter().all(|&h| !registry.is_live(h)));
        assert!(freed
            .iter()
            .all(|&h| matches!(registry.enter(h), Err(Refusal::Unknown))));
    }

    #[test]
    fn the_generation_wraps_past_zero_and_the_old_handle_stays_dead() {
        let registry = Registry::<()>::new();
        age(&registry, LAST_GENERATION);
        let last = registry.insert(8, ()).unwrap();
        assert_eq!(last >> SLOT_BITS, LAST_GENERATION);
        assert_eq!(next_generation(LAST_GENERATION), 1);
        registry.enter(last).unwrap().remove();
        // The slot's next instance, generation 1: a non-zero handle, not the old one.
        let word_now = registry.slots[last & INDEX].word.load(Ordering::Relaxed);
        assert_eq!(word_now, word(1, FREE));
        let first = (0..CAPACITY)
            .map(|_| registry.insert(8, ()).unwrap())
            .find(|&h| h & INDEX == last & INDEX)
            .unwrap();
        assert_eq!(first, handle_of(last & INDEX, 1));
        assert_ne!(first, 0);
        assert!(matches!(registry.enter(last), Err(Refusal::Unknown)));
        drop(registry.enter(first).unwrap());
    }

    #[test]
    fn first_generations_differ_between_registries() {
        let (a, b) = (Registry::<()>::new(), Registry::<()>::new());
        let handles_a: Vec<usize> = (0..8).map(|_| a.insert(8, ()).unwrap()).collect();
        let handles_b: Vec<usize> = (0..8).map(|_| b.insert(8, ()).unwrap()).collect();
        // Same slots, drawn generations: a handle of one registry is unknown to the other.
        for (&ha, &hb) in handles_a.iter().zip(&handles_b) {
            assert_eq!(ha & INDEX, hb & INDEX);
            assert_ne!(ha, hb);
            assert!(matches!(a.enter(hb), Err(Refusal::Unknown)));
            assert!(matches!(b.enter(ha), Err(Refusal::Unknown)));
        }
    }

    #[test]
    fn a_nested_call_is_refused_and_reported_once_per_level() {
        let registry = Registry::<&str>::new();
        let handle = registry.insert(16, "log").unwrap();
        let outer = registry.enter(handle).unwrap();
        {
            // The nested call gets the report channel...
            let Err(Refusal::Busy(Some(report))) = registry.enter(handle) else {
                panic!("nested call not refused with a report")
            };
            assert_eq!(*report, "log");
            // ...and a call from inside that report is refused silently.
            assert!(matches!(registry.enter(handle), Err(Refusal::Busy(None))));
        }
        // After the report, a further nested call is reported again.
        assert!(matches!(
            registry.enter(handle),
            Err(Refusal::Busy(Some(_)))
        ));
        drop(outer);
        // After the outer call, the instance is idle.
        drop(registry.enter(handle).unwrap());
    }

    #[test]
    fn a_free_during_a_nested_report_leaves_nothing_behind() {
        let registry = Registry::<&str>::new();
        let handle = registry.insert(24, "log").unwrap();
        let outer = registry.enter(handle).unwrap();
        let nested = registry.enter(handle);
        assert!(matches!(nested, Err(Refusal::Busy(Some(_)))));
        outer.remove();
        drop(nested);
        assert!(!registry.is_live(handle));
        assert!(registry.registered().reports.is_empty());
        assert!(registry
            .slots
            .iter()
            .all(|s| s.word.load(Ordering::Relaxed) & ACTIVITY == FREE));
    }

    #[test]
    fn instances_at_one_address_or_in_neighbouring_slots_stay_apart() {
        let registry = Registry::<usize>::new();
        // The layer never registers one address twice, but the registry does not care:
        // each registration is its own handle, activity and report.
        let handles: Vec<usize> = (0..3).map(|k| registry.insert(8, k).unwrap()).collect();
        assert_eq!(handles.len(), 3);
        assert!(handles.iter().all(|&h| h != 0));
        registry.enter(handles[1]).unwrap().remove();
        assert!(matches!(registry.enter(handles[1]), Err(Refusal::Unknown)));
        let last = registry.enter(handles[2]).unwrap();
        let Err(Refusal::Busy(Some(report))) = registry.enter(handles[2]) else {
            panic!("the busy instance was not refused with its own report")
        };
        assert_eq!(*report, 2);
        drop(report);
        // Its neighbour is idle while it is busy.
        drop(registry.enter(handles[0]).unwrap());
        drop(last);
        assert_eq!(registry.enter(handles[2]).unwrap().address(), 8);
    }

    #[test]
    fn made_up_handles_are_unknown() {
        let registry = Registry::<()>::new();
        // An odd address is as good as any: only the handle is checked.
        let handle = registry.insert(65, ()).unwrap();
        let made_up = [
            0,
            1,
            8,
            usize::MAX,
            handle & INDEX,
            handle ^ 1,
            handle + CAPACITY,
            handle - CAPACITY,
            handle ^ 1 << (usize::BITS - 1),
            65,
        ];
        for h in made_up {
            assert!(matches!(registry.enter(h), Err(Refusal::Unknown)), "{h:#x}");
            assert!(!registry.is_live(h));
        }
        assert_eq!(registry.enter(handle).unwrap().address(), 65);
    }

    #[test]
    fn a_full_table_refuses_one_more_until_one_is_freed() {
        let registry = Registry::<()>::new();
        let handles: Vec<usize> = (1..=CAPACITY)
            .map(|k| registry.insert(8 * k, ()).unwrap())
            .collect();
        let distinct: std::collections::HashSet<_> = handles.iter().collect();
        assert_eq!(distinct.len(), CAPACITY);
        let extra = 8 * (CAPACITY + 1);
        assert_eq!(registry.insert(extra, ()), Err(Full));
        assert!(handles.iter().all(|&h| registry.is_live(h)));
        let freed = handles[CAPACITY / 2];
        registry.enter(freed).unwrap().remove();
        let handle = registry.insert(extra, ()).unwrap();
        assert_eq!(registry.enter(handle).unwrap().address(), extra);
        assert!(!registry.is_live(freed));
        assert_eq!(registry.insert(extra, ()), Err(Full));
    }

    /// Two threads calling on one instance: never both inside, and every refusal is Busy.
    #[test]
    fn two_threads_never_hold_one_instance_at_once() {
        use std::sync::atomic::AtomicBool;
        let registry = Registry::<()>::new();
        let handle = registry.insert(8, ()).unwrap();
        let inside = AtomicBool::new(false);
        let entered = AtomicUsize::new(0);
        std::thread::scope(|scope| {
            for _ in 0..2 {
                scope.spawn(|| {
                    for _ in 0..20_000 {
                        match registry.enter(handle) {
                            Ok(guard) => {
                                assert!(!inside.swap(true, Ordering::SeqCst), "both inside");
                                assert_eq!(guard.address(), 8);
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
        assert!(registry.is_live(handle));
    }

    /// One thread frees and re-registers instances at one address in a single free slot,
    /// the other calls with the handles it has seen freed: none of them ever enters, and a
    /// live handle always finds its own address.
    #[test]
    fn stale_handles_never_enter_while_another_thread_reuses_the_slot() {
        use std::sync::atomic::AtomicBool;
        use std::sync::Mutex;
        let registry = Registry::<usize>::new();
        // All slots but one taken: every new instance lands in the same slot.
        for k in 1..CAPACITY {
            registry.insert(16 * k, 0).unwrap();
        }
        let freed = Mutex::new(Vec::new());
        let done = AtomicBool::new(false);
        std::thread::scope(|scope| {
            scope.spawn(|| {
                for n in 0..5_000 {
                    let handle = registry.insert(0x10_0000, n).unwrap();
                    let entered = registry.enter(handle).unwrap();
                    assert_eq!(entered.address(), 0x10_0000);
                    entered.remove();
                    freed.lock().unwrap().push(handle);
                }
                done.store(true, Ordering::SeqCst);
            });
            scope.spawn(|| {
                while !done.load(Ordering::SeqCst) {
                    let stale: Vec<usize> = freed
                        .lock()
                        .unwrap()
                        .iter()
                        .rev()
                        .take(4)
                        .copied()
                        .collect();
                    for h in stale {
                        assert!(
                            matches!(registry.enter(h), Err(Refusal::Unknown)),
                            "a freed handle entered"
                        );
                    }
                }
            });
        });
        let freed = freed.into_inner().unwrap();
        let distinct: std::collections::HashSet<_> = freed.iter().collect();
        assert_eq!(distinct.len(), freed.len());
    }
}
