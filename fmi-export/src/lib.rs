//! The one export core of our FMUs: everything the FMI 2.0 and FMI 3.0 layers share, once.
//!
//! ```text
//! fmi-model (declarations, Model)  ->  fmi-export (this crate)  ->  fmi2-export / fmi3-export
//! ```
//!
//! A version layer implements [`Abi`] (its status codes, its state table, its logger call,
//! its variable view, its symbol prefix and state magic) and keeps only what is its own: the
//! exported symbols, the unpacking of C arguments, its XML writer and its view of the
//! variables (FMI 2.0 scalars, FMI 3.0 arrays). Everything else lives here: the registry of
//! live instances (`registry`), the instance and its copied core, the call guard (registry
//! lookup, re-entrancy, panic guard, call trace, state check, one log line per refusal), the
//! step rules with a version-neutral outcome, FMU-state storage, its serialized form
//! (`snapshot`) and the checks of a restored one (`restored`), the setter rules and their
//! messages, the Real value lists a master repeats (`prepared`), the description of a
//! model's errors, the Model Exchange accessors and the unit table.
//!
//! Nothing here names an FMI version: messages speak of "initialization", "the step" and
//! "the FMU state"; a version's function names come from its own table.
//!
//! `unsafe` is denied but for the modules that need it, each allowing it by name: the C
//! bodies (`raw`), entering a call through a handle (`call`), the master's logger
//! (`logging`) and the model's bytes behind a prepared list (`prepared`).
#![deny(unsafe_code)]

pub mod call;
pub mod derivatives;
mod describe;
pub mod fmu_state;
#[doc(hidden)]
pub mod function_table;
pub mod instance;
pub mod lifecycle;
pub mod logging;
pub mod model_exchange;
pub mod prepared;
pub mod raw;
pub mod registry;
pub mod restored;
pub mod setters;
pub mod snapshot;
pub mod state;
pub mod status;
pub mod step;
mod units;
mod version;
pub mod warnings;

pub use describe::describe_model_error;
pub use instance::{Core, Instance, Options};
pub use logging::{Category, Logger, Sink};
pub use state::{Interface, State, StateMask};
pub use status::{CallError, Refusal, Status, Success};
pub use units::{base_unit, check_units, display_unit};

/// Who made the FMUs and under which terms, and when, for every model description.
pub mod provenance {
    pub const AUTHOR: &str = "the lander-fmi contributors";
    pub const COPYRIGHT: &str = "Copyright (c) 2026 the lander-fmi contributors";
    pub const LICENSE: &str = env!("CARGO_PKG_LICENSE");

    /// `generationDateAndTime` from `SOURCE_DATE_EPOCH` (seconds since 1970, UTC), the
    /// reproducible-builds convention: the packager sets it to the commit's time, so the same
    /// commit gives the same description on every machine. Unset or unreadable: none.
    pub fn generation_date_and_time() -> Option<String> {
        let seconds: i64 = std::env::var("SOURCE_DATE_EPOCH")
            .ok()?
            .trim()
            .parse()
            .ok()?;
        Some(model_description::iso8601_utc(seconds))
    }
}
pub use version::{admitted_when_fatal, assert_function_table, Abi, Function};

/// Relative tolerance on communication points and times: masters accumulate `t += h` and
/// arrive a few ulps off (fmpy reaches step 1200 of 0.01 s at 11.999999999999789). A point
/// `t` is accepted when `|t - time| <= 1e-9 * max(1, |time|)`; the same bound applies to the
/// declared stop time and to a restored state's bookkeeping.
pub const TIME_TOLERANCE: f64 = 1e-9;

/// The tolerance of [`TIME_TOLERANCE`] around `reference`.
pub fn time_tolerance(reference: f64) -> f64 {
    TIME_TOLERANCE * reference.abs().max(1.0)
}
