//! One declaration per variable: what it is (causality, variability, unit, bounds), what it
//! looks like (scalar or vector) and how to read and write it in the model.
use crate::enumeration::EnumType;

/// Who computes a variable and who may set it (the FMI causality; the FMI 3.0-only
/// `structuralParameter` is not used by our models).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Causality {
    Parameter,
    CalculatedParameter,
    Input,
    Output,
    Local,
    Independent,
}

/// When a variable may change.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Variability {
    Constant,
    Fixed,
    Tunable,
    Discrete,
    Continuous,
}

/// How the start value is meant (FMI `initial`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Initial {
    Exact,
    Approx,
    Calculated,
}

/// A causality with its usual variability and initial, so that a declaration names one word.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Role {
    pub causality: Causality,
    pub variability: Variability,
    pub initial: Option<Initial>,
}

/// The roles [`decl!`](crate::decl) accepts, by the word written in the declaration.
#[allow(non_upper_case_globals)]
pub mod role {
    use super::{Causality as C, Initial as I, Role, Variability as V};

    const fn r(causality: C, variability: V, initial: Option<I>) -> Role {
        Role {
            causality,
            variability,
            initial,
        }
    }
    /// Set by the master before every step.
    pub const input: Role = r(C::Input, V::Continuous, None);
    /// Computed by the model, changes continuously.
    pub const output: Role = r(C::Output, V::Continuous, Some(I::Calculated));
    /// Computed by the model, changes only at steps or events.
    pub const discrete_output: Role = r(C::Output, V::Discrete, Some(I::Calculated));
    /// Set before the simulation, fixed afterwards.
    pub const parameter: Role = r(C::Parameter, V::Fixed, Some(I::Exact));
    /// A parameter the master may change between steps.
    pub const tunable: Role = r(C::Parameter, V::Tunable, Some(I::Exact));
    /// Computed from fixed parameters.
    pub const calculated_parameter: Role = r(C::CalculatedParameter, V::Fixed, Some(I::Calculated));
    /// Computed from tunable parameters.
    pub const calculated_tunable: Role = r(C::CalculatedParameter, V::Tunable, Some(I::Calculated));
    /// A constant the master may read.
    pub const constant: Role = r(C::Local, V::Constant, Some(I::Exact));
    /// A continuous state the model computes internally (Model Exchange integrates it).
    pub const continuous_state: Role = r(C::Local, V::Continuous, Some(I::Calculated));
    /// The time derivative of a continuous state.
    pub const derivative: Role = r(C::Local, V::Continuous, Some(I::Calculated));
    /// Computed by the model for inspection (e.g. an event indicator), not an output.
    pub const local: Role = r(C::Local, V::Continuous, Some(I::Calculated));
}

/// A scalar or a vector of `n` elements (an FMI 3.0 array with one `Dimension`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Shape {
    Scalar,
    Vector(usize),
}

impl Shape {
    /// Number of scalar elements.
    pub const fn len(self) -> usize {
        match self {
            Shape::Scalar => 1,
            Shape::Vector(n) => n,
        }
    }

    pub const fn is_empty(self) -> bool {
        self.len() == 0
    }
}

/// A bound of a Real variable. The FMI `min`/`max` attributes are inclusive; an exclusive
/// bound ("> 0") is written as the nearest value it admits (`min="5e-324"`, see
/// [`Limit::fmi_min`]) and stated in words in the variable's description ([`bounds_note`]),
/// so that what the description says and what a set does agree.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Limit {
    Inclusive(f64),
    Exclusive(f64),
}

impl Limit {
    pub const fn value(self) -> f64 {
        match self {
            Limit::Inclusive(v) | Limit::Exclusive(v) => v,
        }
    }

    /// The same kind of limit at `-value`: a lower bound of the negated quantity for an
    /// upper one, and the reverse.
    pub const fn negated(self) -> Limit {
        match self {
            Limit::Inclusive(v) => Limit::Inclusive(-v),
            Limit::Exclusive(v) => Limit::Exclusive(-v),
        }
    }

    /// The lowest finite value a lower bound admits: itself if inclusive, the next double
    /// up if exclusive, `-f64::MAX` for none (or -inf); NaN stays NaN. With
    /// [`Limit::highest_admitted`], a finite value `v` is in range exactly when
    /// `lowest <= v <= highest`, and infinities and NaN fail those two comparisons: the
    /// check on every set a master makes.
    pub fn lowest_admitted(min: Option<Limit>) -> f64 {
        let lowest = match min {
            None => f64::NEG_INFINITY,
            Some(Limit::Inclusive(v)) => v,
            Some(Limit::Exclusive(v)) => v.next_up(),
        };
        if lowest == f64::NEG_INFINITY {
            -f64::MAX
        } else {
            lowest
        }
    }

    /// The highest finite value an upper bound admits (see [`Limit::lowest_admitted`]).
    pub fn highest_admitted(max: Option<Limit>) -> f64 {
        -Limit::lowest_admitted(max.map(Limit::negated))
    }

    /// FMI's inclusive `min` attribute for this lower bound: the lowest value it admits.
    pub fn fmi_min(self) -> f64 {
        match self {
            Limit::Inclusive(v) => v,
            Limit::Exclusive(v) => v.next_up(),
        }
    }

    /// FMI's inclusive `max` attribute for this upper bound: the highest value it admits.
    pub fn fmi_max(self) -> f64 {
        -self.negated().fmi_min()
    }

    /// Whether `value` respects this limit as a lower bound.
    pub fn admits_above(self, value: f64) -> bool {
        match self {
            Limit::Inclusive(b) => value >= b,
            Limit::Exclusive(b) => value > b,
        }
    }

    /// Whether `value` respects this limit as an upper bound.
    pub fn admits_below(self, value: f64) -> bool {
        match self {
            Limit::Inclusive(b) => value <= b,
            Limit::Exclusive(b) => value < b,
        }
    }
}

/// The exclusive bounds of a real range in words ("> 0", "> -1.5707963267948966 and
/// < 1.5707963267948966"), for the description: FMI's `min`/`max` cannot say "excluded".
pub fn bounds_note(min: Option<Limit>, max: Option<Limit>) -> Option<String> {
    let low = match min {
        Some(Limit::Exclusive(v)) => Some(format!("> {}", crate::readable(v))),
        _ => None,
    };
    let high = match max {
        Some(Limit::Exclusive(v)) => Some(format!("< {}", crate::readable(v))),
        _ => None,
    };
    match (low, high) {
        (Some(l), Some(h)) => Some(format!("{l} and {h}")),
        (l, h) => l.or(h),
    }
}

/// The value type of a declaration and its accessors (plain function pointers, so that a
/// table can be a `static`). `set` is `None` for what the master may never set.
pub enum Kind<M> {
    /// Element `i` of a scalar (`i` = 0) or a vector.
    Real {
        shape: Shape,
        min: Option<Limit>,
        max: Option<Limit>,
        get: fn(&M, usize) -> f64,
        set: Option<fn(&mut M, usize, f64)>,
        /// Where element `i` is stored, for a Real that is a field of the model (`None`
        /// for a computed one): a layer that finds it inside the model's own bytes reads
        /// and writes it there directly, without calling `get` or `set` per value. It must
        /// give the address of the very `f64` that `get` reads and `set` writes, in every
        /// value of the model; [`decl!`](crate::decl) derives it from the field path, and a
        /// declaration written by hand should leave it `None`. A reference, not an address:
        /// what it points at is an `f64` that exists; the layer uses it only where it lies
        /// inside the model's own bytes, aligned, and keeps its offset, which is why the
        /// model must be a struct (a field path has one offset in every value; an enum's
        /// variants do not).
        place: Option<fn(&M, usize) -> &f64>,
    },
    Integer {
        min: Option<i32>,
        max: Option<i32>,
        get: fn(&M) -> i32,
        set: Option<fn(&mut M, i32)>,
    },
    /// Values are those of `ty`'s items; the layer refuses any other before `set` runs.
    Enumeration {
        ty: &'static EnumType,
        get: fn(&M) -> i32,
        set: Option<fn(&mut M, i32)>,
        /// Exchange it as a plain Integer: bounds from the items, the items listed in the
        /// description, the type still written in `TypeDefinitions` for a tool that reads
        /// the items' names. For a selector every master must be able to set: some (libcosim,
        /// Ecos) ignore FMI 2.0 Enumeration variables altogether.
        as_integer: bool,
    },
    Boolean {
        get: fn(&M) -> bool,
        set: Option<fn(&mut M, bool)>,
    },
    String {
        get: fn(&M) -> &str,
        set: Option<fn(&mut M, &str)>,
    },
}

/// A variable, declared once.
pub struct Declaration<M> {
    /// The base name (`r_nue`, not `r_nue[1]`).
    pub name: &'static str,
    /// The value reference; FMI 2.0 numbers the elements of a vector from it upwards.
    pub value_reference: u32,
    pub causality: Causality,
    pub variability: Variability,
    pub initial: Option<Initial>,
    /// Unit symbol (Real only).
    pub unit: Option<&'static str>,
    pub description: &'static str,
    /// Words appended to the description of each element of a vector by a layer that
    /// writes the elements separately (FMI 2.0), e.g. `["North", "Up", "East"]`.
    pub components: &'static [&'static str],
    /// Where the value lives in the model (`params.inertia_body_kgm2`), as written in the
    /// declaration: a [`ModelError`](crate::ModelError) names the field, the layer names
    /// the variable declared for it. Empty for computed values.
    pub field: &'static str,
    pub kind: Kind<M>,
}

/// Which inputs an output depends on within one step (direct feedthrough), see
/// [`Model::output_dependencies`](crate::Model::output_dependencies). Names are
/// declaration names.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Dependencies {
    AllInputs,
    NoInputs,
    /// These inputs (all their elements).
    Inputs(&'static [&'static str]),
    /// Element `i` of this output depends on element `i` of the named vector input only.
    SameElementOf(&'static str),
}

impl<M> Declaration<M> {
    const fn base(
        vr: u32,
        name: &'static str,
        role: Role,
        description: &'static str,
        kind: Kind<M>,
    ) -> Self {
        Declaration {
            name,
            value_reference: vr,
            causality: role.causality,
            variability: role.variability,
            initial: role.initial,
            unit: None,
            description,
            components: &[],
            field: "",
            kind,
        }
    }

    /// Whether the master may ever set it (a setter is kept exactly for these).
    pub const fn settable(role: Role) -> bool {
        matches!(role.causality, Causality::Parameter | Causality::Input)
            && !matches!(role.variability, Variability::Constant)
    }

    /// The one constructor with all of a Real's facts; [`decl!`](crate::decl) fills it in.
    #[allow(clippy::too_many_arguments)]
    pub const fn real(
        vr: u32,
        name: &'static str,
        role: Role,
        shape: Shape,
        unit: &'static str,
        description: &'static str,
        get: fn(&M, usize) -> f64,
        set: fn(&mut M, usize, f64),
    ) -> Self {
        let set = if Self::settable(role) {
            Some(set)
        } else {
            None
        };
        let kind = Kind::Real {
            shape,
            min: None,
            max: None,
            get,
            set,
            place: None,
        };
        let mut d = Self::base(vr, name, role, description, kind);
        // "1" is how every unitless Real is declared, so that all layers write one symbol.
        d.unit = Some(unit);
        d
    }

    pub const fn integer(
        vr: u32,
        name: &'static str,
        role: Role,
        description: &'static str,
        get: fn(&M) -> i32,
        set: fn(&mut M, i32),
    ) -> Self {
        let set = if Self::settable(role) {
            Some(set)
        } else {
            None
        };
        Self::base(
            vr,
            name,
            role,
            description,
            Kind::Integer {
                min: None,
                max: None,
                get,
                set,
            },
        )
    }

    pub const fn enumeration(
        vr: u32,
        name: &'static str,
        role: Role,
        description: &'static str,
        ty: &'static EnumType,
        get: fn(&M) -> i32,
        set: fn(&mut M, i32),
    ) -> Self {
        let set = if Self::settable(role) {
            Some(set)
        } else {
            None
        };
        let kind = Kind::Enumeration {
            ty,
            get,
            set,
            as_integer: false,
        };
        Self::base(vr, name, role, description, kind)
    }

    pub const fn boolean(
        vr: u32,
        name: &'static str,
        role: Role,
        description: &'static str,
        get: fn(&M) -> bool,
        set: fn(&mut M, bool),
    ) -> Self {
        let set = if Self::settable(role) {
            Some(set)
        } else {
            None
        };
        Self::base(vr, name, role, description, Kind::Boolean { get, set })
    }

    pub const fn string(
        vr: u32,
        name: &'static str,
        role: Role,
        description: &'static str,
        get: fn(&M) -> &str,
        set: fn(&mut M, &str),
    ) -> Self {
        let set = if Self::settable(role) {
            Some(set)
        } else {
            None
        };
        Self::base(vr, name, role, description, Kind::String { get, set })
    }

    // ---- options, written `key = value` after a `decl!` ----

    pub const fn field(mut self, field: &'static str) -> Self {
        self.field = field;
        self
    }

    /// Where a Real field's elements are stored (see [`Kind::Real`] for what `at` must
    /// give); [`decl!`](crate::decl) gives it for every field it is written with.
    pub const fn stored(mut self, at: fn(&M, usize) -> &f64) -> Self {
        if let Kind::Real { place, .. } = &mut self.kind {
            *place = Some(at);
        } else {
            panic!("stored applies to Real declarations");
        }
        self
    }

    pub const fn components(mut self, components: &'static [&'static str]) -> Self {
        self.components = components;
        self
    }

    pub const fn initial(mut self, initial: Option<Initial>) -> Self {
        self.initial = initial;
        self
    }

    /// Inclusive lower bound of a Real (`value >= min`).
    pub const fn min(self, min: f64) -> Self {
        self.real_limits(Some(Limit::Inclusive(min)), None)
    }

    /// Exclusive lower bound of a Real (`value > min`).
    pub const fn above(self, min: f64) -> Self {
        self.real_limits(Some(Limit::Exclusive(min)), None)
    }

    /// Inclusive upper bound of a Real (`value <= max`).
    pub const fn max(self, max: f64) -> Self {
        self.real_limits(None, Some(Limit::Inclusive(max)))
    }

    /// Exclusive upper bound of a Real (`value < max`).
    pub const fn below(self, max: f64) -> Self {
        self.real_limits(None, Some(Limit::Exclusive(max)))
    }

    const fn real_limits(mut self, new_min: Option<Limit>, new_max: Option<Limit>) -> Self {
        if let Kind::Real { min, max, .. } = &mut self.kind {
            if new_min.is_some() {
                *min = new_min;
            }
            if new_max.is_some() {
                *max = new_max;
            }
        } else {
            panic!("min/max/above/below apply to Real declarations; use int_min/int_max");
        }
        self
    }

    /// Exchange an enumeration as a plain Integer (see [`Kind::Enumeration`]).
    pub const fn as_integer(mut self, on: bool) -> Self {
        if let Kind::Enumeration { as_integer, .. } = &mut self.kind {
            *as_integer = on;
        } else {
            panic!("as_integer applies to enumeration declarations");
        }
        self
    }

    pub const fn int_min(mut self, new: i32) -> Self {
        if let Kind::Integer { min, .. } = &mut self.kind {
            *min = Some(new);
        } else {
            panic!("int_min applies to Integer declarations");
        }
        self
    }

    pub const fn int_max(mut self, new: i32) -> Self {
        if let Kind::Integer { max, .. } = &mut self.kind {
            *max = Some(new);
        } else {
            panic!("int_max applies to Integer declarations");
        }
        self
    }

    // ---- reading ----

    pub fn shape(&self) -> Shape {
        match self.kind {
            Kind::Real { shape, .. } => shape,
            _ => Shape::Scalar,
        }
    }

    /// Whether `field` (a path such as `inertia_body_kgm2` or `engines.count`, as a model
    /// error gives it) names this declaration's field: the declared path ends with it.
    /// The description a model description writes: the declared text, with the exclusive
    /// bounds of a real in words when it has any ([`bounds_note`]).
    pub fn described(&self) -> std::borrow::Cow<'static, str> {
        let note = match self.kind {
            Kind::Real { min, max, .. } => bounds_note(min, max),
            _ => None,
        };
        match note {
            Some(note) => format!("{} ({note})", self.description).into(),
            None => self.description.into(),
        }
    }

    pub fn has_field(&self, field: &str) -> bool {
        if field.is_empty() || self.field.is_empty() {
            return false;
        }
        let declared: String = self.field.chars().filter(|c| !c.is_whitespace()).collect();
        declared == field
            || declared
                .strip_suffix(field)
                .is_some_and(|head| head.ends_with('.'))
    }
}

/// Declares one variable in one line. The forms (options `key = value` may follow any of
/// them: `min`, `above`, `max`, `below`, `int_min`, `int_max`, `components`, `initial`,
/// `as_integer`):
///
/// ```text
/// decl!(vr, role name: field.path, "unit", "description")            Real scalar
/// decl!(vr, role name[n]: field.path, "unit", "description")         Real vector of n
/// decl!(vr, role name: field.path as i32, "description")             Integer
/// decl!(vr, role name: field.path as bool, "description")            Boolean
/// decl!(vr, role name: field.path as String, "description")          String
/// decl!(vr, role name: field.path as enum Type, "description")       Enumeration of a Rust enum
/// decl!(vr, role name: get |m, i| expr, "unit", "description")       computed Real (outputs)
/// decl!(vr, role name[n]: get |m, i| expr, "unit", "description")    computed Real vector
/// ```
/// `role` is one of [`role`]'s words (`input`, `output`, `parameter`, ...). The field of an
/// enumeration holds the Rust enum or its raw `i32` value (see [`EnumValue`](crate::EnumValue)).
#[macro_export]
macro_rules! decl {
    // Options are applied as nested calls (`Declaration::min(d, 0.0)`), not as a method
    // chain, so that the model type flows from the table into the accessor closures.
    (@apply $d:expr ; $(,)?) => { $d };
    (@apply $d:expr ; $opt:ident = $val:expr $(, $rest:ident = $rval:expr)* $(,)?) => {
        $crate::decl!(@apply $crate::Declaration::$opt($d, $val) ; $($rest = $rval),*)
    };
    ($vr:literal, $role:ident $name:ident [$n:literal] : get $get:expr, $unit:expr, $desc:expr $(, $opt:ident = $val:expr)* $(,)?) => {
        $crate::decl!(@apply $crate::Declaration::real($vr, stringify!($name), $crate::role::$role, $crate::Shape::Vector($n), $unit, $desc, $get, |_, _, _| {}) ; $($opt = $val),*)
    };
    ($vr:literal, $role:ident $name:ident : get $get:expr, $unit:expr, $desc:expr $(, $opt:ident = $val:expr)* $(,)?) => {
        $crate::decl!(@apply $crate::Declaration::real($vr, stringify!($name), $crate::role::$role, $crate::Shape::Scalar, $unit, $desc, $get, |_, _, _| {}) ; $($opt = $val),*)
    };
    ($vr:literal, $role:ident $name:ident : $($path:ident).+ as enum $ty:ty, $desc:expr $(, $opt:ident = $val:expr)* $(,)?) => {
        $crate::decl!(@apply $crate::Declaration::enumeration(
            $vr, stringify!($name), $crate::role::$role, $desc,
            <$ty as $crate::Enumeration>::TYPE,
            |m| $crate::EnumValue::<$ty>::to_value(&m.$($path).+),
            |m, v| $crate::EnumValue::<$ty>::set_value(&mut m.$($path).+, v),
        ) ; field = stringify!($($path).+) $(, $opt = $val)*)
    };
    ($vr:literal, $role:ident $name:ident : $($path:ident).+ as i32, $desc:expr $(, $opt:ident = $val:expr)* $(,)?) => {
        $crate::decl!(@apply $crate::Declaration::integer($vr, stringify!($name), $crate::role::$role, $desc, |m| m.$($path).+, |m, v| m.$($path).+ = v)
            ; field = stringify!($($path).+) $(, $opt = $val)*)
    };
    ($vr:literal, $role:ident $name:ident : $($path:ident).+ as bool, $desc:expr $(, $opt:ident = $val:expr)* $(,)?) => {
        $crate::decl!(@apply $crate::Declaration::boolean($vr, stringify!($name), $crate::role::$role, $desc, |m| m.$($path).+, |m, v| m.$($path).+ = v)
            ; field = stringify!($($path).+) $(, $opt = $val)*)
    };
    ($vr:literal, $role:ident $name:ident : $($path:ident).+ as String, $desc:expr $(, $opt:ident = $val:expr)* $(,)?) => {
        $crate::decl!(@apply $crate::Declaration::string($vr, stringify!($name), $crate::role::$role, $desc, |m| &m.$($path).+, |m, v| m.$($path).+ = v.to_string())
            ; field = stringify!($($path).+) $(, $opt = $val)*)
    };
    ($vr:literal, $role:ident $name:ident [$n:literal] : $($path:ident).+, $unit:expr, $desc:expr $(, $opt:ident = $val:expr)* $(,)?) => {
        $crate::decl!(@apply $crate::Declaration::real(
            $vr, stringify!($name), $crate::role::$role, $crate::Shape::Vector($n), $unit, $desc,
            |m, i| m.$($path).+[i], |m, i, v| m.$($path).+[i] = v,
        ) ; field = stringify!($($path).+), stored = |m, i| &m.$($path).+[i] $(, $opt = $val)*)
    };
    ($vr:literal, $role:ident $name:ident : $($path:ident).+, $unit:expr, $desc:expr $(, $opt:ident = $val:expr)* $(,)?) => {
        $crate::decl!(@apply $crate::Declaration::real(
            $vr, stringify!($name), $crate::role::$role, $crate::Shape::Scalar, $unit, $desc,
            |m, _| m.$($path).+, |m, _, v| m.$($path).+ = v,
        ) ; field = stringify!($($path).+), stored = |m, _| &m.$($path).+ $(, $opt = $val)*)
    };
}
