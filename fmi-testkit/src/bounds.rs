//! The declared bounds of a model and its own validation must agree.
use fmi_model::{Kind, Limit, Model};

/// For every bound of every settable Real declaration of `M`: a value just past it (the bound
/// itself when it is exclusive), set alone into `M::default()`, must be refused by the
/// model's validation, naming the declaration's field. `refused_field` runs the model's
/// validation and returns the field it names, `None` when it accepts. Returns how many values
/// were probed.
pub fn assert_declared_bounds_are_validated<M: Model>(
    refused_field: impl Fn(&M) -> Option<&'static str>,
) -> usize {
    let past = |limit: Limit, direction: f64| match limit {
        Limit::Inclusive(b) => b + direction * (b.abs() * 1e-9).max(1e-9),
        Limit::Exclusive(b) => b,
    };
    let mut probed = 0;
    for d in M::declarations() {
        let Kind::Real {
            shape,
            min,
            max,
            set: Some(set),
            ..
        } = d.kind
        else {
            continue;
        };
        let probes = min
            .map(|m| past(m, -1.0))
            .into_iter()
            .chain(max.map(|m| past(m, 1.0)));
        for value in probes {
            for element in 0..shape.len() {
                let mut model = M::default();
                set(&mut model, element, value);
                match refused_field(&model) {
                    Some(field) => assert!(
                        d.has_field(field),
                        "{} = {value}: refused naming the field {field}",
                        d.name
                    ),
                    None => panic!(
                        "{} = {value} is outside its declared bounds but valid",
                        d.name
                    ),
                }
                probed += 1;
            }
        }
    }
    probed
}
