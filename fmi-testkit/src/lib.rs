//! The test kit: what every test of an FMU needs, written once.
//!
//! - [`Fmi2Functions`]: the FMI 2.0 entry points of an FMU, taken from a crate linked into
//!   the test ([`fmi2_functions!`]) or from a shared library loaded at run time;
//! - [`Instance`]: one instance driven through those entry points exactly as a C master
//!   drives it, freed on drop;
//! - [`Fmi3Functions`] and [`Fmi3Instance`]: the same for FMI 3.0 ([`fmi3_functions!`]);
//! - [`Driver`]: one interface over both ([`Fmi2`], [`Fmi3`]), so that one test body runs
//!   for each version, with a version-neutral [`Status`] and [`StepOutcome`];
//! - [`TestLogger`]: records every message through the real variadic callback (the C shim
//!   of `fmi-abi`), no transmuted function pointers;
//! - [`MeSolver`]: a Model Exchange master of the kit's own (fixed-step RK4, events by
//!   bisection on the indicators) over an FMU's ME entry points ([`fmi2_me_functions!`]);
//! - [`CountingAllocator`]: a global allocator that counts live and peak bytes;
//! - [`assert_file_matches`]: the drift check of a generated file kept under version control;
//! - [`assert_refused_in_the_set`], [`assert_refused_at_exit`]: a rejected parameter refused
//!   with a log line naming it, in either version, the instance left usable.
//!
//! - [`conformance!`]: the conformance suite an FMU crate gets with one line, derived from its
//!   declarations and its `[package.metadata.fmu]`.
//!
//! It is a dev-dependency only; nothing here ends up in an FMU.
#![allow(unsafe_code)]

mod alloc;
pub mod conformance;
mod drift;
mod driver;
mod fmi3;
mod functions;
mod instance;
mod logger;
mod model_exchange;
mod refusals;
mod test_model;

pub use alloc::{CountingAllocator, HeapUse};
pub use drift::assert_file_matches;
pub use driver::{Driver, Fmi2, Fmi3, Interface, Status, StepOutcome, Version};
pub use fmi3::{
    CoSimulationOptions, Fmi3Derivatives, Fmi3EventUpdate, Fmi3Functions, Fmi3Instance, Fmi3Step,
};
pub use fmi_abi::fmi2;
pub use fmi_abi::fmi3 as fmi3_ffi;
pub use fmi_abi::unpack;
pub use fmi_import;
/// The [`Fmi2MeFunctions`] of an FMU crate linked into the test.
pub use fmi_import::fmi2_model_exchange as fmi2_me_functions;
pub use fmi_model;
pub use functions::Fmi2Functions;
pub use instance::Instance;
pub use logger::{Record, TestLogger};
pub use model_exchange::{Fmi2MeFunctions, MeSolver};
pub use refusals::{assert_refused_at_exit, assert_refused_in_the_set, AtExit, Refusal, Refusals};
