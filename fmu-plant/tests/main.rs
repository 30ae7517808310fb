//! LanderPlant's tests, one binary (each test binary is linked on its own): its physics against
//! closed forms, the FMI 2.0 and 3.0 ABI in both interfaces, and the conformance suite.
mod actuators;
mod common;
mod conformance;
mod continuous;
mod derivatives_abi;
mod description_metadata;
mod faults;
mod fmi3_abi;
mod fmi3_common;
mod fmi3_gear;
mod fmi3_reentrancy;
mod fmi3_restored_state;
mod full_fidelity;
mod gear;
mod jacobian;
mod layer_hardening;
mod loops_end;
mod mass_properties;
mod model_exchange_abi;
mod model_exchange_hardening;
mod physics;
mod restored_state;
mod slosh;
mod specific_force;
mod through_abi;
mod thrusters;
