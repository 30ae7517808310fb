//! The filter, with no FMI in sight: rotations, the 27 x 27 covariance arithmetic, the
//! parameters, the measurement models with their Jacobians, and the ESKF itself.
pub mod covariance;
pub mod eskf;
pub mod measurement;
pub mod parameters;
pub mod rotation;

pub use eskf::{Eskf, Heading, Imu, Update};
pub use parameters::{FilterParameters, ParameterError};
