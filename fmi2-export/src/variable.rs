//! The FMI 2.0 view of a model's declarations: one scalar variable per element, `r_nue`
//! becoming `r_nue[1]`, `r_nue[2]`, `r_nue[3]` with consecutive value references. Get/set
//! dispatch and the model description both work on this table, built from
//! [`Model::declarations`] by [`variables`] (each instance keeps its own copy: a table kept
//! for the process would be leaked by every master that loads and unloads the library).
use crate::model::Model;
pub use fmi_model::{Causality, EnumType, Initial, Limit, Variability};
use fmi_model::{Declaration, Kind, Shape};
use std::borrow::Cow;

/// Typed accessors of one scalar. `set` is `None` for variables the master may never set;
/// `start` is read from `M::default()` where the standard asks for a start value.
pub enum Access<M> {
    Real {
        start: Option<f64>,
        min: Option<Limit>,
        max: Option<Limit>,
        get: fn(&M, usize) -> f64,
        set: Option<fn(&mut M, usize, f64)>,
        /// The element of the declaration this scalar is (0 for a scalar declaration).
        element: usize,
        place: fmi_export::prepared::Place<M>,
    },
    Integer {
        start: Option<i32>,
        min: Option<i32>,
        max: Option<i32>,
        get: fn(&M) -> i32,
        set: Option<fn(&mut M, i32)>,
    },
    /// An enumeration, exchanged as an Integer through the API; `as_integer` also declares
    /// it as an Integer in the model description (see `fmi_model::Kind::Enumeration`).
    Enumeration {
        ty: &'static EnumType,
        start: Option<i32>,
        get: fn(&M) -> i32,
        set: Option<fn(&mut M, i32)>,
        as_integer: bool,
    },
    Boolean {
        start: Option<bool>,
        get: fn(&M) -> bool,
        set: Option<fn(&mut M, bool)>,
    },
    /// A String's start, where the standard asks for one, is `get(&M::default())`.
    String {
        get: fn(&M) -> &str,
        set: Option<fn(&mut M, &str)>,
    },
}

// Plain function pointers and numbers: copied whatever `M` is.
impl<M> Clone for Access<M> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<M> Copy for Access<M> {}

/// One scalar variable of the FMI 2.0 model description; its name and description are
/// composed from its declaration when asked for ([`name`](Variable::name)).
pub struct Variable<M> {
    pub value_reference: u32,
    pub causality: Causality,
    pub variability: Variability,
    pub initial: Option<Initial>,
    pub unit: Option<&'static str>,
    /// The declaration this scalar comes from (its position in `M::declarations()`).
    pub declaration: usize,
    pub access: Access<M>,
}

impl<M> Clone for Variable<M> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<M> Copy for Variable<M> {}

impl<M: Model> Variable<M> {
    pub fn declared(&self) -> &'static Declaration<M> {
        &M::declarations()[self.declaration]
    }

    /// FMI structured name, e.g. `r_nue[1]` (arrays 1-based).
    pub fn name(&self) -> Cow<'static, str> {
        let d = self.declared();
        match d.shape() {
            Shape::Scalar => Cow::Borrowed(d.name),
            Shape::Vector(_) => Cow::Owned(format!("{}[{}]", d.name, self.element() + 1)),
        }
    }

    /// The declaration's description, with the element's component word for a vector
    /// ("position, Up") and the items for an enumeration exchanged as an Integer.
    pub fn description(&self) -> Cow<'static, str> {
        let d = self.declared();
        if let Access::Enumeration {
            ty,
            as_integer: true,
            ..
        } = &self.access
        {
            return Cow::Owned(format!("{}: {}", d.description, ty.listing()));
        }
        let described = d.described();
        match d.shape() {
            Shape::Scalar => described,
            Shape::Vector(_) => {
                let element = self.element();
                Cow::Owned(match d.components.get(element) {
                    Some(word) => format!("{described}, {word}"),
                    None => format!("{described} (element {})", element + 1),
                })
            }
        }
    }
}

impl<M> Variable<M> {
    /// The value of a Real variable in `model`.
    pub fn real(&self, model: &M) -> Option<f64> {
        match &self.access {
            Access::Real { get, element, .. } => Some(get(model, *element)),
            _ => None,
        }
    }

    /// The element index within its declaration (0 for scalars and non-Reals).
    pub fn element(&self) -> usize {
        match &self.access {
            Access::Real { element, .. } => *element,
            _ => 0,
        }
    }
}

/// The FMI 2.0 scalars of every declaration of `M`, in declaration order.
pub fn variables<M: Model>() -> Vec<Variable<M>> {
    let fresh = M::default();
    // Sized once: grown by doubling, a table just past a power of two would briefly hold
    // the old and the new buffer (an instance's heap peak, fmu-plant/tests/heap_size.rs).
    let count = M::declarations().iter().map(|d| d.shape().len()).sum();
    let mut table = Vec::with_capacity(count);
    for (index, d) in M::declarations().iter().enumerate() {
        let with_start = needs_start(d.causality, d.variability, d.initial);
        match (&d.kind, d.shape()) {
            (
                Kind::Real {
                    min,
                    max,
                    get,
                    set,
                    place,
                    ..
                },
                shape,
            ) => {
                for element in 0..shape.len() {
                    table.push(Variable {
                        value_reference: d.value_reference + element as u32,
                        access: Access::Real {
                            start: with_start.then(|| get(&fresh, element)),
                            min: *min,
                            max: *max,
                            get: *get,
                            set: *set,
                            element,
                            place: *place,
                        },
                        ..scalar(d, index)
                    });
                }
            }
            (Kind::Integer { min, max, get, set }, _) => table.push(Variable {
                access: Access::Integer {
                    start: with_start.then(|| get(&fresh)),
                    min: *min,
                    max: *max,
                    get: *get,
                    set: *set,
                },
                ..scalar(d, index)
            }),
            (
                Kind::Enumeration {
                    ty,
                    get,
                    set,
                    as_integer,
                },
                _,
            ) => table.push(Variable {
                access: Access::Enumeration {
                    ty,
                    start: with_start.then(|| get(&fresh)),
                    get: *get,
                    set: *set,
                    as_integer: *as_integer,
                },
                ..scalar(d, index)
            }),
            (Kind::Boolean { get, set }, _) => table.push(Variable {
                access: Access::Boolean {
                    start: with_start.then(|| get(&fresh)),
                    get: *get,
                    set: *set,
                },
                ..scalar(d, index)
            }),
            (Kind::String { get, set }, _) => table.push(Variable {
                access: Access::String {
                    get: *get,
                    set: *set,
                },
                ..scalar(d, index)
            }),
        }
    }
    table
}

/// The fields every scalar of `d` shares; `access` is a placeholder replaced by the caller.
fn scalar<M>(d: &Declaration<M>, index: usize) -> Variable<M> {
    Variable {
        value_reference: d.value_reference,
        causality: d.causality,
        variability: d.variability,
        initial: d.initial,
        unit: d.unit,
        declaration: index,
        access: Access::Boolean {
            start: None,
            get: |_| false,
            set: None,
        },
    }
}

/// Whether FMI 2.0 wants a start value (§2.2.7): inputs, and initial exact or approx.
pub(crate) fn needs_start(
    causality: Causality,
    variability: Variability,
    initial: Option<Initial>,
) -> bool {
    causality == Causality::Input
        || matches!(
            initial.or_else(|| { initial_rule(causality, variability).and_then(|(d, _)| d) }),
            Some(Initial::Exact | Initial::Approx)
        )
}

/// The `initial` attribute a (causality, variability) pair allows, FMI 2.0 table of
/// §2.2.7: `None` if the pair itself is illegal; otherwise (default, allowed values), where
/// an empty `allowed` means the attribute must be absent (inputs, independent).
pub fn initial_rule(
    causality: Causality,
    variability: Variability,
) -> Option<(Option<Initial>, &'static [Initial])> {
    use Causality as C;
    use Initial::*;
    use Variability as V;
    const A: (Option<Initial>, &[Initial]) = (Some(Exact), &[Exact]);
    const B: (Option<Initial>, &[Initial]) = (Some(Calculated), &[Approx, Calculated]);
    const C_: (Option<Initial>, &[Initial]) = (Some(Calculated), &[Exact, Approx, Calculated]);
    const NONE: (Option<Initial>, &[Initial]) = (None, &[]);
    match (causality, variability) {
        (C::Parameter, V::Fixed | V::Tunable) => Some(A),
        (C::CalculatedParameter, V::Fixed | V::Tunable) => Some(B),
        (C::Output | C::Local, V::Constant) => Some(A),
        (C::Local, V::Fixed | V::Tunable) => Some(B),
        (C::Output | C::Local, V::Discrete | V::Continuous) => Some(C_),
        (C::Input, V::Discrete | V::Continuous) => Some(NONE),
        (C::Independent, V::Continuous) => Some(NONE),
        _ => None,
    }
}

/// The declared `initial`, or the default for the variable's causality and variability.
pub fn effective_initial<M>(var: &Variable<M>) -> Option<Initial> {
    var.initial
        .or_else(|| initial_rule(var.causality, var.variability).and_then(|(d, _)| d))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A few cells of the FMI 2.0 table, read off the standard independently of the match.
    #[test]
    fn initial_rules_match_the_standard_table() {
        use Causality as C;
        use Initial::*;
        use Variability as V;
        assert_eq!(
            initial_rule(C::Parameter, V::Fixed),
            Some((Some(Exact), &[Exact][..]))
        );
        assert_eq!(initial_rule(C::Input, V::Continuous), Some((None, &[][..])));
        assert_eq!(
            initial_rule(C::Output, V::Continuous),
            Some((Some(Calculated), &[Exact, Approx, Calculated][..]))
        );
        assert_eq!(
            initial_rule(C::CalculatedParameter, V::Tunable),
            Some((Some(Calculated), &[Approx, Calculated][..]))
        );
        // Illegal pairs: constant inputs, continuous parameters, fixed outputs.
        assert_eq!(initial_rule(C::Input, V::Constant), None);
        assert_eq!(initial_rule(C::Parameter, V::Continuous), None);
        assert_eq!(initial_rule(C::Output, V::Fixed), None);
        assert_eq!(initial_rule(C::Independent, V::Discrete), None);
    }
}
