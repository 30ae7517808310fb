//! The master loop allocates nothing per step: a run of N steps and a run of 2N steps make
//! exactly as many heap allocations (counted by a global allocator that wraps the system's).
//! Whatever a run allocates (the trajectory, reserved once from the step count; error paths)
//! does not grow with its length, so a per-step allocation shows up as a difference of N.
mod common;

use cosim::master::{Recorder, Simulation, Trajectory};
use cosim::system::SystemDescription;
use lander::scenarios;
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;

struct Counting;

static ALLOCATIONS: AtomicU64 = AtomicU64::new(0);

// SAFETY: forwards every call to the system allocator unchanged; only counts.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        // SAFETY: same contract as ours.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: same contract as ours.
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        // SAFETY: same contract as ours.
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        // SAFETY: same contract as ours.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// The counter is process-wide: tests in this file take turns.
static ONE_AT_A_TIME: Mutex<()> = Mutex::new(());

/// Heap allocations made by one `run` of `system` stopped at `stop_time`, recording into a
/// fresh `make()`, after a first run, so lazy one-time set-up in the FMUs and the loader is
/// out of the count.
fn allocations_of_a_run<R: Recorder>(
    mut system: SystemDescription,
    stop_time: f64,
    mut make: impl FnMut() -> R,
) -> (u64, R) {
    system.stop_time = stop_time;
    let mut simulation = Simulation::new(system, &common::fmu_dir()).unwrap();
    simulation.run(&mut make()).unwrap();
    let mut recorder = make();
    let before = ALLOCATIONS.load(Ordering::Relaxed);
    simulation.run(&mut recorder).unwrap();
    (ALLOCATIONS.load(Ordering::Relaxed) - before, recorder)
}

/// A recorder that keeps nothing, so only the master loop and the FMUs are counted.
struct Discard;
impl Recorder for Discard {
    fn record(&mut self, _time: f64, _values: &[f64]) {}
}

fn paper_with_every_output() -> SystemDescription {
    let mut system = scenarios::load("paper").unwrap();
    system.record = None;
    system
}

#[test]
fn the_master_loop_allocates_nothing_per_step() {
    let _turn = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    // 5 s and 10 s: 500 and 1,000 steps, both before touchdown.
    let (short, _) = allocations_of_a_run(paper_with_every_output(), 5.0, || Discard);
    let (long, _) = allocations_of_a_run(paper_with_every_output(), 10.0, || Discard);
    assert_eq!(
        short, long,
        "a run of 1,000 steps made {long} allocations, one of 500 steps {short}: \
         something allocates per step"
    );
}

#[test]
fn recording_into_a_trajectory_allocates_once_per_run_not_per_row() {
    let _turn = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let (short, short_rows) =
        allocations_of_a_run(paper_with_every_output(), 5.0, Trajectory::default);
    let (long, long_rows) =
        allocations_of_a_run(paper_with_every_output(), 10.0, Trajectory::default);
    assert_eq!(short_rows.len(), 501);
    assert_eq!(long_rows.len(), 1001);
    assert_eq!(
        short, long,
        "recording 1,001 rows made {long} allocations, 501 rows {short}: the trajectory \
         grows by reallocation"
    );
}

#[test]
fn the_master_loop_over_fmi3_fmus_allocates_nothing_per_step() {
    let _turn = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    // The FMI 3.0 pair: arrays read and written whole, Event Mode at every point for the GNC.
    let fmi3 = || {
        let mut system = paper_with_every_output();
        for instance in &mut system.instances {
            instance.fmu = std::path::Path::new("fmi3").join(&instance.fmu);
        }
        system
    };
    let (short, _) = allocations_of_a_run(fmi3(), 5.0, || Discard);
    let (long, _) = allocations_of_a_run(fmi3(), 10.0, || Discard);
    assert_eq!(
        short, long,
        "an FMI 3.0 run of 1,000 steps made {long} allocations, one of 500 steps {short}"
    );
}
