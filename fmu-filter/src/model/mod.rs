//! The filter, with no FMI in sight: the 27 x 27 covariance arithmetic, the
//! parameters, the measurement models with their Jacobians, and the ESKF itself.
pub mod covariance;
pub mod eskf;
pub mod measurement;
pub mod parameters;
/// The interface's quaternion (Hamilton, scalar first), shared with the other FMUs.
pub use lander_math::quaternion as rotation;

pub use eskf::{Eskf, Heading, Imu, Update};
pub use parameters::{FilterParameters, ParameterError};
