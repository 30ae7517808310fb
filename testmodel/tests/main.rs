//! The Oscillator's tests, one binary (each test binary is linked on its own): every part of the
//! export layers through the C ABI. The registry's capacity is a binary of its own
//! (capacity.rs): it fills the registry, which would refuse other tests' instances.
#[macro_use]
mod common;
mod bad_input;
mod communication_point;
mod conformance;
mod fmu_state;
mod logging;
mod model_description;
mod reentrancy;
mod simulation;
mod state_machine;
