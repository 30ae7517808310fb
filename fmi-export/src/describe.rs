//! A model's error in the master's words.
use fmi_model::{Model, ModelError};

/// `error` with the field it names replaced by the variable declared for it, and the
/// element as the variable's name shows it (1-based, `inertia_body[2]`): the same text in
/// both FMI versions. A name that is no declared field is kept as the model wrote it.
pub fn describe_model_error<M: Model>(error: &ModelError) -> String {
    let (kind, field, index, value, reason) = match error {
        ModelError::InvalidParameter {
            field,
            index,
            value,
            reason,
        } => ("parameter", field, index, value, reason),
        ModelError::InvalidInput {
            field,
            index,
            value,
            reason,
        } => ("input", field, index, value, reason),
        ModelError::Other(text) | ModelError::Refused(text) => return text.clone(),
    };
    let declared = M::declarations().iter().find(|d| d.has_field(field));
    let name = declared.map_or(*field, |d| d.name);
    let element = match (declared, index) {
        (Some(d), Some(i)) if d.shape().len() > 1 => format!("[{}]", i + 1),
        (Some(_), _) => String::new(),
        (None, Some(i)) => format!("[{i}]"),
        (None, None) => String::new(),
    };
    format!("{kind} {name}{element} = {value}: {reason}")
}
