//! A global allocator that forwards to the system allocator and counts.
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicIsize, Ordering};

/// Install with `#[global_allocator] static A: CountingAllocator = CountingAllocator::new();`
/// in a test binary with one test (so that nothing else allocates meanwhile).
#[derive(Debug)]
pub struct CountingAllocator {
    live: AtomicIsize,
    peak: AtomicIsize,
}

impl CountingAllocator {
    pub const fn new() -> CountingAllocator {
        CountingAllocator {
            live: AtomicIsize::new(0),
            peak: AtomicIsize::new(0),
        }
    }

    /// Bytes allocated and not freed.
    pub fn live(&self) -> isize {
        self.live.load(Ordering::SeqCst)
    }

    /// Highest `live` since the last [`reset_peak`](Self::reset_peak).
    pub fn peak(&self) -> isize {
        self.peak.load(Ordering::SeqCst)
    }

    /// Starts a new peak measurement at the current live bytes.
    pub fn reset_peak(&self) {
        self.peak.store(self.live(), Ordering::SeqCst);
    }
}

/// What [`CountingAllocator::measure`] saw, in bytes relative to the start.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct HeapUse {
    /// Held by the object after it was exercised, before it was dropped.
    pub held: isize,
    /// The highest point while it lived.
    pub peak: isize,
    /// Still allocated after it was dropped (0 when it frees everything).
    pub after: isize,
}

impl CountingAllocator {
    /// Creates an object, exercises it, drops it, and reports its heap use. The first
    /// measurement in a process also counts what the process sets up once (output capture,
    /// thread data): measure twice and judge the second.
    pub fn measure<T>(&self, create: impl FnOnce() -> T, exercise: impl FnOnce(&T)) -> HeapUse {
        let before = self.live();
        self.reset_peak();
        let object = create();
        exercise(&object);
        let held = self.live() - before;
        drop(object);
        HeapUse {
            held,
            peak: self.peak() - before,
            after: self.live() - before,
        }
    }
}

impl Default for CountingAllocator {
    fn default() -> Self {
        Self::new()
    }
}

// SAFETY: forwards every call to the system allocator unchanged; only counts.
unsafe impl GlobalAlloc for CountingAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            let size = layout.size() as isize;
            let live = self.live.fetch_add(size, Ordering::SeqCst) + size;
            self.peak.fetch_max(live, Ordering::SeqCst);
        }
        p
    }

    unsafe fn dealloc(&self, p: *mut u8, layout: Layout) {
        unsafe { System.dealloc(p, layout) };
        self.live
            .fetch_sub(layout.size() as isize, Ordering::SeqCst);
    }
}
