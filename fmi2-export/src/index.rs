//! Value reference -> table row, one lookup per FMI base type. Integer and Enumeration
//! share one value-reference space, as they share `fmi2Get/SetInteger`.
//!
//! This sits on the hot path of every `fmi2Get*`/`fmi2Set*` (a master exchanges a dozen
//! values per variable per step), so the usual case is a direct array access: value
//! references are small integers chosen by the model author, and a table indexed by them
//! costs a few bytes per unused slot. Sparse references (a model numbering its variables
//! by hash, say) fall back to a binary search so that memory stays proportional to the
//! table.
use crate::variable::{Access, Variable};

/// The four base types of the C API.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BaseType {
    Real,
    Integer,
    Boolean,
    String,
}

impl BaseType {
    pub fn of<M>(access: &Access<M>) -> BaseType {
        match access {
            Access::Real { .. } => BaseType::Real,
            Access::Integer { .. } | Access::Enumeration { .. } => BaseType::Integer,
            Access::Boolean { .. } => BaseType::Boolean,
            Access::String { .. } => BaseType::String,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            BaseType::Real => "Real",
            BaseType::Integer => "Integer",
            BaseType::Boolean => "Boolean",
            BaseType::String => "String",
        }
    }
}

/// A dense table is used while it has at most this many slots per variable of its type
/// (plus a fixed allowance for small tables), i.e. while it is a few times larger than
/// the sorted list it replaces.
const DENSE_SLOTS_PER_VARIABLE: usize = 8;
const DENSE_SLOTS_ALLOWANCE: usize = 256;

/// Marks an unused slot of a dense table.
const NO_ROW: u32 = u32::MAX;

#[derive(Debug)]
enum Lookup {
    /// `rows[vr]` is the row of `vr`, or `NO_ROW`.
    Dense(Box<[u32]>),
    /// `(vr, row)` sorted by `vr`.
    Sorted(Box<[(u32, u32)]>),
}

impl Default for Lookup {
    fn default() -> Lookup {
        Lookup::Dense(Box::default())
    }
}

impl Lookup {
    fn new(mut pairs: Vec<(u32, u32)>) -> Lookup {
        // A table with a reference used twice is refused by `check_table`; should one get
        // here anyway, the first row declared wins, as it would in a linear search.
        pairs.sort_by_key(|&(vr, row)| (vr, row));
        pairs.dedup_by_key(|&mut (vr, _)| vr);
        let slots = pairs.last().map_or(0, |&(vr, _)| vr as usize + 1);
        if slots <= DENSE_SLOTS_PER_VARIABLE * pairs.len() + DENSE_SLOTS_ALLOWANCE {
            let mut rows = vec![NO_ROW; slots].into_boxed_slice();
            for (vr, row) in pairs {
                rows[vr as usize] = row;
            }
            Lookup::Dense(rows)
        } else {
            Lookup::Sorted(pairs.into_boxed_slice())
        }
    }

    #[inline]
    fn row(&self, vr: u32) -> Option<usize> {
        match self {
            Lookup::Dense(rows) => match rows.get(vr as usize) {
                Some(&row) if row != NO_ROW => Some(row as usize),
                _ => None,
            },
            Lookup::Sorted(pairs) => pairs
                .binary_search_by_key(&vr, |&(v, _)| v)
                .ok()
                .map(|i| pairs[i].1 as usize),
        }
    }
}

/// Lookup built once per instance from the static table.
#[derive(Debug, Default)]
pub struct VariableIndex {
    by_type: [Lookup; 4],
}

impl VariableIndex {
    pub fn new<M>(table: &[Variable<M>]) -> VariableIndex {
        // Rows are stored as u32; no table comes near 4 billion variables.
        assert!(u32::try_from(table.len()).is_ok_and(|n| n < NO_ROW));
        let mut pairs: [Vec<(u32, u32)>; 4] = Default::default();
        for (row, var) in table.iter().enumerate() {
            pairs[BaseType::of(&var.access) as usize].push((var.value_reference, row as u32));
        }
        VariableIndex {
            by_type: pairs.map(Lookup::new),
        }
    }

    /// The table row of `vr` among the variables of `base_type`.
    #[inline]
    pub fn row(&self, base_type: BaseType, vr: u32) -> Option<usize> {
        self.by_type[base_type as usize].row(vr)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every reference of every type against a linear search of the pairs, for a dense
    /// and a sparse set of references.
    #[test]
    fn lookup_agrees_with_a_linear_search() {
        let dense: Vec<(u32, u32)> = [7, 0, 3, 200, 12, 5, 1].into_iter().zip(0..).collect();
        let sparse: Vec<(u32, u32)> = [4_000_000_000, 17, 1 << 20, 0, 99_999]
            .into_iter()
            .zip(10..)
            .collect();
        for (pairs, expect_dense) in [(dense, true), (sparse, false)] {
            let lookup = Lookup::new(pairs.clone());
            assert_eq!(matches!(lookup, Lookup::Dense(_)), expect_dense);
            let probes = pairs
                .iter()
                .flat_map(|&(vr, _)| [vr, vr.wrapping_add(1), vr.wrapping_sub(1)])
                .chain([0, 2, 1000, u32::MAX - 1, u32::MAX]);
            for vr in probes {
                let linear = pairs
                    .iter()
                    .find(|&&(v, _)| v == vr)
                    .map(|&(_, r)| r as usize);
                assert_eq!(lookup.row(vr), linear, "vr {vr}");
            }
        }
    }

    #[test]
    fn a_repeated_reference_finds_the_first_row() {
        let lookup = Lookup::new(vec![(5, 3), (5, 1), (2, 0)]);
        assert_eq!(lookup.row(5), Some(1));
        assert_eq!(lookup.row(2), Some(0));
        assert_eq!(Lookup::new(Vec::new()).row(0), None);
    }
}
