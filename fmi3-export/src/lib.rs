//! Generic FMI 3.0 export layer: Co-Simulation and Model Exchange from the same model
//! declarations as the FMI 2.0 layer.
#![deny(unsafe_code)]

pub mod state;
