//! LanderSensors' tests, one binary (each test binary is linked on its own).
mod conformance;
mod fmi3_abi;
mod measurements;
mod through_abi;
