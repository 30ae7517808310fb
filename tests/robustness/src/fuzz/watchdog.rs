//! A hang detector: a thread that aborts the process, naming the call, when one FFI call has
//! not returned within the limit. A hang cannot be caught any other way (the call never
//! returns), and an abort fails the test or the run loudly.
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

struct Shared {
    base: Instant,
    /// Milliseconds since `base` + 1 at which the current call started; 0 when idle.
    armed_at: AtomicU64,
    what: Mutex<&'static str>,
    stop: AtomicBool,
}

pub struct Watchdog {
    shared: Arc<Shared>,
    limit: Duration,
    thread: Option<JoinHandle<()>>,
}

impl Watchdog {
    pub fn start(limit: Duration) -> Watchdog {
        let shared = Arc::new(Shared {
            base: Instant::now(),
            armed_at: AtomicU64::new(0),
            what: Mutex::new(""),
            stop: AtomicBool::new(false),
        });
        let watched = Arc::clone(&shared);
        let thread = std::thread::spawn(move || {
            let poll = (limit / 20).clamp(Duration::from_millis(5), Duration::from_millis(200));
            while !watched.stop.load(Ordering::Acquire) {
                std::thread::sleep(poll);
                let armed = watched.armed_at.load(Ordering::Acquire);
                if armed == 0 {
                    continue;
                }
                let elapsed_ms =
                    (watched.base.elapsed().as_millis() as u64 + 1).saturating_sub(armed);
                if elapsed_ms > limit.as_millis() as u64 {
                    let what = *watched.what.lock().unwrap_or_else(|p| p.into_inner());
                    eprintln!("watchdog: {what} has not returned after {elapsed_ms} ms (limit {limit:?}): the FMU hangs");
                    std::process::abort();
                }
            }
        });
        Watchdog {
            shared,
            limit,
            thread: Some(thread),
        }
    }

    pub fn limit(&self) -> Duration {
        self.limit
    }

    /// Runs `call` under the watchdog.
    pub fn watch<R>(&self, what: &'static str, call: impl FnOnce() -> R) -> R {
        *self.shared.what.lock().unwrap_or_else(|p| p.into_inner()) = what;
        let now = self.shared.base.elapsed().as_millis() as u64 + 1;
        self.shared.armed_at.store(now, Ordering::Release);
        let result = call();
        self.shared.armed_at.store(0, Ordering::Release);
        result
    }
}

impl Drop for Watchdog {
    fn drop(&mut self) {
        self.shared.stop.store(true, Ordering::Release);
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}
