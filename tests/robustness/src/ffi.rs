//! The FMI 2.0 C types as a master sees them: the workspace's one copy (`fmi-abi`). Every
//! C enumeration there, `fmi2Status` included, is a C `int` (wrapped), so the tests see any
//! value a broken FMU could return without undefined behaviour.
pub use fmi_testkit::fmi2::*;
