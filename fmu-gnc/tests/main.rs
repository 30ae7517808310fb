//! LanderGnc's tests, one binary (each test binary is linked on its own): guidance and the
//! attitude laws against closed forms and the paper, the FMI 2.0 and 3.0 ABI, a vehicle of its
//! own, and the conformance suite.
mod closed_loop;
mod common;
mod conformance;
mod fmi;
mod fmi3_abi;
mod fmu_abi;
mod own_vehicle;
mod parameter_properties;
mod properties;
mod refusals;
mod retarget;
mod section_iv_illustration;
mod shaped_manoeuvre;
mod thrusters;
