//! LanderGnc: guidance and attitude control of a lunar lander after Rallapalli et al.,
//! "Decoupled Thrust-Axis Attitude Control Using Quaternions for Chandrayaan-3 Lunar Landing
//! Mission", with the corrections of `docs/paper-notes.md`, as an FMI 2.0 co-simulation FMU.
//!
//! * [`conventions`]: frames, axes, the scalar-first quaternion and its nalgebra boundary.
//! * [`guidance`]: cubic-polynomial descent, PV hover, the phase sequencer, thrust magnitude.
//! * [`attitude`]: reference attitude, phi_b, the thrust-axis error split, the coupled,
//!   decoupled and reduced laws, gains and saturation.
//! * [`actuation`]: thruster mode: torque allocation to eight thrusters and PWPF modulation.
//! * [`controller`]: one GNC sample from navigation inputs (pure).
//! * [`supervision`]: feasibility of the parameters and the input consistency monitor (pure,
//!   observes only).
//! * [`fmu`]: the FMI variable table and timing; no math.
#![deny(unsafe_code)]

pub mod actuation;
pub mod attitude;
pub mod controller;
pub mod conventions;
pub mod derivatives;
pub mod fmu;
pub mod guidance;
pub mod params;
pub mod supervision;

pub use fmu::LanderGnc;

fmi2_export::export_fmi2!(crate::LanderGnc);
fmi3_export::export_fmi3!(crate::LanderGnc);
