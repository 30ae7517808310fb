//! The model author's API: what a model crate writes, and nothing that runs in an FMU.
//!
//! A model crate implements [`Model`] (and [`ContinuousModel`] for Model Exchange) and
//! declares each variable once, in a table of [`Declaration`]s (usually written with
//! [`decl!`]). An FMI layer (`fmi2-export`, `fmi3-export`, on the export core `fmi-export`)
//! turns that table into its variables, its get/set dispatch and its `modelDescription.xml`:
//!
//! ```text
//! declarations (this crate) -> fmi-export -> FMI 2.0 layer / FMI 3.0 layer -> model crates
//! ```
//!
//! Nothing here knows an FMI version: a vector is one declaration with a [`Shape`] (FMI 2.0
//! expands it to scalars `r_nue[1]`.., FMI 3.0 writes one array), start values are read
//! from the model's `Default`, bounds are the ones the layer enforces on every set, and an
//! enumeration comes from its Rust enum ([`Enumeration`]). The runtime that serves the C
//! calls (instance registry, prepared value lists, FMU-state serialization and its checks)
//! is the export core's. No `unsafe` here, and the compiler holds it so.
#![forbid(unsafe_code)]

mod check;
pub mod continuous;
mod declaration;
mod derivatives;
mod enumeration;
mod interface;
mod model;
pub mod parameter;
mod terminal;

pub use check::check_declarations;
pub use continuous::{ContinuousModel, EventUpdate};
pub use declaration::{
    bounds_note, role, Causality, Declaration, Dependencies, Initial, Kind, Limit, Role, Shape,
    Variability,
};
pub use derivatives::ScalarRef;
pub use enumeration::{EnumItem, EnumType, EnumValue, Enumeration};
pub use interface::Interface;
pub use model::{Experiment, Level, Log, Model, ModelError, StepEnd};
pub use terminal::{check_terminals, same, same_names, MatchingRule, Member, Terminal};

/// A real value in a log line as a user reads it: plain digits, but an exponent where plain
/// digits would run to hundreds (1e300, `f64::MAX`) or bury the value in zeros (1e-12, the
/// subnormals down to 5e-324). The shortest digits that read back as the value, so never
/// more than 25 characters.
pub fn readable(value: f64) -> String {
    if value != 0.0 && value.is_finite() && !(1e-6..1e16).contains(&value.abs()) {
        format!("{value:e}")
    } else {
        format!("{value}")
    }
}

/// A declared Real range as a refusal message shows it: `[0, 100]`, `(0, inf)`. An inclusive
/// end is a bracket, an exclusive one, a missing one (written `-inf`/`inf`) and an infinite
/// one a parenthesis; the values are [`readable`].
pub fn range_text(min: Option<Limit>, max: Option<Limit>) -> String {
    // An end the range reaches: inclusive and finite.
    let closed = |limit: Option<Limit>| matches!(limit, Some(Limit::Inclusive(v)) if v.is_finite());
    let low = min.map_or("-inf".into(), |m| readable(m.value()));
    let high = max.map_or("inf".into(), |m| readable(m.value()));
    let open = if closed(min) { '[' } else { '(' };
    let close = if closed(max) { ']' } else { ')' };
    format!("{open}{low}, {high}{close}")
}

#[cfg(test)]
mod readable_tests {
    use super::{range_text, readable, Limit};

    #[test]
    fn huge_and_tiny_values_use_an_exponent_others_plain_digits() {
        assert_eq!(readable(1e300), "1e300");
        assert_eq!(readable(-2.5e-12), "-2.5e-12");
        assert_eq!(readable(0.0), "0");
        assert_eq!(readable(116.0), "116");
        assert_eq!(readable(0.01), "0.01");
        assert_eq!(readable(f64::INFINITY), "inf");
    }

    #[test]
    fn extreme_values_are_short() {
        assert_eq!(readable(5e-324), "5e-324");
        assert_eq!(readable(-5e-324), "-5e-324");
        assert_eq!(readable(1e-310), "1e-310");
        assert_eq!(readable(f64::MIN_POSITIVE), "2.2250738585072014e-308");
        assert_eq!(readable(f64::MAX), "1.7976931348623157e308");
        assert_eq!(readable(-f64::MAX), "-1.7976931348623157e308");
        assert_eq!(readable(f64::NEG_INFINITY), "-inf");
        assert_eq!(readable(f64::NAN), "NaN");
        // Either side of the thresholds.
        assert_eq!(readable(1e16), "1e16");
        assert_eq!(readable(9999999999999998.0), "9999999999999998");
        assert_eq!(readable(1e-6), "0.000001");
        assert_eq!(readable(9.99e-7), "9.99e-7");
        // No value runs long: at most 17 significant digits, with a sign and a point, and
        // either an exponent or (just above 1e-6) five leading zeros.
        let mut x = 5e-324_f64;
        while x.is_finite() {
            for v in [x, -x, x.next_up(), x.next_down()] {
                assert!(readable(v).len() <= 25, "{v:?} as {}", readable(v));
            }
            x *= 3.7;
        }
    }

    #[test]
    fn a_range_shows_each_end_inclusive_exclusive_or_open() {
        use Limit::{Exclusive, Inclusive};
        assert_eq!(
            range_text(Some(Inclusive(0.0)), Some(Inclusive(100.0))),
            "[0, 100]"
        );
        assert_eq!(
            range_text(Some(Exclusive(0.0)), Some(Inclusive(1e20))),
            "(0, 1e20]"
        );
        assert_eq!(range_text(Some(Exclusive(0.0)), None), "(0, inf)");
        assert_eq!(
            range_text(Some(Inclusive(-std::f64::consts::FRAC_PI_2)), None),
            "[-1.5707963267948966, inf)"
        );
        assert_eq!(range_text(None, Some(Exclusive(1.0))), "(-inf, 1)");
        assert_eq!(range_text(None, None), "(-inf, inf)");
        assert_eq!(
            range_text(Some(Inclusive(5e-324)), Some(Exclusive(f64::MAX))),
            "[5e-324, 1.7976931348623157e308)"
        );
        // Plain digits below 1e16, as in the value refused.
        assert_eq!(
            range_text(Some(Exclusive(0.0)), Some(Inclusive(1e9))),
            "(0, 1000000000]"
        );
        // An infinite bound is no end the range reaches, whatever its kind.
        assert_eq!(
            range_text(
                Some(Inclusive(f64::NEG_INFINITY)),
                Some(Inclusive(f64::INFINITY))
            ),
            "(-inf, inf)"
        );
    }
}
