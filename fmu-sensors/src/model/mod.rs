//! The sensor models, with no FMI in sight: parameters and their validation, the true state
//! they measure, the counter-based draws, the IMU, the terrain plane and its beams, and
//! [`sensors::Sensors`] that combines them with the timing.
pub mod beams;
pub mod draws;
pub mod imu;
pub mod parameters;
pub mod sensors;
pub mod terrain;
pub mod truth;

pub use parameters::{ParameterError, SensorParameters};
pub use sensors::{Measurements, Sensors};
pub use terrain::Terrain;
pub use truth::Truth;
