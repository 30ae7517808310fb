//! The FMI 3.0 view of a model's declarations: one variable per declaration (a vector is
//! one Float64 array with one `Dimension`), found by its value reference.
use fmi_model::{Declaration, Kind, Limit, Model};
use std::collections::HashMap;

/// Value reference of the independent variable `time`, which FMI 3.0 requires to be
/// declared; far above the model's own value references (checked by `check`).
pub const TIME_VR: u32 = 999_999;

/// The FMI 3.0 type of a declaration.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Type {
    Float64,
    Int32,
    /// An enumeration: exchanged as Int64 through the API.
    Enumeration,
    Boolean,
    String,
}

impl Type {
    pub fn of<M>(d: &Declaration<M>) -> Type {
        match d.kind {
            Kind::Real { .. } => Type::Float64,
            Kind::Integer { .. } => Type::Int32,
            // A selector every master must be able to set is exchanged as a plain Int32.
            Kind::Enumeration {
                as_integer: true, ..
            } => Type::Int32,
            Kind::Enumeration { .. } => Type::Enumeration,
            Kind::Boolean { .. } => Type::Boolean,
            Kind::String { .. } => Type::String,
        }
    }

    /// The name of the get/set functions' type and of the XML element.
    pub fn api_name(self) -> &'static str {
        match self {
            Type::Float64 => "Float64",
            Type::Int32 => "Int32",
            Type::Enumeration => "Int64 (Enumeration)",
            Type::Boolean => "Boolean",
            Type::String => "String",
        }
    }
}

/// Value reference -> position in `M::declarations()`: a table indexed by the reference when
/// the references are small integers (as model authors number them), a sorted list otherwise.
/// On the path of every get and set, so no hashing.
pub enum Index {
    Dense(Box<[u32]>),
    Sorted(Box<[(u32, u32)]>),
}

/// A Float64 declaration in the form the exchange needs on every get and set: its accessors,
/// its element count, its bounds folded into two comparisons and where it may be set; the
/// declaration itself for the messages of a refusal.
pub struct Float64Slot<M: 'static> {
    pub declaration: &'static Declaration<M>,
    pub len: usize,
    pub get: fn(&M, usize) -> f64,
    pub set: Option<fn(&mut M, usize, f64)>,
    pub place: fmi_export::prepared::Place<M>,
    /// The closed range of finite values the bounds admit ([`Limit::lowest_admitted`]).
    pub lowest: f64,
    pub highest: f64,
    /// Whether [`settable`] accepts it in initialization (true) and after it (false).
    pub settable_initializing: bool,
    pub settable_running: bool,
}

impl<M: Model> Float64Slot<M> {
    /// One entry per declaration, `None` for the other types.
    pub fn table() -> Box<[Option<Float64Slot<M>>]> {
        M::declarations()
            .iter()
            .map(|d| match d.kind {
                Kind::Real {
                    shape,
                    min,
                    max,
                    get,
                    set,
                    place,
                } => Some(Float64Slot {
                    declaration: d,
                    len: shape.len(),
                    get,
                    set,
                    place,
                    lowest: Limit::lowest_admitted(min),
                    highest: Limit::highest_admitted(max),
                    settable_initializing: settable(d, true).is_ok(),
                    settable_running: settable(d, false).is_ok(),
                }),
                _ => None,
            })
            .collect()
    }

    /// Whether `value` may be set as one of its elements (finite, within the bounds).
    #[inline]
    pub fn admits(&self, value: f64) -> bool {
        value >= self.lowest && value <= self.highest
    }
}

/// No declaration at this reference (dense table).
const NONE: u32 = u32::MAX;

impl Index {
    pub fn new<M: Model>() -> Index {
        Index::of_references(M::declarations().iter().map(|d| d.value_reference))
    }

    /// The index of declarations with these references, in declaration order.
    fn of_references(vrs: impl Iterator<Item = u32>) -> Index {
        let mut pairs: Vec<(u32, u32)> = vrs.zip(0..).collect();
        // A duplicate reference is refused by `check`; should one get here, the first
        // declared wins, as in a linear search.
        pairs.sort_by_key(|&pair| pair);
        pairs.dedup_by_key(|&mut (vr, _)| vr);
        let slots = pairs.last().map_or(0, |&(vr, _)| vr as usize + 1);
        if slots <= 8 * pairs.len() + 256 {
            let mut rows = vec![NONE; slots];
            for (vr, i) in pairs {
                rows[vr as usize] = i;
            }
            Index::Dense(rows.into_boxed_slice())
        } else {
            Index::Sorted(pairs.into_boxed_slice())
        }
    }

    #[inline]
    pub fn get<M: Model>(&self, vr: u32) -> Option<&'static Declaration<M>> {
        M::declarations().get(self.row(vr)?)
    }

    /// The declaration row of `vr`.
    #[inline]
    pub fn row(&self, vr: u32) -> Option<usize> {
        let row = match self {
            Index::Dense(rows) => rows.get(vr as usize).copied().filter(|&i| i != NONE)?,
            Index::Sorted(pairs) => {
                let at = pairs.binary_search_by_key(&vr, |&(v, _)| v).ok()?;
                pairs[at].1
            }
        };
        Some(row as usize)
    }
}

/// The problems that would make an invalid FMI 3.0 description (duplicate value
/// references, a clash with `time`); empty when there are none.
pub fn check<M: Model>() -> Vec<String> {
    let mut problems = Vec::new();
    let mut seen: HashMap<u32, &str> = HashMap::new();
    for d in M::declarations() {
        if d.value_reference == TIME_VR {
            problems.push(format!("{}: value reference {TIME_VR} is `time`'s", d.name));
        }
        if let Some(other) = seen.insert(d.value_reference, d.name) {
            problems.push(format!(
                "{} and {other} share value reference {}",
                d.name, d.value_reference
            ));
        }
    }
    problems
}

/// Why the master may not set `d`, before the end of initialization (`initializing`) or
/// after it: the core's rule.
pub fn settable<M>(d: &Declaration<M>, initializing: bool) -> Result<(), &'static str> {
    let state = if initializing {
        fmi_export::State::InitializationMode
    } else {
        fmi_export::State::StepComplete
    };
    fmi_export::setters::settable(d.causality, d.variability, state)
}

#[cfg(test)]
mod index_tests {
    use super::Index;

    /// Both layouts against a linear search, at every reference and its neighbours.
    #[test]
    fn lookup_agrees_with_a_linear_search_dense_and_sparse() {
        let dense = vec![7, 0, 3, 200, 12, 5, 1, 3];
        let sparse = vec![4_000_000_000, 17, 1 << 20, 0, 99_999];
        for (vrs, expect_dense) in [(dense, true), (sparse, false)] {
            let index = Index::of_references(vrs.iter().copied());
            assert_eq!(matches!(index, Index::Dense(_)), expect_dense);
            let probes = vrs
                .iter()
                .flat_map(|&vr: &u32| [vr, vr.wrapping_add(1), vr.wrapping_sub(1)])
                .chain([2, 1000, u32::MAX - 1, u32::MAX]);
            for vr in probes {
                let linear = vrs.iter().position(|&v| v == vr);
                assert_eq!(index.row(vr), linear, "vr {vr}");
            }
        }
    }
}
