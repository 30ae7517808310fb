//! Value reference -> table row, one sorted list per FMI base type. Integer and
//! Enumeration share one value-reference space, as they share `fmi2Get/SetInteger`.
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

/// Lookup built once per instance from the static table (a few hundred entries at most,
/// so a binary search beats hashing and allocates once).
#[derive(Debug, Default)]
pub struct VariableIndex {
    by_type: [Vec<(u32, usize)>; 4],
}

impl VariableIndex {
    pub fn new<M>(table: &[Variable<M>]) -> VariableIndex {
        let mut index = VariableIndex::default();
        for (row, var) in table.iter().enumerate() {
            index.by_type[BaseType::of(&var.access) as usize].push((var.value_reference, row));
        }
        for list in &mut index.by_type {
            list.sort_unstable();
        }
        index
    }

    /// The table row of `vr` among the variables of `base_type`.
    pub fn row(&self, base_type: BaseType, vr: u32) -> Option<usize> {
        let list = &self.by_type[base_type as usize];
        list.binary_search_by_key(&vr, |&(v, _)| v)
            .ok()
            .map(|i| list[i].1)
    }
}
