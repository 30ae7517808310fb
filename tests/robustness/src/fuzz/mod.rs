//! API fuzzing through the C ABI: random call sequences over all 34 functions (see
//! [`ops`]) with hostile arguments, run against a packaged FMU.
//!
//! Invariants, checked after every call ([`session`]):
//! - no crash, and no call takes longer than the watchdog's limit (no hang);
//! - the status is one of fmi2OK..fmi2Fatal, and fmi2Fatal never happens (it would mean a
//!   caught panic) except on an instance holding a crafted state;
//! - a call that must be refused (NULL array with a count, unknown value reference,
//!   non-finite Real, step size <= 0, unsupported function, corrupted state buffer, ...) is
//!   answered with fmi2Error;
//! - every fmi2Error/fmi2Fatal is logged with that status in a message naming the function,
//!   every fmi2Warning with a warning; no message is more severe than the status; messages go
//!   to the calling instance only, with its name;
//! - Real outputs read successfully are finite; Booleans are 0 or 1; strings are readable.
//! - no fmi2GetReal is refused because a value is not finite (the export layer's last
//!   guard) on an instance that holds no crafted state.
//!
//! And after every sequence: fmi2Reset on each instance, then a legal run, gives the reference
//! result bit for bit, and so does a new instance.
pub mod ops;
pub mod session;
pub mod watchdog;

use crate::instance::Fmu;
use proptest::strategy::{Strategy, ValueTree};
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
pub use session::{Baseline, Session, Stats};
pub use watchdog::Watchdog;

/// Longest generated sequence.
pub const MAX_SEQUENCE: usize = 160;

/// Runs sequences drawn from `seed` until at least `calls` fuzz calls were made; the first
/// invariant violation (with the sequence that caused it) as `Err`.
pub fn run(
    fmu: &Fmu,
    calls: u64,
    seed: u64,
    dog: &Watchdog,
    mut progress: impl FnMut(&Stats),
) -> Result<Stats, String> {
    let base = Baseline::new(fmu)?;
    let mut seed_bytes = [0u8; 32];
    seed_bytes[..8].copy_from_slice(&seed.to_le_bytes());
    let rng = TestRng::from_seed(RngAlgorithm::ChaCha, &seed_bytes);
    let mut runner = TestRunner::new_with_rng(Config::default(), rng);
    let strategy = ops::sequence(MAX_SEQUENCE);
    let mut total = Stats::default();
    while total.fuzz_calls < calls {
        let ops = strategy
            .new_tree(&mut runner)
            .map_err(|e| format!("cannot draw a sequence: {e}"))?
            .current();
        let stats = Session::new(fmu, &base, dog).run(&ops).map_err(|e| {
            format!(
                "{} after {} sequences: {e}\nsequence: {ops:#?}",
                fmu.lander().model_identifier(),
                total.sequences
            )
        })?;
        total.add(&stats);
        progress(&total);
    }
    Ok(total)
}
