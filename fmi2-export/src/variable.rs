//! The FMI 2.0 view of a model's declarations: one scalar variable per element, `r_nue`
//! becoming `r_nue[1]`, `r_nue[2]`, `r_nue[3]` with consecutive value references. Get/set
//! dispatch and the model description both work on this table, built once per model type
//! from [`Model::declarations`] (see [`variables`]).
use crate::model::Model;
pub use fmi_model::{Causality, EnumType, Initial, Limit, Variability};
use fmi_model::{Declaration, Kind, Shape};
use std::any::{Any, TypeId};
use std::collections::HashMap;
use std::sync::{Mutex, OnceLock};

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
    String {
        start: Option<String>,
        get: fn(&M) -> &str,
        set: Option<fn(&mut M, &str)>,
    },
}

/// One scalar variable of the FMI 2.0 model description.
pub struct Variable<M> {
    /// FMI structured name, e.g. `r_nue[1]` (arrays 1-based).
    pub name: &'static str,
    pub value_reference: u32,
    pub causality: Causality,
    pub variability: Variability,
    pub initial: Option<Initial>,
    pub unit: Option<&'static str>,
    pub description: &'static str,
    /// The declaration this scalar comes from (its position in `M::declarations()`).
    pub declaration: usize,
    pub access: Access<M>,
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

/// The FMI 2.0 scalar table of `M`, built from its declarations on first use and kept for
/// the life of the process (one small table per model type: the names and descriptions of
/// vector elements are composed once, and every instance then shares them).
pub fn variables<M: Model>() -> &'static [Variable<M>] {
    type Tables = Mutex<HashMap<TypeId, &'static (dyn Any + Send + Sync)>>;
    static TABLES: OnceLock<Tables> = OnceLock::new();
    let tables = TABLES.get_or_init(Default::default);
    // A poisoned lock only means another thread panicked while building a table; the map
    // itself is consistent (an insert either happened or not).
    let mut tables = tables.lock().unwrap_or_else(|e| e.into_inner());
    let table = *tables.entry(TypeId::of::<M>()).or_insert_with(|| {
        let table: &'static Vec<Variable<M>> = Box::leak(Box::new(expand::<M>()));
        table
    });
    table
        .downcast_ref::<Vec<Variable<M>>>()
        .expect("the table stored under M's TypeId is M's")
}

/// The scalars of every declaration, in declaration order.
fn expand<M: Model>() -> Vec<Variable<M>> {
    let fresh = M::default();
    let mut table = Vec::new();
    for (index, d) in M::declarations().iter().enumerate() {
        let with_start = needs_start(d.causality, d.variability, d.initial);
        match (&d.kind, d.shape()) {
            (
                Kind::Real {
                    min, max, get, set, ..
                },
                shape,
            ) => {
                for element in 0..shape.len() {
                    let (name, description) = element_name(d, shape, element);
                    table.push(Variable {
                        name,
                        value_reference: d.value_reference + element as u32,
                        description,
                        access: Access::Real {
                            start: with_start.then(|| get(&fresh, element)),
                            min: *min,
                            max: *max,
                            get: *get,
                            set: *set,
                            element,
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
                // As an Integer, the description says what the values mean.
                description: if *as_integer {
                    Box::leak(format!("{}: {}", d.description, ty.listing()).into_boxed_str())
                } else {
                    d.description
                },
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
                    start: with_start.then(|| get(&fresh).to_string()),
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
        name: d.name,
        value_reference: d.value_reference,
        causality: d.causality,
        variability: d.variability,
        initial: d.initial,
        unit: d.unit,
        description: d.description,
        declaration: index,
        access: Access::Boolean {
            start: None,
            get: |_| false,
            set: None,
        },
    }
}

/// `r_nue[2]` and "position, Up" for element 1 of a vector; the declaration's own for a scalar.
fn element_name<M>(
    d: &Declaration<M>,
    shape: Shape,
    element: usize,
) -> (&'static str, &'static str) {
    match shape {
        Shape::Scalar => (d.name, d.description),
        Shape::Vector(_) => {
            let name = format!("{}[{}]", d.name, element + 1);
            let description = match d.components.get(element) {
                Some(word) => format!("{}, {word}", d.description),
                None => format!("{} (element {})", d.description, element + 1),
            };
            (
                Box::leak(name.into_boxed_str()),
                Box::leak(description.into_boxed_str()),
            )
        }
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
            initial.or_else(|| {
                crate::check::initial_rule(causality, variability).and_then(|(d, _)| d)
            }),
            Some(Initial::Exact | Initial::Approx)
        )
}
