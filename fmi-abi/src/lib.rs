//! The FMI C ABI as Rust types, written once and used on both sides of it: by the export
//! layers that implement the functions inside our FMUs, by the harness loader that calls
//! them in foreign FMUs, and by the test crates.
//!
//! The types are written by hand after the official headers rather than taken from
//! `fmi-sys`: a crate that links into our FMUs must not drag a foreign library (or its
//! symbols) along. The system tests compare these types with the official headers.
//!
//! Features (off by default, so an FMU gets only the types): `callbacks`, the master's
//! logger shim and memory functions; `unpack`, unpacking a `.fmu` archive.
#[allow(unsafe_code)]
pub mod args;
pub mod fmi2;
pub mod fmi3;

#[cfg(feature = "callbacks")]
pub mod callbacks;
#[cfg(feature = "unpack")]
pub mod unpack;
