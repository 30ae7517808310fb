//! A global allocator that forwards to the system allocator and counts what the measuring
//! thread allocates and frees.
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::atomic::{AtomicIsize, Ordering};

thread_local! {
    /// Whether this thread's allocations are counted: only the thread inside
    /// [`CountingAllocator::measure`]'s is. The test harness's own threads allocate when
    /// they are scheduled (the main thread books a started test after the test thread has
    /// begun), which would otherwise land in a measurement at random. Const-initialised and
    /// without a destructor, so reading it never allocates.
    static COUNTED: Cell<bool> = const { Cell::new(false) };
}

fn counted() -> bool {
    COUNTED.try_with(Cell::get).unwrap_or(false)
}

/// Install with `#[global_allocator] static A: CountingAllocator = CountingAllocator::new();`
/// in a test binary. It counts the allocations of a thread while that thread is inside
/// [`measure`](Self::measure): the object measured must not hand its memory to other
/// threads.
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
        let outer = COUNTED.with(|c| c.replace(true));
        let before = self.live();
        self.reset_peak();
        let object = create();
        exercise(&object);
        let held = self.live() - before;
        drop(object);
        let heap = HeapUse {
            held,
            peak: self.peak() - before,
            after: self.live() - before,
        };
        COUNTED.with(|c| c.set(outer));
        heap
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
        if !p.is_null() && counted() {
            let size = layout.size() as isize;
            let live = self.live.fetch_add(size, Ordering::SeqCst) + size;
            self.peak.fetch_max(live, Ordering::SeqCst);
        }
        p
    }

    unsafe fn dealloc(&self, p: *mut u8, layout: Layout) {
        unsafe { System.dealloc(p, layout) };
        if counted() {
            self.live
                .fetch_sub(layout.size() as isize, Ordering::SeqCst);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[global_allocator]
    static ALLOCATOR: CountingAllocator = CountingAllocator::new();

    #[test]
    fn another_threads_allocation_during_a_measurement_is_not_counted() {
        use std::sync::{Arc, Barrier};
        // Barriers wait without allocating, so the measured thread allocates only its vector.
        let (start, done) = (Arc::new(Barrier::new(2)), Arc::new(Barrier::new(2)));
        let (other_start, other_done) = (start.clone(), done.clone());
        let other = std::thread::spawn(move || {
            other_start.wait();
            let kept = std::hint::black_box(vec![1u8; 4096]);
            other_done.wait();
            kept
        });
        let heap = ALLOCATOR.measure(
            || vec![0u64; 100],
            |_| {
                start.wait();
                done.wait();
            },
        );
        let kept = other.join().unwrap();
        assert_eq!(kept.len(), 4096);
        assert_eq!(
            heap,
            HeapUse {
                held: 800,
                peak: 800,
                after: 0
            }
        );
    }
}
