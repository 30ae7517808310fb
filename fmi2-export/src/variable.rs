//! The single declaration of a model variable. Get/set dispatch and the model description
//! are both produced from a `&'static [Variable<M>]` table.
pub use model_description::{Causality, Initial, Variability};

/// Typed accessors (plain function pointers, so tables can be `static`). `set` is `None`
/// for variables the master may never set (outputs, locals, calculated parameters).
pub enum Access<M> {
    Real {
        start: Option<f64>,
        min: Option<f64>,
        max: Option<f64>,
        get: fn(&M) -> f64,
        set: Option<fn(&mut M, f64)>,
    },
    Integer {
        start: Option<i32>,
        min: Option<i32>,
        max: Option<i32>,
        get: fn(&M) -> i32,
        set: Option<fn(&mut M, i32)>,
    },
    /// An enumeration, exchanged as an Integer through the API.
    Enumeration {
        type_name: &'static str,
        start: Option<i32>,
        get: fn(&M) -> i32,
        set: Option<fn(&mut M, i32)>,
    },
    Boolean {
        start: Option<bool>,
        get: fn(&M) -> bool,
        set: Option<fn(&mut M, bool)>,
    },
    String {
        start: Option<&'static str>,
        get: fn(&M) -> &str,
        set: Option<fn(&mut M, &str)>,
    },
}

/// One row of the variable table.
pub struct Variable<M> {
    /// FMI structured name, e.g. `r_nue[1]` (arrays 1-based).
    pub name: &'static str,
    pub value_reference: u32,
    pub causality: Causality,
    pub variability: Variability,
    /// `None` where the standard forbids the attribute (e.g. inputs) or uses the default.
    pub initial: Option<Initial>,
    /// Unit symbol (Real only), declared in `UnitDefinitions` by the layer.
    pub unit: Option<&'static str>,
    pub description: &'static str,
    pub access: Access<M>,
}
