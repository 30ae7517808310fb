//! LanderSensors: the lander's sensors as an FMI 2.0 and FMI 3.0 Co-Simulation FMU. Its inputs
//! are the plant's true state and specific force, its outputs what an IMU (accelerometer and
//! gyro), a laser altimeter and a three-beam Doppler velocimeter measure of it, with seeded,
//! reproducible errors.
//!
//! [`model`] holds the sensor models with no FMI in sight; [`fmu`] declares the variable table
//! and implements [`fmi_model::Model`]. docs/sensors.md gives the equations and timing.
#![deny(unsafe_code)]

pub mod fmu;
pub mod model;

pub use fmu::LanderSensors;

fmi2_export::export_fmi2!(crate::LanderSensors);
fmi3_export::export_fmi3!(crate::LanderSensors);
