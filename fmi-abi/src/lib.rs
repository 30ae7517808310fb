//! The FMI C ABI as Rust types, written once and used on both sides of it: by the export
//! layers that implement the functions inside our FMUs, by the harness loader that calls
//! them in foreign FMUs, and by the test crates.
//!
//! The types are written by hand after the official headers rather than taken from
//! `fmi-sys`: a crate that links into our FMUs must not drag a foreign library (or its
//! symbols) along. The system tests compare these types with the official headers.
pub mod fmi2;
pub mod fmi3;
