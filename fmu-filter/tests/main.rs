//! LanderFilter's tests, one binary (each test binary is linked on its own). The two that use
//! LanderSensors' model (consistency.rs, shared_parameters.rs) are binaries of their own: in
//! one binary with LanderFilter's C functions, LanderSensors' would take their place.
mod calibration;
mod conformance;
mod fmi3_abi;
mod linear;
mod refusals;
mod rotating_step;
mod through_abi;
