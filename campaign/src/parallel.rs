//! The parallel loop of every campaign: a rayon pool of `workers` threads runs one worker
//! loop per thread ([`rayon::ThreadPool::broadcast`]), so each thread loads exactly one
//! simulation and reuses it for every run it takes. Runs are handed out through an atomic
//! counter over the shard's stride (computed as they are handed out: a list would be 8 bytes
//! per run before the first one runs); each result goes through a bounded channel to the
//! caller's writer on one thread. Nothing accumulates per run: peak memory depends on the
//! number of workers, not of runs.
use crate::definition::Shard;
use std::collections::BTreeSet;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{mpsc, Mutex};

/// Which runs a campaign invocation runs, and on how many threads.
pub struct Work<'a> {
    pub workers: usize,
    pub shard: Shard,
    /// Runs in the whole campaign.
    pub total: u64,
    /// Runs finished before (resume), skipped.
    pub done: &'a BTreeSet<u64>,
}

/// Runs every index of `work.shard` among `work.total` that `work.done` does not hold:
/// `run(worker, index)`
/// gives a result and whether the worker must be loaded afresh (after an FMU's error its
/// instances may not be reusable); `write` takes the results one at a time. `first` is the
/// worker loaded already (a bad scenario fails before any file is written); the others come
/// from `load`. Returns how many results were written.
pub fn run<W: Send, R: Send>(
    work: Work<'_>,
    first: W,
    load: &(dyn Fn() -> anyhow::Result<W> + Sync),
    run: &(dyn Fn(&mut W, u64) -> (R, bool) + Sync),
    mut write: impl FnMut(R) -> anyhow::Result<()> + Send,
) -> anyhow::Result<u64> {
    let Work {
        workers,
        shard,
        total,
        done,
    } = work;
    anyhow::ensure!(workers > 0, "--workers must be at least 1");
    let positions = shard.len(total);
    let next = AtomicU64::new(0);
    let stop = AtomicBool::new(false);
    let spare = Mutex::new(Some(first));
    let (sender, receiver) = mpsc::sync_channel::<R>(2 * workers);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(workers)
        .thread_name(|i| format!("campaign-worker-{i}"))
        .build()?;
    let (worker_results, written) = std::thread::scope(|scope| {
        let writer_thread = scope.spawn(move || -> anyhow::Result<u64> {
            let mut written = 0;
            for result in receiver {
                // Returning drops the receiver, which makes the workers stop.
                write(result)?;
                written += 1;
            }
            Ok(written)
        });
        let worker_results = pool.broadcast(|_| -> anyhow::Result<()> {
            let sender = sender.clone();
            let mut worker = match spare.lock().map(|mut s| s.take()) {
                Ok(Some(worker)) => worker,
                _ => load()?,
            };
            loop {
                if stop.load(Ordering::Relaxed) {
                    return Ok(());
                }
                let j = next.fetch_add(1, Ordering::Relaxed);
                if j >= positions {
                    return Ok(());
                }
                let index = (shard.k - 1) + j * shard.n;
                if done.contains(&index) {
                    continue;
                }
                let (result, reload) = run(&mut worker, index);
                if sender.send(result).is_err() {
                    return Ok(()); // The writer has failed; its error is reported.
                }
                if reload {
                    worker = load().inspect_err(|_| stop.store(true, Ordering::Relaxed))?;
                }
            }
        });
        drop(sender);
        let written = writer_thread
            .join()
            .unwrap_or_else(|_| Err(anyhow::anyhow!("the manifest writer panicked")));
        (worker_results, written)
    });
    for result in worker_results {
        result?;
    }
    written
}
