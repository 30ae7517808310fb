//! What the lander FMUs share beyond the FMI core, written once.
//!
//! - [`sensor_limits`]: the admissible ranges of the sensor error parameters, which
//!   LanderSensors draws its errors from and LanderFilter assumes of the same sensors.
#![deny(unsafe_code)]

pub mod sensor_limits;
