//! Robustness of the lander FMUs under hostile use, through their C ABI exactly as shipped
//! (`target/fmu/*.fmu`): API fuzzing, the bad-input table, threads, leaks, long runs and
//! memory. The functions are called through raw C function pointers ([`api`], the test kit's
//! table) with the C types of `fmi-abi` ([`ffi`]) and a logger formatted in C ([`logger`]),
//! so nothing of the export layer's own Rust types stands between the tests and the ABI.
//!
//! Commands (each also runs, shorter, in `cargo test -p robustness-tests`):
//! - `cargo run --release -p robustness-tests --bin fuzz-api -- --calls 1000000 --seed 1`
//! - `cargo run --release -p robustness-tests --bin cycles -- --cycles 10000` (under
//!   `valgrind --leak-check=full` for leaks; prints VmRSS along the way)
//! - `cargo run --release -p robustness-tests --bin long-run -- --steps 10000000`
#![deny(unsafe_code)]
// The header's status names (`fmi2OK`, ...) are matched as patterns throughout.
#![allow(non_upper_case_globals)]

pub mod api;
pub mod cycles;
pub mod ffi;
pub mod fuzz;
pub mod instance;
pub mod logger;
pub mod long_run;
pub mod package;
pub mod reference;
pub mod rss;
