//! Generic FMI 3.0 export layer: Co-Simulation and Model Exchange from the same model
//! declarations as the FMI 2.0 layer.
#![deny(unsafe_code)]

// Until the shared C-types crate exists on this branch, the FMI 3.0 types come from its file.
#[path = "../../fmi-abi/src/fmi3.rs"]
pub mod ffi;
pub mod logging;
pub mod state;
