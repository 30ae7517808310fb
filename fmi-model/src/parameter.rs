//! A parameter value a model refuses, in the one shape every model reports it: the field it
//! is stored in and the reason, which the layer turns into the variable's name.
use crate::ModelError;

/// A parameter value a model refuses: `field` is its path as the declaration writes it
/// (`engines.count`; a layer finds the variable whose declared field ends with it), `index`
/// the 0-based element of a vector.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("parameter {field}{} = {value}: {reason}", index.map(|i| format!("[{i}]")).unwrap_or_default())]
pub struct ParameterError {
    pub field: &'static str,
    pub index: Option<usize>,
    pub value: String,
    pub reason: String,
}

impl ParameterError {
    /// `value` as written (a count, an item, a vector shown whole).
    pub fn new(
        field: &'static str,
        index: Option<usize>,
        value: impl ToString,
        reason: impl Into<String>,
    ) -> Self {
        ParameterError {
            field,
            index,
            value: value.to_string(),
            reason: reason.into(),
        }
    }

    /// A real value, shown as a user reads it ([`readable`](crate::readable)).
    pub fn real(
        field: &'static str,
        index: Option<usize>,
        value: f64,
        reason: impl Into<String>,
    ) -> Self {
        Self::new(field, index, crate::readable(value), reason)
    }

    /// `Ok` when `ok`, otherwise the refusal of the real `value`.
    pub fn require(
        ok: bool,
        field: &'static str,
        index: Option<usize>,
        value: f64,
        reason: impl Into<String>,
    ) -> Result<(), Self> {
        if ok {
            Ok(())
        } else {
            Err(Self::real(field, index, value, reason))
        }
    }

    /// A direction vector: finite, with a length to normalise (its norm above 1e-9).
    pub fn direction(field: &'static str, v: &[f64; 3]) -> Result<(), Self> {
        if let Some(i) = v.iter().position(|x| !x.is_finite()) {
            return Err(Self::real(field, Some(i), v[i], "not finite"));
        }
        let norm = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        Self::require(
            norm > 1e-9,
            field,
            None,
            norm,
            "a direction must have a length (its norm is below 1e-9)",
        )
    }
}

impl From<ParameterError> for ModelError {
    fn from(e: ParameterError) -> Self {
        ModelError::InvalidParameter {
            field: e.field,
            index: e.index,
            value: e.value,
            reason: e.reason,
        }
    }
}

/// Every settable parameter of `model` against its declaration: a Real finite and within
/// its declared bounds, an Integer within its own, an enumeration one of its items. The FMI
/// layers check each value as it is set; this is the same check for a model built or
/// changed without them (in-process, tests, a restored state), so that a model's own
/// validation keeps to what declarations cannot say (relations between parameters). The
/// refusal names the field below the model's own one that holds it (`params.thrust_max_n`
/// is `thrust_max_n`), as the model's validation names its fields, the value with its unit
/// and the declared range.
pub fn check_declared<M: crate::Model>(model: &M) -> Result<(), ParameterError> {
    use crate::{Causality, Kind};
    for d in M::declarations() {
        if d.causality != Causality::Parameter {
            continue;
        }
        let field = d.field.split_once('.').map_or(d.field, |(_, below)| below);
        match d.kind {
            Kind::Real {
                shape,
                min,
                max,
                get,
                set: Some(_),
                ..
            } => {
                let unit = d.unit.filter(|u| *u != "1");
                let with_unit = |text: String| match unit {
                    Some(u) => format!("{text} {u}"),
                    None => text,
                };
                for i in 0..shape.len() {
                    let value = get(model, i);
                    let admitted = value.is_finite()
                        && min.is_none_or(|m| m.admits_above(value))
                        && max.is_none_or(|m| m.admits_below(value));
                    if !admitted {
                        let index = (shape != crate::Shape::Scalar).then_some(i);
                        let range = with_unit(crate::range_text(min, max));
                        return Err(ParameterError::new(
                            field,
                            index,
                            with_unit(crate::readable(value)),
                            format!("outside its declared range {range}"),
                        ));
                    }
                }
            }
            Kind::Integer {
                min,
                max,
                get,
                set: Some(_),
            } => {
                let value = get(model);
                if min.is_some_and(|m| value < m) || max.is_some_and(|m| value > m) {
                    let end = |b: Option<i32>, none: &str| b.map_or(none.into(), |b| b.to_string());
                    let (open, close) = (
                        if min.is_some() { '[' } else { '(' },
                        if max.is_some() { ']' } else { ')' },
                    );
                    return Err(ParameterError::new(
                        field,
                        None,
                        value,
                        format!(
                            "outside its declared range {open}{}, {}{close}",
                            end(min, "-inf"),
                            end(max, "inf")
                        ),
                    ));
                }
            }
            Kind::Enumeration {
                ty,
                get,
                set: Some(_),
                ..
            } => {
                let value = get(model);
                if ty.item(value).is_none() {
                    return Err(ParameterError::new(
                        field,
                        None,
                        value,
                        format!("not an item of {}: {}", ty.name, ty.listing()),
                    ));
                }
            }
            _ => {}
        }
    }
    Ok(())
}
