//! The FMI 2.0 C types and the master's callbacks, from the workspace's one copy (`fmi-abi`).
pub use fmi_abi::callbacks::{text, LogSink};
pub use fmi_abi::fmi2::*;
