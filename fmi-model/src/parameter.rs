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
