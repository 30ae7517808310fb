//! The lander physics, free of FMI: usable on its own and tested on its own.
pub mod actuators;
pub mod continuous;
pub mod events;
pub mod frames;
pub mod gear;
pub mod integrator;
pub mod mass_properties;
pub mod parameters;
pub mod plant;
pub mod rigid_body;
pub mod slosh;
pub mod slosh_dynamics;
pub mod state;
pub mod thrusters;
pub mod translation_flat;
pub mod translation_spherical;
