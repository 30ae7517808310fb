//! The FMI version of a loaded FMU: a leaf every other module may name.

/// The FMI version of a loaded FMU.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FmiVersion {
    Fmi2,
    Fmi3,
}
