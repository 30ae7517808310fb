//! LanderFilter: an error-state Kalman filter (ESKF) as an FMI 2.0 and FMI 3.0 Co-Simulation
//! FMU. Its inputs are LanderSensors' measurements (IMU, laser altimeter, Doppler
//! velocimeter), its outputs the navigation state under the names LanderGnc reads, with the
//! filter's covariance, innovation statistics and bias estimates.
//!
//! [`model`] holds the filter with no FMI in sight; [`fmu`] declares the variable table and
//! implements [`fmi_model::Model`]. docs/filter.md gives the equations.
#![deny(unsafe_code)]

pub mod fmu;
pub mod model;

pub use fmu::LanderFilter;

fmi2_export::export_fmi2!(crate::LanderFilter);
fmi3_export::export_fmi3!(crate::LanderFilter);
