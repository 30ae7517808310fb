//! The checks of a restored FMU state that no FMI version changes. A crafted buffer carries
//! a valid header and checksum as easily as a genuine one, so a layer accepts a state only
//! if an instance could have reached it: its bookkeeping ([`check_bookkeeping`]), every
//! parameter and input holding a value the layer's set functions would have accepted
//! ([`check_declared_values`]), then [`Model::validate_restored`]. Each refusal is one line
//! `FMU state refused: <field> = <value>: <reason>`.
use fmi_model::{range_text, readable, Causality, Kind, Model};
use std::fmt::Display;

/// A refusal naming the field at fault.
pub fn refused(what: &str, value: impl Display, reason: &str) -> String {
    format!("FMU state refused: {what} = {value}: {reason}")
}

/// A layer's bookkeeping of a restored state.
#[derive(Debug, Clone, Copy)]
pub struct Bookkeeping {
    pub time: f64,
    pub start_time: f64,
    /// Kept by layers that report it (FMI 2.0's `fmi2LastSuccessfulTime`).
    pub last_successful_time: Option<f64>,
    pub stop_time: Option<f64>,
    /// The state was saved from an unusable instance (state Fatal).
    pub fatal: bool,
}

/// Finite times, ordered within `relative_tolerance` (of the largest magnitude, at least 1 s);
/// no Fatal state.
pub fn check_bookkeeping(b: &Bookkeeping, relative_tolerance: f64) -> Result<(), String> {
    let times = [
        ("time", Some(b.time)),
        ("start time", Some(b.start_time)),
        ("last successful time", b.last_successful_time),
    ];
    for (what, t) in times {
        if let Some(t) = t.filter(|t| !t.is_finite()) {
            return Err(refused(what, t, "not finite"));
        }
    }
    let tolerance = relative_tolerance * b.start_time.abs().max(b.time.abs()).max(1.0);
    if b.time < b.start_time - tolerance {
        return Err(refused("time", readable(b.time), "before the start time"));
    }
    if let Some(last) = b.last_successful_time {
        if last > b.time + tolerance || last < b.start_time - tolerance {
            return Err(refused(
                "last successful time",
                readable(last),
                "outside [start time, time]",
            ));
        }
    }
    if let Some(stop) = b.stop_time {
        if !stop.is_finite() || stop < b.start_time {
            return Err(refused(
                "stop time",
                readable(stop),
                "not finite or before the start time",
            ));
        }
    }
    if b.fatal {
        return Err(refused(
            "state",
            "Fatal",
            "an unusable instance cannot be restored",
        ));
    }
    Ok(())
}

/// Every parameter and input of `model` holds a value the layer's set functions accept:
/// Reals finite and within their bounds, Integers within theirs, enumerations one of
/// their type's items. The first one at fault is named.
pub fn check_declared_values<M: Model>(model: &M) -> Result<(), String> {
    for d in M::declarations() {
        if !matches!(d.causality, Causality::Parameter | Causality::Input) {
            continue;
        }
        match &d.kind {
            Kind::Real {
                shape,
                min,
                max,
                get,
                ..
            } => {
                for i in 0..shape.len() {
                    let v = get(model, i);
                    let name = if shape.len() > 1 {
                        format!("{}[{}]", d.name, i + 1)
                    } else {
                        d.name.to_string()
                    };
                    if !v.is_finite() {
                        return Err(refused(&name, v, "not finite"));
                    }
                    let below = min.is_some_and(|m| !m.admits_above(v));
                    let above = max.is_some_and(|m| !m.admits_below(v));
                    if below || above {
                        let reason = format!("outside {}", range_text(*min, *max));
                        return Err(refused(&name, readable(v), &reason));
                    }
                }
            }
            Kind::Integer { min, max, get, .. } => {
                let v = get(model);
                if min.is_some_and(|m| v < m) || max.is_some_and(|m| v > m) {
                    let bound =
                        |b: Option<i32>, open: &str| b.map_or(open.into(), |b| b.to_string());
                    let reason =
                        format!("outside [{}, {}]", bound(*min, "-inf"), bound(*max, "inf"));
                    return Err(refused(d.name, v, &reason));
                }
            }
            Kind::Enumeration { ty, get, .. } => {
                let v = get(model);
                if ty.item(v).is_none() {
                    let reason = format!("not an item of {}: {}", ty.name, ty.listing());
                    return Err(refused(d.name, v, &reason));
                }
            }
            Kind::Boolean { .. } | Kind::String { .. } => {}
        }
    }
    Ok(())
}
