//! What the lander FMUs share beyond the FMI core, written once.
//!
//! - [`quaternion`]: the attitude quaternion of every FMU interface (Hamilton, scalar first,
//!   `q_body_to_nue`), its matrix, product and exponential, and where it meets nalgebra.
//! - [`frames`]: vectors that carry their frame (NUE or body), and the attitude as the one way
//!   between them.
//! - [`sensor_limits`]: the admissible ranges of the sensor error parameters, which
//!   LanderSensors draws its errors from and LanderFilter assumes of the same sensors.
#![deny(unsafe_code)]

pub mod frames;
pub mod quaternion;
pub mod sensor_limits;
pub mod signal_groups;
