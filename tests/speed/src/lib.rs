//! Speed side by side, in one run: our FMUs through the C ABI, the paper scenario and a
//! Monte Carlo campaign in our master, the same scenario in fmpy's master loop, and our
//! plant against the same equations packaged with pythonfmu.
//!
//! `cargo xtask bench` packages the FMUs and runs the binary (src/main.rs), which prints
//! the table; see the README there for what each row measures.
#![deny(unsafe_code)]

pub mod c_floor;
pub mod c_master;
/// Loads FMU binaries itself (the one unsafe part: foreign code).
#[allow(unsafe_code)]
pub mod call_orders;
pub mod callgrind;
pub mod closed_loop;
pub mod duel;
/// Loads FMU binaries itself and calls the FMI 3.0 functions (foreign code).
#[allow(unsafe_code)]
pub mod fmi3_pair;
pub mod python;
pub mod record;
pub mod replay;
pub mod stats;
pub mod table;
