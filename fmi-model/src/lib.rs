//! The version-neutral core of our FMUs.
//!
//! A model crate implements [`Model`] and declares each variable once, in a table of
//! [`Declaration`]s (usually written with [`decl!`]). An FMI layer (`fmi2-export`, and the
//! FMI 3.0 layer built on the same declarations) turns that table into its variables, its
//! get/set dispatch and its `modelDescription.xml`:
//!
//! ```text
//! declarations (this crate) -> FMI 2.0 layer / FMI 3.0 layer -> model crates
//! ```
//!
//! Nothing here knows an FMI version: a vector is one declaration with a [`Shape`] (FMI 2.0
//! expands it to scalars `r_nue[1]`.., FMI 3.0 writes one array), start values are read
//! from the model's `Default`, bounds are the ones the layer enforces on every set, and an
//! enumeration comes from its Rust enum ([`Enumeration`]). No `unsafe` here.
#![deny(unsafe_code)]

mod check;
pub mod continuous;
mod declaration;
mod enumeration;
mod interface;
mod model;
pub mod prepared;
pub mod registry;
pub mod restored;
pub mod snapshot;

pub use check::check_declarations;
pub use continuous::{ContinuousModel, EventUpdate};
pub use declaration::{
    role, Causality, Declaration, Dependencies, Initial, Kind, Limit, Role, Shape, Variability,
};
pub use enumeration::{EnumItem, EnumType, EnumValue, Enumeration};
pub use interface::Interface;
pub use model::{Experiment, Level, Log, Model, ModelError, StepEnd};

/// A real value in a log line as a user reads it: plain digits, but an exponent where plain
/// digits would run to hundreds (1e300) or bury the value in zeros (1e-12).
pub fn readable(value: f64) -> String {
    if value != 0.0 && value.is_finite() && !(1e-6..1e16).contains(&value.abs()) {
        format!("{value:e}")
    } else {
        format!("{value}")
    }
}

#[cfg(test)]
mod readable_tests {
    use super::readable;

    #[test]
    fn huge_and_tiny_values_use_an_exponent_others_plain_digits() {
        assert_eq!(readable(1e300), "1e300");
        assert_eq!(readable(-2.5e-12), "-2.5e-12");
        assert_eq!(readable(0.0), "0");
        assert_eq!(readable(116.0), "116");
        assert_eq!(readable(0.01), "0.01");
        assert_eq!(readable(f64::INFINITY), "inf");
    }
}
